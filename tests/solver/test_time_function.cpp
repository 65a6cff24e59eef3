// Load amplitudes over time: constant, the paper's pulse (Eq. 21), ramp and hold (Eq. 23),
// tables.

#include <gtest/gtest.h>

#include <cmath>

#include "hexdem/solver/time_function.hpp"

namespace hexdem::solver {
namespace {

/// Eq. 21 as printed: alpha = 5.689e9 1/s^2, beta = 2659 1/s.
TimeFunction paper_pulse() {
  TimeFunction f;
  f.kind = TimeFunction::Kind::Pulse;
  f.alpha = 5.689e9;
  f.beta = 2659.0;
  return f;
}

TimeFunction ramp_hold(double t1, double t2) {
  TimeFunction f;
  f.kind = TimeFunction::Kind::RampHold;
  f.t1 = t1;
  f.t2 = t2;
  return f;
}

TimeFunction table(std::vector<std::pair<double, double>> points) {
  TimeFunction f;
  f.kind = TimeFunction::Kind::Table;
  f.table = std::move(points);
  return f;
}

/// max |f| on [0, t_end] from n + 1 equally spaced samples (independent of max_abs).
double sampled_max(const TimeFunction& f, double t_end, int n) {
  double best = 0.0;
  for (int k = 0; k <= n; ++k) best = std::max(best, std::abs(f(t_end * k / n)));
  return best;
}

TEST(TimeFunction, ConstantIsOne) {
  const TimeFunction f;
  EXPECT_EQ(f.kind, TimeFunction::Kind::Constant);
  EXPECT_EQ(f(0.0), 1.0);
  EXPECT_EQ(f(1.0), 1.0);
  EXPECT_EQ(f(-1.0), 1.0);
  EXPECT_EQ(f.max_abs(10.0), 1.0);
  EXPECT_EQ(f.max_abs(0.0), 1.0);
}

TEST(TimeFunction, PulseFormula) {
  const TimeFunction f = paper_pulse();
  EXPECT_EQ(f(0.0), 0.0);
  for (const double t : {1e-6, 9.4e-6, 30e-6, 104e-6}) {
    EXPECT_DOUBLE_EQ(f(t), std::exp(-5.689e9 * t * t) * std::sin(2659.0 * t));
  }
}

TEST(TimeFunction, PaperPulseMaximum) {
  // For beta^2 << alpha the maximum is near t = 1/sqrt(2 alpha): about 0.0151 at 9.4 us.
  const TimeFunction f = paper_pulse();
  const double m = f.max_abs(104e-6);
  const double dense = sampled_max(f, 104e-6, 2'000'000);
  EXPECT_GE(m, dense * (1.0 - 1e-12));
  EXPECT_NEAR(m, dense, 1e-9 * dense);
  const double t_peak = 1.0 / std::sqrt(2.0 * 5.689e9);
  EXPECT_NEAR(m, 2659.0 * t_peak * std::exp(-0.5), 2e-3 * m);
  // Before the peak, the maximum is the value at the end of the interval.
  EXPECT_NEAR(f.max_abs(4e-6), f(4e-6), 1e-14);
}

TEST(TimeFunction, OscillatingPulseMaximum) {
  // Many lobes under a slowly decaying envelope: the first lobe is the largest.
  TimeFunction f;
  f.kind = TimeFunction::Kind::Pulse;
  f.alpha = 1e8;
  f.beta = 2.0e6;
  const double t_end = 300e-6;
  const double m = f.max_abs(t_end);
  const double dense = sampled_max(f, t_end, 4'000'000);
  EXPECT_GE(m, dense * (1.0 - 1e-12));
  EXPECT_NEAR(m, dense, 1e-7);
  EXPECT_LE(m, 1.0);
  // A negative lobe counts by its magnitude.
  TimeFunction g = f;
  g.beta = -f.beta;
  EXPECT_NEAR(g.max_abs(t_end), m, 1e-12);
}

TEST(TimeFunction, RampHoldCorners) {
  // Eq. 23 with the paper's example 2: t1 = 100 us, t2 = 160 us.
  const TimeFunction f = ramp_hold(100e-6, 160e-6);
  EXPECT_EQ(f(0.0), 0.0);
  EXPECT_EQ(f(-1e-6), 0.0);
  EXPECT_DOUBLE_EQ(f(25e-6), 0.25);
  EXPECT_DOUBLE_EQ(f(100e-6), 1.0);
  EXPECT_EQ(f(100.000001e-6), 1.0);
  EXPECT_EQ(f(160e-6), 1.0);
  EXPECT_EQ(f(160.000001e-6), 0.0);
  EXPECT_EQ(f(1.0), 0.0);
  EXPECT_DOUBLE_EQ(f.max_abs(50e-6), 0.5);
  EXPECT_DOUBLE_EQ(f.max_abs(104e-6), 1.0);
  EXPECT_DOUBLE_EQ(f.max_abs(1.0), 1.0);
  EXPECT_EQ(f.max_abs(0.0), 0.0);
  // t1 = t2: a ramp and an immediate release.
  const TimeFunction g = ramp_hold(1e-5, 1e-5);
  EXPECT_EQ(g(1e-5), 1.0);
  EXPECT_EQ(g(1.1e-5), 0.0);
  EXPECT_EQ(g.max_abs(1.0), 1.0);
}

TEST(TimeFunction, TableInterpolates) {
  const TimeFunction f = table({{1.0, 2.0}, {2.0, -4.0}, {4.0, 0.0}});
  EXPECT_EQ(f(0.0), 2.0);  // constant before the first point
  EXPECT_EQ(f(1.0), 2.0);
  EXPECT_DOUBLE_EQ(f(1.5), -1.0);
  EXPECT_EQ(f(2.0), -4.0);
  EXPECT_DOUBLE_EQ(f(3.0), -2.0);
  EXPECT_EQ(f(4.0), 0.0);
  EXPECT_EQ(f(9.0), 0.0);  // constant after the last point
  EXPECT_DOUBLE_EQ(f.max_abs(1.5), 2.0);
  EXPECT_DOUBLE_EQ(f.max_abs(1.75), 2.5);  // end of the interval inside a segment
  EXPECT_DOUBLE_EQ(f.max_abs(10.0), 4.0);  // interior vertex
  const TimeFunction g = table({{-1.0, 0.0}, {1.0, 2.0}});
  EXPECT_DOUBLE_EQ(g(0.0), 1.0);
  EXPECT_DOUBLE_EQ(g.max_abs(0.5), 1.5);
  EXPECT_DOUBLE_EQ(g.max_abs(0.0), 1.0);
}

TEST(TimeFunction, TableSpanBeyondTheDoubleRangeInterpolates) {
  // Was: t1 - t0 overflowed to inf, and (t - t0) / inf = 0 gave the first value everywhere:
  // a pressure of [[-1e308, 0], [1e308, 1]] was never applied.
  const TimeFunction f = table({{-1e308, 0.0}, {1e308, 1.0}});
  EXPECT_DOUBLE_EQ(f(0.0), 0.5);
  EXPECT_DOUBLE_EQ(f(1e-6), 0.5);
  EXPECT_DOUBLE_EQ(f(1e307), 0.55);
  EXPECT_DOUBLE_EQ(f(-1e308), 0.0);
  EXPECT_DOUBLE_EQ(f.max_abs(1e-4), 0.5);
  const TimeFunction g = table({{-1.7e308, -1.0}, {1.7e308, 1.0}});
  EXPECT_DOUBLE_EQ(g(0.0), 0.0);
  EXPECT_DOUBLE_EQ(g(8.5e307), 0.5);
}

}  // namespace
}  // namespace hexdem::solver
