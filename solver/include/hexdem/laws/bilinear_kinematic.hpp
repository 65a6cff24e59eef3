#pragma once
/// \file bilinear_kinematic.hpp
/// Bilinear spring with linear kinematic hardening (Masing rule), the paper's Eq. 16 and
/// "yield degree" bookkeeping (Fig. 2) restated in physics.md section 7. SI units: N, m, N/m, J.

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>

#include "hexdem/error.hpp"

namespace hexdem::laws {

/// State of one bilinear spring. Start from the default (virgin, unloaded) state.
struct BilinearState {
  double f = 0;      ///< spring force [N], tension (or positive shear) positive
  double alpha = 0;  ///< back-force: centre of the elastic range [f - f_y, f + f_y] [N]
};

/// What one update did.
struct BilinearStep {
  /// Plastic dissipation of the increment along the true (piecewise linear) path [J], >= 0.
  double dissipation = 0;
  /// The dissipation that closes a balance whose work is summed with the trapezoid rule,
  /// (f_old + f_new) du / 2 - change of stored_energy() [J], as the leap-frog energy
  /// identity does (docs/model.md, "Stress and energy"). It equals `dissipation` except on
  /// an increment that passes from elastic (travel a) to plastic (travel b), where it is
  /// smaller by a b (k - k_h) / 2; it is never negative (a <= 2 f_y / k).
  double dissipation_trapezoid = 0;
  bool yielding = false;  ///< the increment ended on the yield surface with plastic flow
};

/// 1D spring: elastic stiffness k, hardening stiffness k_h (0 <= k_h < k), yield force f_y,
/// and an elastic range of width 2 f_y that translates with the back-force alpha.
/// Ref: Liu, Gao, Tanimura (2004), Eq. 16 and Fig. 2; physics.md section 7.
///
/// Rheology (series form): an elastic spring k in series with a friction slider of strength
/// f_y that is braced by a hardening spring H = k k_h / (k - k_h). With u_p the slider's
/// displacement, f = k (u - u_p), alpha = H u_p, yield when |f - alpha| = f_y, and the
/// tangent stiffness is k elastically and k H / (k + H) = k_h while yielding.
///
/// Energy (exact for every path): the work done on the spring, W = int f du, splits into
///   W = elastic_energy + hardening_energy + D_plastic
///   elastic_energy   = f^2 / (2 k)         recovered on elastic unloading to f = 0
///   hardening_energy = alpha^2 / (2 H)     stored but locked in: it stays in the spring at
///                                          f = 0 and comes back only through reverse flow
///   D_plastic        = f_y int |du_p|      dissipated (sum of BilinearStep::dissipation)
/// In an energy balance both stored terms count as stored energy (stored_energy()); only
/// D_plastic is dissipated.
struct BilinearKinematic {
  static constexpr std::string_view name = "bilinear_kinematic";
  double k = 0;    ///< elastic stiffness [N/m], > 0
  double k_h = 0;  ///< hardening (post-yield tangent) stiffness [N/m], 0 <= k_h < k
  double f_y = 0;  ///< yield force [N], > 0 (sigma_y * 2r * w, physics.md section 7)

  /// Throws hexdem::InputError "bilinear_kinematic: <field>: <problem> (got <value>)".
  void validate() const;

  /// Yield displacement u_y = f_y / k [m] of the virgin spring.
  [[nodiscard]] double yield_displacement() const noexcept { return f_y / k; }

  /// Applies the displacement increment du [m] by elastic predictor and return mapping.
  /// Exact for any |du| (a bilinear law has one kink per monotone increment, and the
  /// closest-point projection lands on it): one huge increment gives the same state and
  /// dissipation as any subdivision of it. Branch-free, allocation-free.
  BilinearStep update(BilinearState& s, double du) const noexcept {
    const double f_trial = s.f + k * du;
    const double xi = f_trial - s.alpha;
    const double excess = std::fmax(std::fabs(xi) - f_y, 0.0);  // yield function, trial
    const double direction = std::copysign(1.0, xi);
    const double r = k_h / k;
    // Plastic displacement dgamma = excess / (k + H) = excess (k - k_h) / k^2: the
    // back-force moves by H dgamma = excess r, and the force returns by k dgamma =
    // excess (1 - r), which puts it at alpha + direction f_y. Written as "back-force plus
    // the clamped relative force" so that a huge increment loses no digits.
    const double back = s.alpha + direction * excess * r;
    s.f = back + direction * std::fmin(std::fabs(xi), f_y);
    s.alpha = back;
    // The trial overshoots the yield surface by k b (b: plastic travel); a = |du| - b.
    const double elastic_travel = std::fmax(std::fabs(du) - excess / k, 0.0);
    const double dgamma = excess * (1.0 - r) / k;
    return {f_y * dgamma, dgamma * std::fmax(f_y - 0.5 * k * elastic_travel, 0.0), excess > 0.0};
  }

  /// Recoverable elastic energy f^2 / (2 k) [J].
  [[nodiscard]] double elastic_energy(const BilinearState& s) const noexcept {
    return 0.5 * s.f * s.f / k;
  }

  /// Energy locked in the hardening spring, alpha^2 / (2 H) = alpha^2 (k - k_h) / (2 k k_h)
  /// [J]; zero without hardening (alpha stays 0 when k_h = 0).
  [[nodiscard]] double hardening_energy(const BilinearState& s) const noexcept {
    return k_h > 0.0 ? 0.5 * s.alpha * s.alpha * (k - k_h) / (k * k_h) : 0.0;
  }

  /// elastic_energy + hardening_energy [J]: the spring's stored energy in a balance.
  [[nodiscard]] double stored_energy(const BilinearState& s) const noexcept {
    return elastic_energy(s) + hardening_energy(s);
  }
};

inline void BilinearKinematic::validate() const {
  const auto fail = [](const char* field, const char* problem, double value) {
    char buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
    throw InputError(std::string(name) + ": " + field + ": " + problem + " (got " +
                     std::string(buffer, end) + ")");
  };
  // Written as !(ok) so that NaN fails too.
  if (!(k > 0.0) || !std::isfinite(k)) fail("k", "must be finite and > 0", k);
  if (!(k_h >= 0.0) || !(k_h < k)) fail("k_h", "must be >= 0 and < k", k_h);
  if (!(f_y > 0.0) || !std::isfinite(f_y)) fail("f_y", "must be finite and > 0", f_y);
}

}  // namespace hexdem::laws
