/// \file time_function.cpp
/// Load amplitudes over time: the paper's pulse (Eq. 21), ramp and hold (Eq. 23), tables.

#include "hexdem/solver/time_function.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

namespace hexdem::solver {
namespace {

/// Largest |f| on [a, b] near a single peak, by golden-section search.
template <typename F>
double golden_max(const F& f, double a, double b) {
  const double inv_phi = (std::sqrt(5.0) - 1.0) / 2.0;
  double c = b - inv_phi * (b - a), d = a + inv_phi * (b - a);
  double fc = std::abs(f(c)), fd = std::abs(f(d));
  double best = std::max({std::abs(f(a)), std::abs(f(b)), fc, fd});
  for (int iteration = 0; iteration < 200 && b - a > 1e-14 * std::max(std::abs(a), std::abs(b));
       ++iteration) {
    if (fc > fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - inv_phi * (b - a);
      fc = std::abs(f(c));
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + inv_phi * (b - a);
      fd = std::abs(f(d));
    }
    best = std::max({best, fc, fd});
  }
  return best;
}

}  // namespace

double TimeFunction::operator()(double t) const {
  switch (kind) {
    case Kind::Constant:
      return 1.0;
    case Kind::Pulse:
      // Eq. 21: p(t) = p0 exp(-alpha t^2) sin(beta t).
      return std::exp(-alpha * t * t) * std::sin(beta * t);
    case Kind::RampHold:
      // Eq. 23: linear ramp to 1 at t1, held to t2, removed after t2. Zero before t = 0.
      if (t <= 0.0) return 0.0;
      if (t <= t1) return t / t1;
      return t <= t2 ? 1.0 : 0.0;
    case Kind::Table: {
      if (table.empty()) return 0.0;
      if (t <= table.front().first) return table.front().second;
      if (t >= table.back().first) return table.back().second;
      // First point with time > t; its predecessor has time <= t.
      const auto next =
          std::upper_bound(table.begin(), table.end(), t,
                           [](double x, const auto& point) { return x < point.first; });
      const auto prev = next - 1;
      const double span = next->first - prev->first;
      if (span <= 0.0) return next->second;
      // Points more than DBL_MAX apart ([[-1e308, 0], [1e308, 1]]) overflow the span to inf,
      // which would give w = 0 everywhere: then the halves of the times, which do not overflow.
      const double w = std::isfinite(span) ? (t - prev->first) / span
                                           : (0.5 * t - 0.5 * prev->first) / (0.5 * next->first - 0.5 * prev->first);
      return (1.0 - w) * prev->second + w * next->second;
    }
  }
  return 0.0;
}

double TimeFunction::max_abs(double t_end) const {
  const double end = std::max(t_end, 0.0);
  switch (kind) {
    case Kind::Constant:
      return 1.0;
    case Kind::RampHold:
      // Rises monotonically to its value at min(end, t1) and holds it until t2.
      if (end <= 0.0) return 0.0;
      return std::abs((*this)(std::min(end, t1 > 0.0 ? t1 : t2)));
    case Kind::Table: {
      // Piecewise linear: the extremes lie at the ends of [0, end] or at vertices inside it.
      double best = std::max(std::abs((*this)(0.0)), std::abs((*this)(end)));
      for (const auto& [t, value] : table)
        if (t > 0.0 && t < end) best = std::max(best, std::abs(value));
      return best;
    }
    case Kind::Pulse: {
      if (end <= 0.0) return 0.0;
      // Sample finely enough to separate the lobes of sin(beta t) (and resolve the Gaussian
      // envelope), then refine the best few samples by golden-section search.
      const double periods = std::abs(beta) * end / (2.0 * std::numbers::pi);
      const double widths = std::sqrt(std::max(alpha, 0.0)) * end;
      const auto n = static_cast<std::size_t>(std::clamp(64.0 * (periods + widths), 1000.0, 2.0e6));
      const double h = end / static_cast<double>(n);
      std::vector<double> value(n + 1);
      for (std::size_t k = 0; k <= n; ++k) value[k] = std::abs((*this)(static_cast<double>(k) * h));
      double best = std::max(value.front(), value.back());
      // Local maxima of the samples, largest first; refine the top few.
      std::vector<std::size_t> peaks;
      for (std::size_t k = 1; k < n; ++k)
        if (value[k] >= value[k - 1] && value[k] >= value[k + 1]) peaks.push_back(k);
      std::sort(peaks.begin(), peaks.end(),
                [&](std::size_t a, std::size_t b) { return value[a] > value[b]; });
      if (peaks.size() > 4) peaks.resize(4);
      for (const std::size_t k : peaks)
        best = std::max(best, golden_max(*this, static_cast<double>(k - 1) * h,
                                         static_cast<double>(k + 1) * h));
      return best;
    }
  }
  return 0.0;
}

}  // namespace hexdem::solver
