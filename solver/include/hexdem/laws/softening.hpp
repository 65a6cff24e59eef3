#pragma once
/// \file softening.hpp
/// Tension softening with a fracture energy, and the continuum criteria that start it
/// (docs/model.md, "Fracture energy and softening"). SI units: Pa, m, J/m^2.
///
/// A bond of a material with `fracture_energy` G_F does not break when its own force reaches
/// a strength. It starts to crack when the continuum stress at its midpoint (from the local
/// strains of its two disks) reaches the tensile strength in its largest principal direction
/// n1 (Rankine), whatever the bond's own direction; then its springs soften with a scalar
/// damage D (secant unloading, closure restores the normal stiffness) so that it fails at the
/// crack opening w_c = 2 G_F / f_t projected on the bond, delta_f = w_c |n_b . n1|. Summed over
/// the bonds that a straight crack cuts, the work of their normal forces is G_F per unit
/// crack area at any lattice angle and spacing: the bonds' normal forces across the crack,
/// projected on n1, add up to f_t times the crack area at the start (equilibrium), and each
/// does F0 delta_f / 2 of work.
/// Refs: Hillerborg, Modeer, Petersson (1976) for the fictitious crack; Bolander and Saito
/// (1998) and Grassl and Jirasek (2010) for lattice models with crack-opening softening.

#include <algorithm>
#include <cmath>

namespace hexdem::laws {

/// Linear softening in the bond elongation delta (or any strain-like driver): force
/// (1 - D) k delta, peak at delta0, zero at delta_f. The area under the curve is
/// k delta0 delta_f / 2.
struct LinearSoftening {
  /// Damage at history kappa (the largest driver reached) [-], in [0, 1]:
  /// D = 1 - delta0 (delta_f - kappa) / ((delta_f - delta0) kappa) between delta0 and delta_f.
  [[nodiscard]] static double damage(double kappa, double delta0, double delta_f) noexcept {
    if (!(kappa > delta0)) return 0.0;
    if (!(kappa < delta_f)) return 1.0;
    return 1.0 - delta0 * (delta_f - kappa) / ((delta_f - delta0) * kappa);
  }

  /// Critical crack opening of a linear traction-separation law [m]: w_c = 2 G_F / f_t.
  [[nodiscard]] static double crack_opening(double G_F, double f_t) noexcept { return 2.0 * G_F / f_t; }
};

/// In-plane principal stresses and the direction of the largest one.
struct Principal2D {
  double s1 = 0, s2 = 0;  ///< s1 >= s2 [Pa]
  double n1x = 1, n1y = 0;  ///< unit vector of s1
};

/// Principal values of the symmetric tensor (sxx, syy, sxy), without the direction (one
/// square root: the criteria need the direction only when a crack starts).
[[nodiscard]] inline Principal2D principal_values_2d(double sxx, double syy, double sxy) noexcept {
  const double c = 0.5 * (sxx + syy), R = std::hypot(0.5 * (sxx - syy), sxy);
  Principal2D p;
  p.s1 = c + R;
  p.s2 = c - R;
  return p;
}

/// Principal values of the symmetric tensor (sxx, syy, sxy) and the direction of s1.
[[nodiscard]] inline Principal2D principal_2d(double sxx, double syy, double sxy) noexcept {
  const double c = 0.5 * (sxx + syy), d = 0.5 * (sxx - syy);
  const double R = std::hypot(d, sxy);
  Principal2D p;
  p.s1 = c + R;
  p.s2 = c - R;
  const double angle = 0.5 * std::atan2(sxy, d);
  p.n1x = std::cos(angle);
  p.n1y = std::sin(angle);
  return p;
}

/// Mohr-Coulomb on the continuum stress with principal values s_max >= s_min (tension
/// positive, the out-of-plane one included): shear failure when
///   (s_max - s_min) / 2 >= c cos(phi) - (s_max + s_min) / 2 sin(phi),
/// crushing when s_min <= -f_c. Uniaxial compression then fails at 2 c cos(phi) / (1 - sin(phi))
/// or f_c, whichever is smaller (the paper's Eq. 19 restated for stresses).
struct StressMohrCoulomb {
  double c = 0;        ///< cohesion [Pa]
  double sin_phi = 0;  ///< [-]
  double cos_phi = 1;  ///< [-]
  double f_c = 0;      ///< crushing strength [Pa], > 0

  /// 0: none, 2: shear, 3: compression (the FailureMode values).
  [[nodiscard]] int mode(double s_max, double s_min, double scale) const noexcept {
    if (s_min <= -f_c * scale) return 3;
    if (0.5 * (s_max - s_min) >= c * scale * cos_phi - 0.5 * (s_max + s_min) * sin_phi) return 2;
    return 0;
  }
};

/// Whether the continuum criteria can fire on the stress (sxx, syy, sxy) with out-of-plane
/// principal stress s3 [Pa]: Rankine s1 > f_t and Mohr-Coulomb mc.mode(max(s1, s3),
/// min(s2, s3), scale) (f_t already scaled and > 0; infinite: no tension check). False only
/// where the exact test is certain to find nothing, so a filtered pass gives the same bits as
/// an unfiltered one. Each criterion grows with the Mohr radius R = hypot(d, sxy) at a fixed
/// centre (s1 = c + R up, s2 = c - R down, and the Mohr-Coulomb function
/// s_max (1 + sin phi) / 2 - s_min (1 - sin phi) / 2 with them), so it is checked at an upper
/// bound of R in two brackets:
///  - |d| + |sxy| (no square root; at most sqrt(2) R), with margins of 1e-9 of the stresses
///    (skipped for a deviator below 1e-140 Pa, where subnormals lose that precision);
///  - sqrt(d^2 + sxy^2) (1 + 1e-12), with margins of 1e-12.
/// Both margins are far above the rounding of these few operations (1e-15), and the exact
/// test (principal_values_2d's hypot) decides every state that passes both.
[[nodiscard]] inline bool near_a_criterion(double sxx, double syy, double sxy, double s3, double f_t,
                                           const StressMohrCoulomb& mc, double scale) {
  const double c = 0.5 * (sxx + syy), d = 0.5 * (sxx - syy);
  // Whether the criteria can fire at Mohr radius r, with relative margin `rel`.
  const auto can_fire = [&](double r, double rel) {
    const double s1 = c + r, s2 = c - r;
    if (s1 > f_t * (1 - rel)) return true;
    const double s_max = std::max(s1, s3), s_min = std::min(s2, s3);
    if (s_min <= -mc.f_c * scale * (1 - rel)) return true;
    const double lhs = 0.5 * (s_max - s_min), rhs = mc.c * scale * mc.cos_phi - 0.5 * (s_max + s_min) * mc.sin_phi;
    const double slack = rel * (std::abs(s_max) + std::abs(s_min) + std::abs(mc.c * scale));
    return lhs >= rhs - slack;
  };
  const double r1 = std::abs(d) + std::abs(sxy);
  if (!(r1 < 1e140) || !(std::abs(c) < 1e140)) return true;  // overflow: the exact test decides
  if (r1 > 1e-140 && !can_fire(r1 * (1 + 1e-9), 1e-9)) return false;
  const double r2 = d * d + sxy * sxy;
  if (!(r2 > 1e-280)) return true;                   // underflow: the exact test decides
  return can_fire(std::sqrt(r2) * (1 + 1e-12), 1e-12);  // >= hypot(d, sxy)
}

}  // namespace hexdem::laws
