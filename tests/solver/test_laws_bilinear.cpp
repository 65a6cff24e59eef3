// Bilinear kinematic-hardening spring (physics.md section 7, the paper's Eq. 16), checked
// against closed forms that do not share its formulation.
//
// Reference model. The law is written in series form (spring k, slider f_y braced by a
// hardening spring H). The tests use the equivalent parallel form instead: a reversible
// spring k_h in parallel with an elastic-perfectly-plastic element of stiffness k - k_h and
// slip force s_y = (1 - k_h/k) f_y. On a monotone leg starting at (u0, s0) that element's
// force is the clamp of s0 + (k - k_h)(u - u0) to [-s_y, s_y], so
//   f(u) = k_h u + clamp(s0 + (k - k_h)(u - u0), -s_y, s_y),
// and the energy it dissipates is s_y times its slip. Only the turning points of the
// displacement history enter, never the step sizes.
//
// Loop area. After loading a virgin spring to u_a >= u_y, the cycle u_a -> -u_a -> u_a is
// the parallelogram spanned by an elastic side (2 u_y, 2 f_y) (slope k, reverse yield 2 f_y
// below the reversal force) and a hardening side (2 (u_a - u_y), 2 k_h (u_a - u_y)):
//   area = |2 u_y 2 k_h (u_a - u_y) - 2 f_y 2 (u_a - u_y)| = 4 f_y (u_a - u_y) (1 - k_h/k).
// Equivalently, the element above slips 2 (u_a - u_y) per half cycle at force s_y.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/laws/bilinear_kinematic.hpp"

namespace hexdem::laws {
namespace {

/// Parallel-form closed form of the loop, leg by leg.
struct LoopReference {
  double k, k_h, f_y;
  double u0 = 0, s0 = 0;  // start of the current leg and the element's force there
  double direction = 0;   // +1 / -1 on the current leg

  double s_y() const { return (1.0 - k_h / k) * f_y; }
  double element(double u) const { return std::clamp(s0 + (k - k_h) * (u - u0), -s_y(), s_y()); }
  double force(double u) const { return k_h * u + element(u); }
  /// Dissipation since the start of the current leg.
  double leg_dissipation(double u) const {
    const double elastic_travel = (s_y() - direction * s0) / (k - k_h);
    return s_y() * std::max(0.0, direction * (u - u0) - elastic_travel);
  }
  void start_leg(double u, double new_direction) {
    s0 = element(u);
    u0 = u;
    direction = new_direction;
  }
  /// Exact int f du from ua to ub on the current leg: f is linear on both sides of the
  /// point where the element saturates.
  double work(double ua, double ub) const {
    const double u_sat = u0 + (direction * s_y() - s0) / (k - k_h);
    const auto trapezoid = [&](double a, double b) {
      return 0.5 * (force(a) + force(b)) * (b - a);
    };
    if ((u_sat - ua) * (ub - u_sat) > 0.0) return trapezoid(ua, u_sat) + trapezoid(u_sat, ub);
    return trapezoid(ua, ub);
  }
};

/// Drives a spring through `turning_points` (starting from u = 0, virgin) with random
/// increments, some of them the rest of the leg at once, and checks every sample against the
/// reference.
struct DriveResult {
  double max_force_error = 0;        // relative to f_y + the largest |f| so far
  double max_dissipation_error = 0;  // relative to f_y u_y + D
  double max_energy_error = 0;       // |W - stored - D| relative to sum |dW| + f_y u_y
  double max_trapezoid_error = 0;    // the same with trapezoid work and dissipation
  BilinearState state;
  double dissipation = 0;
  double work = 0;
  std::size_t samples = 0;
};

DriveResult drive(const BilinearKinematic& law, const std::vector<double>& turning_points,
                  std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double u_y = law.yield_displacement();
  LoopReference ref{law.k, law.k_h, law.f_y};
  DriveResult out;
  double u = 0, dissipation_before_leg = 0, abs_work = 0, f_max = 0;
  double work_trapezoid = 0, dissipation_trapezoid = 0;
  for (const double target : turning_points) {
    if (target == u) continue;
    const double direction = target > u ? 1.0 : -1.0;
    ref.start_leg(u, direction);
    dissipation_before_leg = out.dissipation;
    while (u != target) {
      // 3 %: the rest of the leg in one increment; else log-uniform in [1e-4, 5] u_y.
      double step =
          unit(rng) < 0.03 ? std::fabs(target - u) : u_y * std::pow(10.0, -4.0 + 4.699 * unit(rng));
      step = std::min(step, std::fabs(target - u));
      const double u_next = (step == std::fabs(target - u)) ? target : u + direction * step;
      const double du = u_next - u;
      const double f_old = out.state.f;
      const BilinearStep r = law.update(out.state, du);
      work_trapezoid += 0.5 * (f_old + out.state.f) * du;
      dissipation_trapezoid += r.dissipation_trapezoid;
      EXPECT_GE(r.dissipation_trapezoid, 0.0);
      EXPECT_LE(r.dissipation_trapezoid, r.dissipation);
      const double dw = ref.work(u, u_next);
      out.work += dw;
      abs_work += std::fabs(dw);
      out.dissipation += r.dissipation;
      EXPECT_GE(r.dissipation, 0.0);
      u = u_next;
      const double f_ref = ref.force(u);
      const double d_ref = dissipation_before_leg + ref.leg_dissipation(u);
      // Round-off of an incremental law scales with the largest force of the history.
      f_max = std::max(f_max, std::fabs(f_ref));
      out.max_force_error =
          std::max(out.max_force_error, std::fabs(out.state.f - f_ref) / (law.f_y + f_max));
      out.max_dissipation_error = std::max(
          out.max_dissipation_error, std::fabs(out.dissipation - d_ref) / (law.f_y * u_y + d_ref));
      const double balance = out.work - law.stored_energy(out.state) - out.dissipation;
      out.max_energy_error =
          std::max(out.max_energy_error, std::fabs(balance) / (abs_work + law.f_y * u_y));
      const double balance_trapezoid =
          work_trapezoid - law.stored_energy(out.state) - dissipation_trapezoid;
      out.max_trapezoid_error = std::max(out.max_trapezoid_error,
                                         std::fabs(balance_trapezoid) / (abs_work + law.f_y * u_y));
      // The state never leaves the elastic range around the back-force.
      EXPECT_LE(std::fabs(out.state.f - out.state.alpha), law.f_y * (1.0 + 1e-12));
      ++out.samples;
    }
  }
  return out;
}

BilinearKinematic spring(double hardening_ratio) {
  BilinearKinematic law;
  law.k = 2.0e8;  // N/m
  law.k_h = hardening_ratio * law.k;
  law.f_y = 4.0e3;  // N
  return law;
}

const double kHardeningRatios[] = {0.0, 0.01, 0.1, 0.5, 0.9};

TEST(BilinearKinematic, Name) {
  EXPECT_EQ(BilinearKinematic::name, "bilinear_kinematic");
}

TEST(BilinearKinematic, TracesClosedFormLoopUnderRandomIncrements) {
  for (const double ratio : kHardeningRatios) {
    const BilinearKinematic law = spring(ratio);
    const double u_y = law.yield_displacement();
    // Growing, shrinking, elastic-only and offset cycles, and a very large excursion.
    std::vector<double> turns;
    for (const double a : {0.5, 1.0, 1.5, 3.0, 10.0, 2.0, 0.3, 40.0}) {
      turns.push_back(a * u_y);
      turns.push_back(-a * u_y);
    }
    for (const double t : {5.0, 4.0, 6.0, 2.0, 9.0, -1e3, 1e3, 0.0}) turns.push_back(t * u_y);
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      const DriveResult r = drive(law, turns, seed);
      EXPECT_GT(r.samples, 300u);
      EXPECT_LT(r.max_force_error, 1e-12) << "k_h/k = " << ratio << ", seed " << seed;
      EXPECT_LT(r.max_dissipation_error, 1e-12) << "k_h/k = " << ratio << ", seed " << seed;
      // W = f^2/(2k) + alpha^2/(2H) + D at every sample (physics.md section 6, Eq. 25).
      EXPECT_LT(r.max_energy_error, 1e-12) << "k_h/k = " << ratio << ", seed " << seed;
      // The trapezoid variant closes the discrete balance of a leap-frog solver.
      EXPECT_LT(r.max_trapezoid_error, 1e-12) << "k_h/k = " << ratio << ", seed " << seed;
    }
  }
}

TEST(BilinearKinematic, HugeIncrementsAreExact) {
  // A bilinear return mapping needs no sub-stepping: one increment across the whole loop
  // gives the closed form, and equals the same path cut into 10^4 pieces.
  for (const double ratio : kHardeningRatios) {
    const BilinearKinematic law = spring(ratio);
    const double u_y = law.yield_displacement();
    LoopReference ref{law.k, law.k_h, law.f_y};
    BilinearState one;
    BilinearState many;
    double d_one = 0, d_many = 0, d_ref = 0, u = 0;
    for (const double target : {1e6 * u_y, -1e6 * u_y, 0.5 * u_y}) {
      ref.start_leg(u, target > u ? 1.0 : -1.0);
      const double leg_start = u;
      d_one += law.update(one, target - u).dissipation;
      const int n = 10000;
      for (int i = 0; i < n; ++i) d_many += law.update(many, (target - u) / n).dissipation;
      d_ref += ref.leg_dissipation(target);
      u = target;
      const double f_ref = ref.force(u);
      EXPECT_NEAR(one.f, f_ref, 1e-12 * (law.f_y + std::fabs(f_ref))) << "k_h/k = " << ratio;
      // The 10^4 pieces do not add up to the leg exactly: allow their round-off, relative to
      // the force change k |du| the leg would have caused elastically.
      const double roundoff = 1e-12 * law.k * std::fabs(target - leg_start);
      EXPECT_NEAR(many.f, one.f, roundoff) << "k_h/k = " << ratio;
      EXPECT_NEAR(many.alpha, one.alpha, roundoff) << "k_h/k = " << ratio;
    }
    // Total slip of the parallel element over the three legs, at force s_y.
    const double s_y = (1 - ratio) * law.f_y;
    const double slip = (1e6 - 1.0) * u_y + (2e6 - 2.0) * u_y + (1e6 + 0.5 - 2.0) * u_y;
    EXPECT_NEAR(d_one, s_y * slip, 1e-12 * s_y * slip) << "k_h/k = " << ratio;
    EXPECT_NEAR(d_ref, s_y * slip, 1e-12 * s_y * slip) << "k_h/k = " << ratio;
    EXPECT_NEAR(d_many, d_one, 1e-9 * d_one) << "k_h/k = " << ratio;
  }
}

TEST(BilinearKinematic, CycleDissipationEqualsLoopArea) {
  for (const double ratio : kHardeningRatios) {
    const BilinearKinematic law = spring(ratio);
    const double u_y = law.yield_displacement();
    const double k = law.k, k_h = law.k_h, f_y = law.f_y;
    for (const double amplitude : {1.0, 1.5, 3.0, 10.0, 1000.0}) {
      const double u_a = amplitude * u_y;
      std::mt19937_64 rng(static_cast<std::uint64_t>(amplitude * 1000 + ratio * 100));
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      BilinearState s;
      law.update(s, u_a);  // virgin loading to the amplitude in one increment
      const BilinearState start = s;
      // Explicit Masing branches of the stabilised loop, reversal force f_a.
      const double f_a = f_y + k_h * (u_a - u_y);
      const auto branch = [&](double travel) {  // force change after `travel` from reversal
        return travel <= 2 * u_y ? k * travel : 2 * f_y + k_h * (travel - 2 * u_y);
      };
      double dissipation = 0, u = u_a;
      for (const double direction : {-1.0, 1.0}) {
        const double leg_start = u;
        const double target = direction * u_a;
        while (u != target) {
          double step = u_y * std::pow(10.0, -3.0 + 4.0 * unit(rng));
          if (unit(rng) < 0.05) step = 2 * u_a;
          const double u_next = std::fabs(target - u) <= step ? target : u + direction * step;
          dissipation += law.update(s, u_next - u).dissipation;
          u = u_next;
          const double travel = std::fabs(u - leg_start);
          const double expected = direction < 0 ? f_a - branch(travel) : -f_a + branch(travel);
          ASSERT_NEAR(s.f, expected, 1e-12 * (f_y + std::fabs(expected)))
              << "k_h/k = " << ratio << ", u_a/u_y = " << amplitude;
        }
      }
      const double area = 4 * f_y * (u_a - u_y) * (1 - k_h / k);
      EXPECT_NEAR(dissipation, area, 1e-12 * (area + f_y * u_y))
          << "k_h/k = " << ratio << ", u_a/u_y = " << amplitude;
      // The loop closes: same force and back-force as at the start of the cycle.
      EXPECT_NEAR(s.f, start.f, 1e-12 * (f_y + std::fabs(start.f)));
      EXPECT_NEAR(s.alpha, start.alpha, 1e-12 * (f_y + std::fabs(start.f)));
    }
  }
}

TEST(BilinearKinematic, BauschingerReverseYield) {
  for (const double ratio : kHardeningRatios) {
    const BilinearKinematic law = spring(ratio);
    const double u_y = law.yield_displacement();
    BilinearState loaded;
    EXPECT_TRUE(law.update(loaded, 5 * u_y).yielding);
    const double f_r = law.f_y + law.k_h * 4 * u_y;
    EXPECT_NEAR(loaded.f, f_r, 1e-12 * f_r);
    EXPECT_NEAR(loaded.alpha, f_r - law.f_y, 1e-12 * f_r);
    // Reverse yield 2 f_y below the reversal force, at alpha - f_y: less compressive than
    // the virgin -f_y as soon as there is hardening (even tensile once f_r > 3 f_y).
    const double reverse_yield = f_r - 2 * law.f_y;
    EXPECT_NEAR(reverse_yield, loaded.alpha - law.f_y, 1e-12 * f_r);
    if (ratio > 0) {
      EXPECT_GT(reverse_yield, -law.f_y);
    }
    const double travel = 2 * law.f_y / law.k;
    BilinearState just_inside = loaded;
    const BilinearStep inside = law.update(just_inside, -travel * (1 - 1e-12));
    EXPECT_FALSE(inside.yielding);
    EXPECT_EQ(inside.dissipation, 0.0);
    EXPECT_GT(just_inside.f, reverse_yield);
    EXPECT_EQ(just_inside.alpha, loaded.alpha);
    BilinearState just_beyond = loaded;
    const BilinearStep beyond = law.update(just_beyond, -travel * (1 + 1e-12));
    EXPECT_TRUE(beyond.yielding);
    EXPECT_GT(beyond.dissipation, 0.0);
    EXPECT_LE(just_beyond.f, reverse_yield);
    EXPECT_NEAR(just_beyond.f, reverse_yield, 1e-11 * law.f_y);
  }
}

TEST(BilinearKinematic, ElasticEnergyIsRecoveredHardeningEnergyIsLocked) {
  // Loadings after which unloading to f = 0 stays elastic (alpha < f_y).
  for (const auto& [ratio, amplitude] : {std::pair{0.1, 7.0}, {0.2, 3.0}, {0.5, 2.0}}) {
    const BilinearKinematic law = spring(ratio);
    const double u_y = law.yield_displacement();
    BilinearState s;
    law.update(s, amplitude * u_y);
    ASSERT_LT(s.alpha, law.f_y);
    const double elastic = law.elastic_energy(s);
    const double hardening = law.hardening_energy(s);
    EXPECT_NEAR(elastic, s.f * s.f / (2 * law.k), 1e-15 * elastic);
    // alpha = H u_p with H = k k_h / (k - k_h).
    const double H = law.k * law.k_h / (law.k - law.k_h);
    EXPECT_NEAR(hardening, s.alpha * s.alpha / (2 * H), 1e-12 * hardening);
    // Elastic unloading to f = 0 returns exactly f^2/(2k); the hardening energy stays.
    const double du = -s.f / law.k;
    const double work_back = 0.5 * s.f * du;  // linear unloading
    const BilinearStep r = law.update(s, du);
    EXPECT_FALSE(r.yielding);
    EXPECT_NEAR(s.f, 0.0, 1e-12 * law.f_y);
    EXPECT_NEAR(-work_back, elastic, 1e-12 * elastic);
    EXPECT_NEAR(law.hardening_energy(s), hardening, 1e-12 * hardening);
  }
  // Without hardening the back-force stays zero and nothing is locked in.
  const BilinearKinematic plastic = spring(0.0);
  BilinearState s;
  plastic.update(s, 50 * plastic.yield_displacement());
  plastic.update(s, -80 * plastic.yield_displacement());
  EXPECT_EQ(s.alpha, 0.0);
  EXPECT_EQ(plastic.hardening_energy(s), 0.0);
  EXPECT_EQ(s.f, -plastic.f_y);
}

TEST(BilinearKinematic, ValidateNamesFieldAndValue) {
  const auto message = [](const BilinearKinematic& law) -> std::string {
    try {
      law.validate();
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(message(spring(0.2)), "");
  EXPECT_EQ(message(spring(0.0)), "");
  BilinearKinematic law = spring(0.2);
  law.k = -1;
  EXPECT_EQ(message(law), "bilinear_kinematic: k: must be finite and > 0 (got -1)");
  law = spring(0.2);
  law.k = 0;
  EXPECT_NE(message(law).find("k: must be finite and > 0 (got 0)"), std::string::npos);
  law = spring(0.2);
  law.k_h = -5;
  EXPECT_EQ(message(law), "bilinear_kinematic: k_h: must be >= 0 and < k (got -5)");
  law = spring(0.2);
  law.k_h = law.k;
  EXPECT_EQ(message(law), "bilinear_kinematic: k_h: must be >= 0 and < k (got 2e+08)");
  law = spring(0.2);
  law.f_y = 0;
  EXPECT_EQ(message(law), "bilinear_kinematic: f_y: must be finite and > 0 (got 0)");
  law = spring(0.2);
  law.f_y = std::nan("");
  EXPECT_NE(message(law).find("f_y: must be finite and > 0 (got nan)"), std::string::npos);
}

}  // namespace
}  // namespace hexdem::laws
