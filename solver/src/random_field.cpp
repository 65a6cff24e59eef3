// Spatially correlated random strength: the spectral method of Shinozuka and Deodatis (1991).
#include "hexdem/solver/random_field.hpp"

#include <array>
#include <cmath>

namespace hexdem::solver {
namespace {

/// SplitMix64 (Steele, Lea, Flood 2014): a portable 64-bit generator.
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in (0, 1).
  double uniform() { return (static_cast<double>(next() >> 11) + 0.5) * 0x1.0p-53; }
};

}  // namespace

std::vector<double> lognormal_field(const std::vector<double>& x, const std::vector<double>& y, std::int64_t seed,
                                    double correlation_length, double cov, std::uint64_t stream) {
  constexpr double kTwoPi = 6.283185307179586477;
  // Stream 0 starts where the strength field always has (its fields are unchanged); another
  // stream's generator starts 2^64 / golden ratio states further per stream.
  SplitMix64 rng{static_cast<std::uint64_t>(seed) * 0x2545F4914F6CDD1Dull + 1 + stream * 0x9E3779B97F4A7C15ull};
  std::array<double, kRandomFieldModes> kx{}, ky{}, phase{};
  for (int n = 0; n < kRandomFieldModes; ++n) {
    // Box-Muller: two standard normals for the wave vector, then a uniform phase.
    const double r = std::sqrt(-2.0 * std::log(rng.uniform())), a = kTwoPi * rng.uniform();
    kx[static_cast<std::size_t>(n)] = r * std::cos(a) / correlation_length;
    ky[static_cast<std::size_t>(n)] = r * std::sin(a) / correlation_length;
    phase[static_cast<std::size_t>(n)] = kTwoPi * rng.uniform();
  }
  const double s2 = std::log1p(cov * cov), s = std::sqrt(s2);
  const double amp = std::sqrt(2.0 / kRandomFieldModes);
  std::vector<double> out(x.size());
  const auto np = static_cast<std::ptrdiff_t>(x.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < np; ++k) {
    const double px = x[static_cast<std::size_t>(k)], py = y[static_cast<std::size_t>(k)];
    double g = 0;
    for (std::size_t n = 0; n < kRandomFieldModes; ++n) g += std::cos(kx[n] * px + ky[n] * py + phase[n]);
    out[static_cast<std::size_t>(k)] = std::exp(s * amp * g - 0.5 * s2);
  }
  return out;
}

}  // namespace hexdem::solver
