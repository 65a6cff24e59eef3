#pragma once
/// \file contact.hpp
/// Linear spring-dashpot contact with Coulomb friction, for broken bonds (state II) and disks
/// of different bodies: physics.md section 8 (the paper's Eq. 17 is ambiguous as printed).
/// SI units: m, m/s, kg, N, N/m, N s/m, J, W.

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>

#include "hexdem/error.hpp"

namespace hexdem::laws {

/// State of one contact: the forces after the last update. Start from the default (no
/// contact). The normal force is recomputed from the overlap each step; the tangential force
/// is incremental and is the only history.
struct ContactState {
  double f_n = 0;  ///< normal force [N], tension positive, so always <= 0
  double f_s = 0;  ///< tangential force [N], same sign convention as a bond's f_s
  double f_v = 0;  ///< the dashpot's part of f_n [N] (f_n + k_n delta), for the trapezoid work
};

/// What one update did.
struct ContactStep {
  double friction_dissipation = 0;  ///< energy dissipated by friction in this update [J]
  double damping_power = 0;         ///< power absorbed by the dashpot [W], >= 0
  /// Power of the dashpot for the leap-frog energy balance [W]: -(f_v,old + f_v,new) delta_dot / 2.
  /// Central differences apply the force of update n over the half steps on both sides of
  /// t_n, so the work that the kinetic energy v(t-dt/2).v(t+dt/2) sees at t_n is, per
  /// velocity v(t-dt/2), half of the previous force and half of the new one: the trapezoid
  /// rule, which makes the booked dashpot work and the kinetic energy agree step by step.
  double damping_power_mid = 0;
  /// Dashpot work of this update in the leap-frog balance [J].
  [[nodiscard]] double damping_work(double dt) const noexcept { return damping_power_mid * dt; }
  /// Friction dissipation for the leap-frog energy balance [J]: the trapezoid work of the
  /// tangential force over the increment, (f_s,old + f_s,new) du_s / 2, less the change of the
  /// tangential spring's energy. It differs from friction_dissipation (the exact slider) within
  /// a step where sticking turns into sliding, and adds up with the kinetic energy of central
  /// differences exactly; it can be negative where a force far above a cap that fell reverses
  /// within one step.
  double friction_dissipation_mid = 0;
  bool sliding = false;             ///< in contact and the Coulomb cap was active
};

/// Normal: linear spring in compression only with a viscous dashpot, the total normal force
/// cut at zero (no tension, ever):
///   f_n = min(0, -(k_n delta + c_n delta_dot))  for delta > 0,  f_n = 0 otherwise,
///   c_n = 2 eta sqrt(m_eff k_n),  m_eff = m_i m_j / (m_i + m_j),
/// delta the overlap [m] and delta_dot its rate [m/s] (positive while approaching).
/// Tangential: incremental spring f_s += k_s du_s capped by Coulomb friction
/// |f_s| <= mu |f_n|, with du_s the tangential displacement increment at the contact point
/// (as for a bond, physics.md section 2). No tangential dashpot: the paper gives only a
/// normal damping, and a tangential dashpot in parallel with the slider would need its own
/// rule for the cap; sliding dissipates the tangential energy instead.
/// Ref: Liu, Gao, Tanimura (2004), Eq. 17; physics.md section 8.
///
/// Energy: stored_energy() = k_n delta^2 / 2 + f_s^2 / (2 k_s). The work done on the
/// contact equals the change of the stored energy plus int damping_power dt plus the sum of
/// friction_dissipation. With the cut, the dashpot part of the force is
/// f_v = f_n + k_n delta (= -c_n delta_dot uncut, = k_n delta while cut), and
/// damping_power = -f_v delta_dot >= 0. Tangential energy still stored when the contact
/// opens is dissipated (counted in friction_dissipation).
///
/// Head-on restitution of this law (restitution()): the cut makes contact end when the
/// total force reaches zero, before the overlap does, so e is larger than the textbook
/// exp(-pi eta / sqrt(1 - eta^2)) of the dashpot that may pull.
struct LinearContact {
  static constexpr std::string_view name = "linear_contact";
  double k_n = 0;  ///< normal stiffness [N/m], > 0
  double k_s = 0;  ///< tangential stiffness [N/m], > 0
  double mu = 0;   ///< friction coefficient [-], >= 0
  double eta = 0;  ///< fraction of critical damping of the normal dashpot [-], >= 0

  /// Throws hexdem::InputError "linear_contact: <field>: <problem> (got <value>)".
  void validate() const;

  /// c_n = 2 eta sqrt(m_eff k_n) [N s/m] for the pair's effective mass m_eff [kg].
  [[nodiscard]] double damping_coefficient(double m_eff) const noexcept {
    return 2.0 * eta * std::sqrt(m_eff * k_n);
  }

  /// Normal force [N] (<= 0) at overlap delta [m], overlap rate delta_dot [m/s] and dashpot
  /// coefficient c_n [N s/m].
  [[nodiscard]] double normal_force(double delta, double delta_dot, double c_n) const noexcept {
    const double f = -(k_n * delta + c_n * delta_dot);
    return delta > 0.0 ? std::fmin(f, 0.0) : 0.0;
  }

  /// Advances one contact by one step: the normal force from the current overlap and its
  /// rate, then the tangential force from the increment du_s [m] since the last update.
  /// Out of contact (delta <= 0) both forces are zero and the tangential spring is released.
  /// The friction dissipation is exact for this update's order (the cap changes first, then
  /// the tangential increment is applied under the new cap):
  ///   1. |f_s| above the new cap mu |f_n|: it drops to the cap, dissipating
  ///      (f_s^2 - cap^2) / (2 k_s) (the normal force fell, or the contact opened);
  ///   2. trial f_s + k_s du_s beyond the cap: it slides at the cap, dissipating
  ///      cap * slip with slip = |trial - f_s| / k_s.
  ContactStep update(ContactState& s, double delta, double delta_dot, double du_s,
                     double c_n) const noexcept {
    ContactStep step;
    const double f_v_old = s.f_v;
    s.f_n = normal_force(delta, delta_dot, c_n);
    const double f_spring = -k_n * std::fmax(delta, 0.0);
    s.f_v = s.f_n - f_spring;
    step.damping_power = -s.f_v * delta_dot;
    step.damping_power_mid = -0.5 * (f_v_old + s.f_v) * delta_dot;
    const double cap = -mu * s.f_n;
    const double f_held = std::fmax(-cap, std::fmin(s.f_s, cap));
    const double trial = f_held + k_s * du_s;
    const double f_new = std::fmax(-cap, std::fmin(trial, cap));
    step.friction_dissipation =
        (0.5 * (s.f_s * s.f_s - f_held * f_held) + cap * std::fabs(trial - f_new)) / k_s;
    step.friction_dissipation_mid = 0.5 * (s.f_s + f_new) * du_s - 0.5 * (f_new * f_new - s.f_s * s.f_s) / k_s;
    step.sliding = delta > 0.0 && std::fabs(trial) > cap;
    s.f_s = f_new;
    return step;
  }

  /// Energy stored in the springs [J] at overlap delta [m].
  [[nodiscard]] double stored_energy(const ContactState& s, double delta) const noexcept {
    const double d = std::fmax(delta, 0.0);
    return 0.5 * k_n * d * d + 0.5 * s.f_s * s.f_s / k_s;
  }

  /// Coefficient of restitution of a head-on collision under this law (dashpot force cut so
  /// that the total normal force never pulls). Contact ends when k_n delta + c_n delta_dot = 0;
  /// solving the damped oscillator up to that instant gives
  ///   e = exp(-2 eta g(eta)),  g = acos(eta) / sqrt(1 - eta^2)    eta < 1
  ///                            g = 1                              eta = 1
  ///                            g = acosh(eta) / sqrt(eta^2 - 1)   eta > 1
  /// (1 at eta = 0, 0.7441 at 0.1, 0.2984 at 0.5, exp(-2) at 1; the same result as
  /// T. Schwager, T. Poeschel, Granular Matter 9 (2007) 465). Independent of the masses and
  /// of the impact speed.
  [[nodiscard]] static double restitution(double eta) noexcept {
    double g = 1.0;
    if (eta < 1.0) {
      g = std::acos(eta) / std::sqrt((1.0 - eta) * (1.0 + eta));
    } else if (eta > 1.0) {
      g = std::acosh(eta) / std::sqrt((eta - 1.0) * (eta + 1.0));
    }
    return std::exp(-2.0 * eta * g);
  }
};

inline void LinearContact::validate() const {
  const auto fail = [](const char* field, const char* problem, double value) {
    char buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
    throw InputError(std::string(name) + ": " + field + ": " + problem + " (got " +
                     std::string(buffer, end) + ")");
  };
  // Written as !(ok) so that NaN fails too.
  if (!(k_n > 0.0) || !std::isfinite(k_n)) fail("k_n", "must be finite and > 0", k_n);
  if (!(k_s > 0.0) || !std::isfinite(k_s)) fail("k_s", "must be finite and > 0", k_s);
  if (!(mu >= 0.0) || !std::isfinite(mu)) fail("mu", "must be finite and >= 0", mu);
  if (!(eta >= 0.0) || !std::isfinite(eta)) fail("eta", "must be finite and >= 0", eta);
}

}  // namespace hexdem::laws
