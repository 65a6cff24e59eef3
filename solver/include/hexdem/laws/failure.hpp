#pragma once
/// \file failure.hpp
/// Bond failure: tension cut-off, Mohr-Coulomb shear and crushing, with the strain-rate
/// dependence of the strengths. The paper's Eqs. 19 and 20, restated in physics.md section 8.
/// SI units: Pa, N, m^2, 1/s.

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

#include "hexdem/error.hpp"

namespace hexdem::laws {

/// How a bond broke. The values follow hexdem::solver::BondState: a bond broken in mode m
/// has state 1 + m (BrokenTension = 2, BrokenShear = 3, BrokenCompression = 4).
enum class FailureMode : std::uint8_t { None = 0, Tension = 1, Shear = 2, Compression = 3 };

/// "none", "tension", "shear" or "compression".
constexpr std::string_view failure_mode_name(FailureMode m) noexcept {
  switch (m) {
    case FailureMode::None:
      return "none";
    case FailureMode::Tension:
      return "tension";
    case FailureMode::Shear:
      return "shear";
    case FailureMode::Compression:
      return "compression";
  }
  return "unknown";
}

/// Dynamic increase factors of Eq. 20 at one strain rate: f_td/f_t, f_cd/f_c, c_d/c.
struct RateFactors {
  double tension = 1;
  double compression = 1;
  double cohesion = 1;
};

/// A bond's strengths as forces, rate factors and cross-section included.
struct BondStrength {
  double F_t = 0;      ///< tensile strength [N]
  double F_c = 0;      ///< crushing strength [N], > 0
  double C = 0;        ///< cohesion [N]
  double tan_phi = 0;  ///< friction coefficient of the envelope [-]
};

/// Mohr-Coulomb failure with a tension cut-off and a crushing limit (forces tension positive):
///   tension      f_n > F_t
///   compression  -f_n > F_c
///   shear        |f_s| > C + tan(phi) max(-f_n, 0)
/// with F_t = f_td a, F_c = f_cd a, C = c_d a and a = 2r w the bond's cross-section (Eq. 19).
/// Ref: Liu, Gao, Tanimura (2004), Eqs. 19-20; physics.md section 8.
///
/// Precedence when several criteria hold: tension, then compression, then shear. Tension and
/// compression exclude each other (F_t >= 0, F_c > 0), so the order only ranks a normal mode
/// above shear: a bond that is past its tensile or crushing strength is reported as that,
/// whatever its shear force. A fixed order needs no division (a ratio rule would divide by
/// F_t or C, which may be zero) and, since the check runs every step, simultaneous crossings
/// are rare and the first criterion crossed is the one reported.
struct MohrCoulombFailure {
  static constexpr std::string_view name = "mohr_coulomb";
  double f_t = 0;              ///< static tensile strength [Pa], 0 <= f_t <= f_c
  double f_c = 0;              ///< static compressive strength [Pa], > 0
  double c = 0;                ///< static cohesion [Pa], >= 0
  double phi = 0;              ///< friction angle [degrees], 0 <= phi < 90
  bool rate_dependent = true;  ///< apply Eq. 20; false: all factors are 1

  /// Throws hexdem::InputError "mohr_coulomb: <field>: <problem> (got <value>)", or
  /// "mohr_coulomb: f_t > f_c (got ...)".
  void validate() const;

  /// Eq. 20, tension: 0.8743 + 0.02987 L + 0.04379 L^2 with L = log10(edot), edot [1/s].
  /// The fit is meaningless below 1/s (it rises again as the rate falls): 1 for
  /// edot <= 1/s, and never below 1 (the fit is 0.948 at 10/s and exceeds 1 above 24.4/s).
  [[nodiscard]] static double tension_rate_factor(double edot) noexcept {
    return edot > 1.0 ? tension_fit(std::log10(edot)) : 1.0;
  }

  /// Eq. 20, compression: 1.021 - 0.05076 L + 0.02583 L^2, with the same guards. Note the
  /// fit starts at 1.021 just above 1/s: the factor jumps from 1 to 1.021 there, the fit dips
  /// below 1 (clamped to 1) between 3.9/s and 23.6/s, and grows beyond.
  [[nodiscard]] static double compression_rate_factor(double edot) noexcept {
    return edot > 1.0 ? compression_fit(std::log10(edot)) : 1.0;
  }

  /// The three factors at bond strain rate edot = |d(du_n/d)/dt| [1/s]; cohesion
  /// c_d/c = sqrt((f_cd/f_c)(f_td/f_t)) (physics.md section 8). All 1 when !rate_dependent.
  [[nodiscard]] RateFactors rate_factors(double edot) const noexcept {
    if (!rate_dependent) return {};
    if (!(edot > 1.0)) return {};
    const double L = std::log10(edot);  // one logarithm for both fits
    const double t = tension_fit(L), cc = compression_fit(L);
    return {t, cc, std::sqrt(t * cc)};
  }

private:
  /// The Eq. 20 fits at L = log10(edot), clamped to >= 1.
  [[nodiscard]] static double tension_fit(double L) noexcept {
    return std::fmax(1.0, 0.8743 + L * (0.02987 + L * 0.04379));
  }
  [[nodiscard]] static double compression_fit(double L) noexcept {
    return std::fmax(1.0, 1.021 + L * (-0.05076 + L * 0.02583));
  }

public:
  /// tan(phi) [-].
  [[nodiscard]] double tan_phi() const noexcept {
    return std::tan(phi * 0.017453292519943295);  // pi / 180
  }

  /// Strengths of a bond with cross-section `section` = 2r w [m^2] (w: thickness in plane
  /// models, ring radius b per radian in axisymmetric ones, as for the stiffnesses) at strain
  /// rate edot [1/s]. Costs one tan and, with the rate law on, one log10 per factor.
  [[nodiscard]] BondStrength strength(double section, double edot) const noexcept {
    const RateFactors r = rate_factors(edot);
    return {f_t * r.tension * section, f_c * r.compression * section, c * r.cohesion * section,
            tan_phi()};
  }

  /// The failure mode of bond forces f_n (tension positive) and f_s [N], with the
  /// precedence above. Strict inequalities: a force exactly at a strength does not break.
  [[nodiscard]] static FailureMode mode(double f_n, double f_s, const BondStrength& s) noexcept {
    const bool tension = f_n > s.F_t;
    const bool compression = -f_n > s.F_c;
    const bool shear = std::fabs(f_s) > s.C + s.tan_phi * std::fmax(-f_n, 0.0);
    return tension       ? FailureMode::Tension
           : compression ? FailureMode::Compression
           : shear       ? FailureMode::Shear
                         : FailureMode::None;
  }

  /// mode(f_n, f_s, strength(section, edot)).
  [[nodiscard]] FailureMode check(double f_n, double f_s, double section,
                                  double edot) const noexcept {
    return mode(f_n, f_s, strength(section, edot));
  }
};

inline void MohrCoulombFailure::validate() const {
  const auto text = [](double value) {
    char buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
    return std::string(buffer, end);
  };
  const auto fail = [&](const char* field, const char* problem, double value) {
    throw InputError(std::string(name) + ": " + field + ": " + problem + " (got " + text(value) +
                     ")");
  };
  // Written as !(ok) so that NaN fails too.
  if (!(f_t >= 0.0) || !std::isfinite(f_t)) fail("f_t", "must be finite and >= 0", f_t);
  if (!(f_c > 0.0) || !std::isfinite(f_c)) fail("f_c", "must be finite and > 0", f_c);
  if (!(c >= 0.0) || !std::isfinite(c)) fail("c", "must be finite and >= 0", c);
  if (!(phi >= 0.0 && phi < 90.0)) fail("phi", "must be in [0, 90) degrees", phi);
  if (f_t > f_c)
    throw InputError(std::string(name) + ": f_t > f_c (got f_t = " + text(f_t) +
                     ", f_c = " + text(f_c) + ")");
}

}  // namespace hexdem::laws
