// The energy balance of Eq. 25 as a run health check: the scale a run is judged on, and the
// warning and stop when the error passes `[time] energy_warning` / `energy_limit`.
#include "hexdem/solver/solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "hexdem/error.hpp"

#include "solver_text.hpp"

namespace hexdem::solver {

using detail::fmt;

/// Run health: the largest distance a disk may travel in one step where contacts act, in
/// radii (docs/model.md, "Contact").
constexpr double kMaxTravelPerStep = 0.5;

void Solver::setup_energy_scale() {
  // The elastic energy of the model at a uniform strain of 1e-9 [J]: far above round-off
  // (about 1e-16 of a run's energies), far below any loading worth simulating.
  constexpr double kStrain = 1e-9;
  std::vector<double> c11;
  for (const BodyMaterial& bm : body_materials_) c11.push_back(bm.material->stiffness(case_.geometry).c11);
  double e = 0;
  for (std::size_t i = 0; i < model_.num_disks(); ++i)
    e += 0.5 * c11[static_cast<std::size_t>(model_.body[i])] * kStrain * kStrain * model_.cell_area[i] * model_.disk_weight(i);
  energy_.scale = e;
}

bool Solver::check_energy(const StepSums& s, bool diagnostics) {
  const EnergyBalance& e = energy_;
  const double scale = std::max(std::abs(e.input()), e.scale);
  auto fail = [&](BlowUp::Kind kind, std::string reason) {
    blow_up_.kind = kind;
    blow_up_.step = step_;
    blow_up_.time = time_;
    blow_up_.reason = std::move(reason);
    return false;
  };
  // The leap-frog kinetic energy v(t-dt/2).v(t+dt/2) turns negative in an unstable mode
  // (the half-step velocities alternate in sign): judge growth on the mean of the squares,
  // and on the magnitude of the elastic energy (a lattice that has become indefinite makes
  // it negative). The velocities already reach t + dt/2: so does the input this is
  // compared with.
  const double elastic = diagnostics ? e.elastic : 0.0;
  const double mech = s.kinetic_sq + std::abs(elastic);
  const double limit = 10.0 * std::max(e.input() + std::max(s.ext_b, 0.0), e.scale);
  if (!std::isfinite(mech) || !std::isfinite(e.external_work))
    return fail(BlowUp::Kind::BlowUp, "the state is no longer finite");
  if (mech > limit) {
    return fail(BlowUp::Kind::BlowUp, "the kinetic and elastic energy (" + fmt(mech) + " J) exceed ten times the input (" +
                                          fmt(std::max(e.input(), e.scale)) + " J)");
  }
  if (!diagnostics) return true;
  if (contacts_on_ || !case_.walls.empty()) {
    // A contact stops an approaching disk over several steps: a disk that travels more than
    // half its radius in one step can cross a partner (a plate one disk thick) unseen, with
    // no force and no energy error to show for it.
    const Model& m = model_;
    const double dt = dt_info_.dt;
    double worst = 0;
    std::size_t at = 0;
    for (std::size_t i = 0; i < m.num_disks(); ++i) {
      const double travel = dt * std::sqrt(m.vx[i] * m.vx[i] + m.vy[i] * m.vy[i]) / m.radius[i];
      if (travel > worst) worst = travel, at = i;
    }
    if (worst > kMaxTravelPerStep) {
      const double v = std::sqrt(m.vx[at] * m.vx[at] + m.vy[at] * m.vy[at]);
      return fail(BlowUp::Kind::BlowUp,
                  "a disk at (" + fmt(m.x0[at] + m.ux[at]) + ", " + fmt(m.y0[at] + m.uy[at]) + ") m moves " +
                      fmt(v * dt) + " m per step at " + fmt(v) + " m/s, " + fmt(worst, 3) + " times its radius " +
                      fmt(m.radius[at]) + " m: contacts cannot stop it (at most " + fmt(kMaxTravelPerStep) +
                      " radius per step); lower [time] safety or give a smaller [time] dt");
    }
  }
  if (elastic < -case_.time.energy_limit * scale) {
    return fail(BlowUp::Kind::BlowUp, "the elastic energy is negative (" + fmt(elastic) + " J, input " +
                                          fmt(e.input()) + " J): the lattice has become unstable");
  }
  const double err = std::abs(e.relative_error());
  if (err > case_.time.energy_limit || (err > case_.time.energy_warning && energy_warning_.empty())) {
    // The ledger terms that moved since the last checked step, largest first.
    const std::array<std::pair<const char*, double>, 10> terms{{
        {"kinetic", e.kinetic - last_checked_.kinetic},
        {"elastic", e.elastic - last_checked_.elastic},
        {"external_work", e.external_work - last_checked_.external_work},
        {"damping", e.damping - last_checked_.damping},
        {"plastic", e.plastic - last_checked_.plastic},
        {"fracture", e.fracture - last_checked_.fracture},
        {"contact_damping", e.contact_damping - last_checked_.contact_damping},
        {"friction", e.friction - last_checked_.friction},
        {"break_kinetic", e.break_kinetic - last_checked_.break_kinetic},
        {"total", e.total() - last_checked_.total()},
    }};
    constexpr std::size_t kTotal = terms.size() - 1;  // the terms above it are ranked
    std::array<std::size_t, kTotal> order{};
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return std::abs(terms[a].second) > std::abs(terms[b].second); });
    std::string moved;
    for (std::size_t k = 0; k < 3; ++k)
      moved += std::string(k ? ", " : "") + terms[order[k]].first + " " + (terms[order[k]].second >= 0 ? "+" : "") +
               fmt(terms[order[k]].second) + " J";
    const std::string what = "energy error " + fmt(100 * err, 3) + " % of max(input " + fmt(e.input()) +
                             " J, scale " + fmt(e.scale) + " J) at t = " + fmt(time_, 6) + " s; since t = " +
                             fmt(last_checked_time_, 6) + " s: " + moved + ", total " +
                             (terms[kTotal].second >= 0 ? "+" : "") + fmt(terms[kTotal].second) + " J";
    if (err > case_.time.energy_limit)
      return fail(BlowUp::Kind::EnergyLimit, what + " (above [time] energy_limit = " + fmt(case_.time.energy_limit) + ")");
    energy_warning_ = what + " (above [time] energy_warning = " + fmt(case_.time.energy_warning) + ")";
  }
  max_energy_error_ = std::max(max_energy_error_, err);
  last_checked_ = e;
  last_checked_time_ = time_;
  return true;
}

}  // namespace hexdem::solver
