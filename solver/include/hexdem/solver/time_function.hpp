#pragma once
/// \file time_function.hpp
/// Load amplitudes as functions of time t [s] (dimensionless factors multiplying a load's
/// magnitude).

#include <string>
#include <utility>
#include <vector>

namespace hexdem::solver {

struct TimeFunction {
  enum class Kind {
    Constant,  ///< 1
    Pulse,     ///< Eq. 21: exp(-alpha t^2) sin(beta t)
    RampHold,  ///< Eq. 23: t/t1 for t <= t1, 1 for t1 < t <= t2, 0 after t2
    Table,     ///< piecewise linear through (t, value) points; constant beyond the ends
  };
  Kind kind = Kind::Constant;
  double alpha = 0, beta = 0;  ///< Pulse [1/s^2], [1/s]
  double t1 = 0, t2 = 0;       ///< RampHold [s]
  std::vector<std::pair<double, double>> table;  ///< Table, times ascending

  [[nodiscard]] double operator()(double t) const;
  /// Largest |value| over [0, t_end] (sampled finely and refined; exact for Constant,
  /// RampHold and Table).
  [[nodiscard]] double max_abs(double t_end) const;
};

}  // namespace hexdem::solver
