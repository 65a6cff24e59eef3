// Bond failure (physics.md section 8, the paper's Eqs. 19-20): each criterion straddled at
// 1e-12 relative, the Mohr-Coulomb envelope, the rate factors against Eq. 20 evaluated here
// independently, and input validation.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "hexdem/error.hpp"
#include "hexdem/laws/failure.hpp"

namespace hexdem::laws {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kBelow = 1.0 - 1e-12;
constexpr double kAbove = 1.0 + 1e-12;

/// The warhead case's concrete (physics.md section 9).
MohrCoulombFailure concrete(bool rate_dependent = true) {
  MohrCoulombFailure law;
  law.f_t = 4.0e6;
  law.f_c = 40.0e6;
  law.c = 11.5e6;
  law.phi = 30.0;
  law.rate_dependent = rate_dependent;
  return law;
}

/// Eq. 20 as printed (log base 10), without the guards.
double tension_fit(double edot) {
  const double L = std::log10(edot);
  return 0.8743 + 0.02987 * L + 0.04379 * L * L;
}
double compression_fit(double edot) {
  const double L = std::log10(edot);
  return 1.021 - 0.05076 * L + 0.02583 * L * L;
}

/// A bond of radius 0.5 mm in a plate 10 mm thick: cross-section 2r w [m^2].
constexpr double kSection = 2 * 0.5e-3 * 10e-3;

TEST(MohrCoulombFailure, Names) {
  EXPECT_EQ(MohrCoulombFailure::name, "mohr_coulomb");
  EXPECT_EQ(failure_mode_name(FailureMode::None), "none");
  EXPECT_EQ(failure_mode_name(FailureMode::Tension), "tension");
  EXPECT_EQ(failure_mode_name(FailureMode::Shear), "shear");
  EXPECT_EQ(failure_mode_name(FailureMode::Compression), "compression");
  // Broken-bond states are 1 + mode (hexdem::solver::BondState).
  EXPECT_EQ(static_cast<int>(FailureMode::Tension), 1);
  EXPECT_EQ(static_cast<int>(FailureMode::Shear), 2);
  EXPECT_EQ(static_cast<int>(FailureMode::Compression), 3);
}

TEST(MohrCoulombFailure, RateFactorsFollowEquation20) {
  // Rates 1, 10, 100, 1000 1/s: Eq. 20 floored at 1, and exactly 1 at and below 1/s.
  EXPECT_EQ(MohrCoulombFailure::tension_rate_factor(1.0), 1.0);
  EXPECT_EQ(MohrCoulombFailure::compression_rate_factor(1.0), 1.0);
  for (const double edot : {10.0, 100.0, 1000.0}) {
    const double t = std::max(1.0, tension_fit(edot));
    const double c = std::max(1.0, compression_fit(edot));
    EXPECT_NEAR(MohrCoulombFailure::tension_rate_factor(edot), t, 1e-14 * t) << edot;
    EXPECT_NEAR(MohrCoulombFailure::compression_rate_factor(edot), c, 1e-14 * c) << edot;
  }
  // The fits themselves dip below 1 at 10/s (0.94796 and 0.99607): floored to 1.
  EXPECT_NEAR(tension_fit(10.0), 0.94796, 1e-12);
  EXPECT_NEAR(compression_fit(10.0), 0.99607, 1e-12);
  EXPECT_EQ(MohrCoulombFailure::tension_rate_factor(10.0), 1.0);
  EXPECT_EQ(MohrCoulombFailure::compression_rate_factor(10.0), 1.0);
  // Hand values of the polynomials at L = 2 and 3.
  EXPECT_NEAR(MohrCoulombFailure::tension_rate_factor(100.0), 1.1092, 1e-12);
  EXPECT_NEAR(MohrCoulombFailure::compression_rate_factor(100.0), 1.02280, 1e-12);
  EXPECT_NEAR(MohrCoulombFailure::tension_rate_factor(1000.0), 1.35802, 1e-12);
  EXPECT_NEAR(MohrCoulombFailure::compression_rate_factor(1000.0), 1.10119, 1e-12);

  const MohrCoulombFailure law = concrete();
  const RateFactors r = law.rate_factors(1000.0);
  EXPECT_NEAR(r.cohesion, std::sqrt(1.35802 * 1.10119), 1e-12);
  EXPECT_NEAR(r.tension, 1.35802, 1e-12);
  EXPECT_NEAR(r.compression, 1.10119, 1e-12);
}

TEST(MohrCoulombFailure, LowRateGuard) {
  // Below 1/s the tension fit grows again (1.19 at 1e-3/s) and the compression fit exceeds 1:
  // both factors are exactly 1 there, including 0 and the rate of a bond at rest.
  EXPECT_GT(tension_fit(1e-3), 1.1);
  EXPECT_GT(compression_fit(0.5), 1.0);
  for (const double edot : {0.0, 1e-300, 1e-9, 1e-3, 0.1, 0.5, 0.999999, 1.0}) {
    EXPECT_EQ(MohrCoulombFailure::tension_rate_factor(edot), 1.0) << edot;
    EXPECT_EQ(MohrCoulombFailure::compression_rate_factor(edot), 1.0) << edot;
  }
  // Never below 1, at any rate.
  for (double edot = 1.0; edot < 1e6; edot *= 1.07) {
    EXPECT_GE(MohrCoulombFailure::tension_rate_factor(edot), 1.0) << edot;
    EXPECT_GE(MohrCoulombFailure::compression_rate_factor(edot), 1.0) << edot;
  }
  // Above 1/s the compression fit starts at 1.021 (the documented jump).
  EXPECT_NEAR(MohrCoulombFailure::compression_rate_factor(1.000001), 1.021, 1e-6);
}

TEST(MohrCoulombFailure, RateLawSwitch) {
  const MohrCoulombFailure off = concrete(false);
  const RateFactors r = off.rate_factors(1000.0);
  EXPECT_EQ(r.tension, 1.0);
  EXPECT_EQ(r.compression, 1.0);
  EXPECT_EQ(r.cohesion, 1.0);
  const BondStrength s = off.strength(kSection, 1e4);
  EXPECT_EQ(s.F_t, 4.0e6 * kSection);
  EXPECT_EQ(s.F_c, 40.0e6 * kSection);
  EXPECT_EQ(s.C, 11.5e6 * kSection);
  EXPECT_NEAR(s.tan_phi, 1.0 / std::sqrt(3.0), 1e-15);
}

TEST(MohrCoulombFailure, EachCriterionBreaksAtPredictedForce) {
  for (const bool rate : {false, true}) {
    for (const double edot : {0.0, 1.0, 100.0, 1000.0}) {
      const MohrCoulombFailure law = concrete(rate);
      // Strengths computed here from Eq. 19 and Eq. 20.
      const double t = rate && edot > 1 ? std::max(1.0, tension_fit(edot)) : 1.0;
      const double c = rate && edot > 1 ? std::max(1.0, compression_fit(edot)) : 1.0;
      const double F_t = law.f_t * t * kSection;
      const double F_c = law.f_c * c * kSection;
      const double C = law.c * std::sqrt(t * c) * kSection;
      const double tan_phi = std::tan(30.0 * kPi / 180.0);
      const BondStrength s = law.strength(kSection, edot);
      EXPECT_NEAR(s.F_t, F_t, 1e-15 * F_t);
      EXPECT_NEAR(s.F_c, F_c, 1e-15 * F_c);
      EXPECT_NEAR(s.C, C, 1e-15 * C);
      EXPECT_NEAR(s.tan_phi, tan_phi, 1e-15);

      // Tension, no shear force.
      EXPECT_EQ(law.check(F_t * kBelow, 0.0, kSection, edot), FailureMode::None);
      EXPECT_EQ(law.check(F_t * kAbove, 0.0, kSection, edot), FailureMode::Tension);
      // Crushing, no shear force.
      EXPECT_EQ(law.check(-F_c * kBelow, 0.0, kSection, edot), FailureMode::None);
      EXPECT_EQ(law.check(-F_c * kAbove, 0.0, kSection, edot), FailureMode::Compression);
      // Pure shear, either sign.
      for (const double sign : {1.0, -1.0}) {
        EXPECT_EQ(law.check(0.0, sign * C * kBelow, kSection, edot), FailureMode::None);
        EXPECT_EQ(law.check(0.0, sign * C * kAbove, kSection, edot), FailureMode::Shear);
      }
      // Shear under tension: no frictional strength, the cohesion alone.
      EXPECT_EQ(law.check(0.5 * F_t, C * kBelow, kSection, edot), FailureMode::None);
      EXPECT_EQ(law.check(0.5 * F_t, C * kAbove, kSection, edot), FailureMode::Shear);
    }
  }
}

TEST(MohrCoulombFailure, EnvelopeUnderCompression) {
  for (const double phi : {0.0, 15.0, 30.0, 45.0, 60.0, 89.0}) {
    MohrCoulombFailure law = concrete(false);
    law.phi = phi;
    const BondStrength s = law.strength(kSection, 0.0);
    const double tan_phi = std::tan(phi * kPi / 180.0);
    for (const double fraction : {0.0, 0.01, 0.1, 0.3, 0.6, 0.9, 0.999}) {
      const double p = fraction * s.F_c;  // compression magnitude
      const double limit = s.C + tan_phi * p;
      for (const double sign : {1.0, -1.0}) {
        EXPECT_EQ(MohrCoulombFailure::mode(-p, sign * limit * kBelow, s), FailureMode::None)
            << "phi " << phi << ", p/F_c " << fraction;
        EXPECT_EQ(MohrCoulombFailure::mode(-p, sign * limit * kAbove, s), FailureMode::Shear)
            << "phi " << phi << ", p/F_c " << fraction;
      }
    }
  }
  // Zero cohesion: a purely frictional envelope through the origin.
  MohrCoulombFailure sand = concrete(false);
  sand.c = 0;
  const BondStrength s = sand.strength(kSection, 0.0);
  EXPECT_EQ(MohrCoulombFailure::mode(0.0, 0.0, s), FailureMode::None);
  EXPECT_EQ(MohrCoulombFailure::mode(0.0, 1e-300, s), FailureMode::Shear);
  EXPECT_EQ(MohrCoulombFailure::mode(-1.0, s.tan_phi * kBelow, s), FailureMode::None);
  EXPECT_EQ(MohrCoulombFailure::mode(-1.0, s.tan_phi * kAbove, s), FailureMode::Shear);
}

TEST(MohrCoulombFailure, PrecedenceTensionThenCompressionThenShear) {
  const MohrCoulombFailure law = concrete(false);
  const BondStrength s = law.strength(kSection, 0.0);
  const double huge_shear = 1e3 * (s.C + s.tan_phi * s.F_c);
  EXPECT_EQ(MohrCoulombFailure::mode(2 * s.F_t, huge_shear, s), FailureMode::Tension);
  EXPECT_EQ(MohrCoulombFailure::mode(-2 * s.F_c, huge_shear, s), FailureMode::Compression);
  EXPECT_EQ(MohrCoulombFailure::mode(0.5 * s.F_t, huge_shear, s), FailureMode::Shear);
  EXPECT_EQ(MohrCoulombFailure::mode(-0.5 * s.F_c, -huge_shear, s), FailureMode::Shear);
  // Exactly at a strength does not break (strict inequalities).
  EXPECT_EQ(MohrCoulombFailure::mode(s.F_t, 0.0, s), FailureMode::None);
  EXPECT_EQ(MohrCoulombFailure::mode(-s.F_c, 0.0, s), FailureMode::None);
  EXPECT_EQ(MohrCoulombFailure::mode(0.0, s.C, s), FailureMode::None);
  // Zero tensile strength: any tension breaks.
  MohrCoulombFailure no_tension = concrete(false);
  no_tension.f_t = 0;
  EXPECT_EQ(no_tension.check(1e-300, 0.0, kSection, 0.0), FailureMode::Tension);
  EXPECT_EQ(no_tension.check(0.0, 0.0, kSection, 0.0), FailureMode::None);
}

std::string validation_message(const MohrCoulombFailure& law) {
  try {
    law.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MohrCoulombFailure, ValidateNamesFieldAndValue) {
  EXPECT_EQ(validation_message(concrete()), "");
  MohrCoulombFailure law = concrete();
  law.f_t = -1;
  EXPECT_EQ(validation_message(law), "mohr_coulomb: f_t: must be finite and >= 0 (got -1)");
  law = concrete();
  law.f_c = 0;
  EXPECT_EQ(validation_message(law), "mohr_coulomb: f_c: must be finite and > 0 (got 0)");
  law = concrete();
  law.f_c = -3e7;
  EXPECT_EQ(validation_message(law), "mohr_coulomb: f_c: must be finite and > 0 (got -3e+07)");
  law = concrete();
  law.c = -0.5;
  EXPECT_EQ(validation_message(law), "mohr_coulomb: c: must be finite and >= 0 (got -0.5)");
  law = concrete();
  law.f_t = 5e7;
  EXPECT_EQ(validation_message(law), "mohr_coulomb: f_t > f_c (got f_t = 5e+07, f_c = 4e+07)");
  law = concrete();
  law.f_t = law.f_c;  // equal is allowed
  EXPECT_EQ(validation_message(law), "");
  for (const double phi : {-1.0, 90.0, 135.0, std::numeric_limits<double>::quiet_NaN()}) {
    law = concrete();
    law.phi = phi;
    const std::string m = validation_message(law);
    EXPECT_NE(m.find("mohr_coulomb: phi: must be in [0, 90) degrees (got "), std::string::npos)
        << m;
  }
  law = concrete();
  law.phi = 0;
  EXPECT_EQ(validation_message(law), "");
  law.phi = 89.999;
  EXPECT_EQ(validation_message(law), "");
  law = concrete();
  law.f_t = std::numeric_limits<double>::infinity();
  EXPECT_EQ(validation_message(law), "mohr_coulomb: f_t: must be finite and >= 0 (got inf)");
  law = concrete();
  law.c = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(validation_message(law).find("mohr_coulomb: c: "), std::string::npos);
}

}  // namespace
}  // namespace hexdem::laws
