// Irregular lattice: the interior disks moved off their sites (lattice_jitter.hpp).
#include "hexdem/meshing/lattice_jitter.hpp"

#include <bit>
#include <cmath>
#include <numbers>
#include <vector>

#include "hexdem/error.hpp"

namespace hexdem::meshing {

namespace {

/// SplitMix64 (Steele, Lea and Flood 2014): a well-mixed 64-bit hash of a 64-bit state.
std::uint64_t splitmix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// A uniform number in [0, 1) from the top 53 bits of h.
double unit(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

}  // namespace

std::vector<std::uint8_t> interior_disks(const Lattice& lattice) {
  const std::size_t n = lattice.num_disks();
  std::vector<std::uint8_t> bonds(n, 0), interior(n, 0);
  for (std::size_t b = 0; b < lattice.num_bonds(); ++b) {
    for (const std::int32_t d : {lattice.bond_i[b], lattice.bond_j[b]}) {
      std::uint8_t& c = bonds[static_cast<std::size_t>(d)];
      if (c < 255) ++c;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double r = lattice.radius[i];
    const double hexagon = 2.0 * std::numbers::sqrt3 * r * r;
    interior[i] = lattice.kind[i] == static_cast<std::uint8_t>(DiskKind::Disk) && bonds[i] == 6 &&
                  std::abs(lattice.cell_area[i] - hexagon) <= 1e-9 * hexagon;
  }
  for (const std::int32_t d : lattice.set_disk) interior[static_cast<std::size_t>(d)] = 0;
  return interior;
}

std::int64_t jitter_lattice(Lattice& lattice, double fraction, std::uint64_t seed) {
  HEXDEM_VERIFY(fraction >= 0.0 && fraction <= kMaxJitter, "jitter fraction out of range");
  if (fraction == 0.0) return 0;
  const std::size_t n = lattice.num_disks();
  const std::vector<std::uint8_t> interior = interior_disks(lattice);
  const bool centroids = lattice.cell_cx.size() == n && lattice.cell_cy.size() == n;
  std::vector<std::uint8_t> moved_disk(n, 0);
  std::int64_t moved = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!interior[i]) continue;
    const double r = lattice.radius[i];
    // The disk's own stream: its site's coordinates (bit patterns) and the seed.
    const std::uint64_t h0 = splitmix64(seed ^ splitmix64(std::bit_cast<std::uint64_t>(lattice.x[i]) ^
                                                          splitmix64(std::bit_cast<std::uint64_t>(lattice.y[i]))));
    const std::uint64_t h1 = splitmix64(h0);
    // Uniform over the disk of radius fraction r: the radius as sqrt of a uniform number.
    const double rho = fraction * r * std::sqrt(unit(h0));
    const double phi = 2.0 * std::numbers::pi * unit(h1);
    const double dx = rho * std::cos(phi), dy = rho * std::sin(phi);
    lattice.x[i] += dx;
    lattice.y[i] += dy;
    if (centroids) {
      lattice.cell_cx[i] += dx;
      lattice.cell_cy[i] += dy;
    }
    moved_disk[i] = 1;
    ++moved;
  }
  if (lattice.mode == GeometryMode::Axisymmetric && lattice.bond_b.size() == lattice.num_bonds()) {
    for (std::size_t b = 0; b < lattice.num_bonds(); ++b) {
      const auto i = static_cast<std::size_t>(lattice.bond_i[b]), j = static_cast<std::size_t>(lattice.bond_j[b]);
      if (!moved_disk[i] && !moved_disk[j]) continue;  // the generator's value stands
      lattice.bond_b[b] = 0.5 * (lattice.x[i] + lattice.x[j]);
    }
  }
  return moved;
}

std::vector<double> contact_radii(const Lattice& lattice, double spread, std::uint64_t seed) {
  HEXDEM_VERIFY(spread >= 0.0 && spread <= kMaxRadiusSpread, "contact radius spread out of range");
  if (spread == 0.0) return {};
  const std::vector<std::uint8_t> interior = interior_disks(lattice);
  std::vector<double> rc(lattice.radius.begin(), lattice.radius.end());
  // A stream of its own: the seed salted, so that a disk's radius and its jitter (the same
  // seed, the same site) are independent draws.
  const std::uint64_t salted = splitmix64(seed ^ 0x636f6e7461637472ULL);  // "contactr"
  for (std::size_t i = 0; i < rc.size(); ++i) {
    if (!interior[i]) continue;
    const std::uint64_t h = splitmix64(salted ^ splitmix64(std::bit_cast<std::uint64_t>(lattice.x[i]) ^
                                                           splitmix64(std::bit_cast<std::uint64_t>(lattice.y[i]))));
    rc[i] *= 1.0 + spread * (2.0 * unit(h) - 1.0);
  }
  return rc;
}

}  // namespace hexdem::meshing
