// Contacts between disks (broken bonds and bodies that meet: physics.md section 8, the
// sweep-and-prune broad phase of sweep_prune.hpp) and with rigid walls, their stiffness cap
// and their stored energy.
#include "hexdem/solver/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "hexdem/error.hpp"
#include "hexdem/laws/contact.hpp"

#include "solver_text.hpp"

namespace hexdem::solver {

using detail::fmt;

void Solver::setup_contact_resolution() {
  // Contacts (between bodies, fragments, broken bonds and walls) are one-sided springs:
  // central differences integrate the instant a spring engages or lets go with an error of
  // order (omega dt)^2 of the contact's energy, omega = sqrt(k / m_eff). At the lattice's own
  // step a contact as stiff as a bond has omega dt of 0.6-0.9, and a run with many contacts
  // (fragments) created several % of its input energy that way (docs/model.md, "Energy at
  // contacts"). A contact is therefore made no stiffer than omega = [contact] resolution /
  // dt_contact, 0.25 by default (about 12 steps per half period at the default step; O'Sullivan
  // and Bray, Eng. Comput. 21 (2004) 278, recommend a fraction of the critical step for
  // accuracy), which also keeps it inside the stability bound of the dashpot,
  // omega dt < 2 (sqrt(1 + eta^2) - eta).
  //
  // dt_contact is the default step (kDefaultSafety = 0.9 x the critical step, landing on the
  // end time: choose_time_step), not the step used: the contacts' stiffness is part of the
  // model, and a run at a smaller [time] dt or safety (a convergence study in the step) must
  // integrate the same contacts, not stiffer ones (docs/validation.md, "Convergence in the
  // time step").
  const double eta = case_.contact.damping;
  const double beta = std::min(case_.contact.resolution, 0.9 * (std::sqrt(1.0 + eta * eta) - eta));
  model_.contact_omega2 = (beta / dt_info_.dt_contact) * (beta / dt_info_.dt_contact);
  // [contact] cap_mass = "whole_cell": a disk whose cell the outline or the axis cuts is
  // lighter than its neighbours, so the cap made its contacts softer than theirs; on the axis
  // of the warhead case the nose's tip sank into the disc by up to 79 % of r_i + r_j
  // (docs/validation.md, "The contacts at the axis"). The cap is then reckoned with the mass
  // of the whole cell, at most Model::kMaxCapMassFactor = 4 times the disk's own: such a
  // contact's omega dt is at most 2 beta, inside the dashpot's stability bound.
  model_.whole_cell_cap = case_.contact.cap_mass == CapMass::WholeCell;
}

void Solver::setup_contacts() {
  wall_fn_.assign(case_.walls.size(), std::vector<double>(model_.num_disks(), 0.0));
  wall_fs_.assign(case_.walls.size(), std::vector<double>(model_.num_disks(), 0.0));
  wall_fv_.assign(case_.walls.size(), std::vector<double>(model_.num_disks(), 0.0));
  contacts_on_ = contacts_wanted();
  if (!contacts_on_) return;
  const Model& m = model_;
  const std::size_t n = m.num_disks();
  px_.resize(n);
  py_.resize(n);
  double r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    px_[i] = m.x0[i] + m.ux[i];
    py_[i] = m.y0[i] + m.uy[i];
    r_min = std::min(r_min, m.contact_r(i));
  }
  // Contact stiffness per unit thickness of each body: its springs along the lattice axis;
  // a pair uses the series (harmonic) combination of its two bodies.
  for (const BodyMaterial& bm : body_materials_) {
    body_kn_.push_back(bm.springs.kn1);
    body_kt_.push_back(bm.springs.ks1 > 0 ? bm.springs.ks1 : 0.5 * bm.springs.kn1);
    body_mu_.push_back(bm.material->friction);
  }
  sweep_.set_exclusion_pairs(m.bi.data(), m.bj.data(), m.num_bonds(), n);
  sweep_.build(px_.data(), py_.data(), m.contact_radii(), n, 0.2 * r_min);
  for (const auto& [i, j] : sweep_.pairs()) {
    const double d = std::hypot(px_[j] - px_[i], py_[j] - py_[i]);
    const double overlap = m.contact_r(i) + m.contact_r(j) - d;
    if (overlap > 1e-6 * r_min && m.body[i] == m.body[j] && !m.contact_radius.empty()) {
      // Unreachable on the generator's lattices (meshing::kMaxRadiusSpread); a lattice file's may.
      throw InputError(case_.source + ": [contact] radius_spread = " + fmt(case_.contact.radius_spread) +
                       ": unbonded disks at (" + fmt(px_[i]) + ", " + fmt(py_[i]) + ") and (" + fmt(px_[j]) + ", " +
                       fmt(py_[j]) + ") overlap at the start by " + fmt(overlap) + " m");
    }
    if (overlap > 1e-6 * r_min && m.body[i] != m.body[j]) {
      throw InputError(case_.source + ": bodies '" + lattice_.body_names[m.body[i]] + "' and '" +
                       lattice_.body_names[m.body[j]] + "' overlap at the start: disks at (" + fmt(px_[i]) + ", " +
                       fmt(py_[i]) + ") and (" + fmt(px_[j]) + ", " + fmt(py_[j]) + ") overlap by " + fmt(overlap) +
                       " m");
    }
    contacts_.push_back({i, j, 0.0, 0.0});
  }
}

void Solver::contact_forces(double dt) {
  Model& m = model_;
  const auto t0 = std::chrono::steady_clock::now();
  const bool changed = sweep_.update(px_.data(), py_.data(), m.contact_radii());
  detection_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (changed) {
    // Carry the forces of pairs that stay (both lists are sorted by (i, j)).
    contacts_next_.clear();
    std::size_t k = 0;
    for (const auto& [i, j] : sweep_.pairs()) {
      // Pairs that left the list are apart by more than the margin: their forces are zero.
      while (k < contacts_.size() && (contacts_[k].i < i || (contacts_[k].i == i && contacts_[k].j < j))) ++k;
      Contact c{i, j, 0.0, 0.0};
      if (k < contacts_.size() && contacts_[k].i == i && contacts_[k].j == j) c = contacts_[k];
      contacts_next_.push_back(c);
    }
    contacts_.swap(contacts_next_);
  }
  const bool axisym = case_.geometry == Geometry::Axisymmetric;
  for (Contact& c : contacts_) {
    const auto i = static_cast<std::size_t>(c.i), j = static_cast<std::size_t>(c.j);
    const double dx = px_[j] - px_[i], dy = py_[j] - py_[i];
    const double d = std::hypot(dx, dy);
    const double delta = m.contact_r(i) + m.contact_r(j) - d;
    // Apart, with nothing left to release (f_v: the dashpot's second half step).
    if (delta <= 0 && c.f_n == 0 && c.f_s == 0 && c.f_v == 0) continue;
    const double nx = dx / d, ny = dy / d, sx = -ny, sy = nx;
    const std::size_t bi = static_cast<std::size_t>(m.body[i]), bj = static_cast<std::size_t>(m.body[j]);
    // Width: the thickness, or (per radian) the mean ring radius of the two disks, as their
    // masses are weighted: a contact stays no stiffer, for its masses, than the bonds are.
    const double w = axisym ? 0.5 * (m.disk_weight(i) + m.disk_weight(j)) : case_.thickness;
    const double kn = w * body_kn_[bi] * body_kn_[bj] / (body_kn_[bi] + body_kn_[bj]);
    const double kt = w * body_kt_[bi] * body_kt_[bj] / (body_kt_[bi] + body_kt_[bj]);
    if (!(kn > 0) || !(kt > 0)) continue;  // a contact on the axis carries nothing per radian
    const double m_eff = m.mass[i] * m.mass[j] / (m.mass[i] + m.mass[j]);
    const double cap = m.contact_cap(i, j);
    const laws::LinearContact law{std::min(kn, cap), std::min(kt, cap), std::min(body_mu_[bi], body_mu_[bj]),
                                  case_.contact.damping};
    const double dvx = m.vx[j] - m.vx[i], dvy = m.vy[j] - m.vy[i];
    const double du_s = dt * (dvx * sx + dvy * sy - (m.contact_r(i) * m.omega[i] + m.contact_r(j) * m.omega[j]));
    laws::ContactState st{c.f_n, c.f_s, c.f_v};
    const laws::ContactStep step = law.update(st, delta, -(dvx * nx + dvy * ny), du_s, law.damping_coefficient(m_eff));
    c.f_n = st.f_n;
    c.f_s = st.f_s;
    c.f_v = st.f_v;
    contact_damping_work_ += step.damping_work(dt);
    contact_friction_work_ += step.friction_dissipation_mid;
    // Force on i: f_n n + f_s s (compression pushes i away from j); moments +r f_s on both.
    const double fx = c.f_n * nx + c.f_s * sx, fy = c.f_n * ny + c.f_s * sy;
    m.fx[i] += fx;
    m.fy[i] += fy;
    m.fx[j] -= fx;
    m.fy[j] -= fy;
    m.torque[i] += m.contact_r(i) * c.f_s;
    m.torque[j] += m.contact_r(j) * c.f_s;
  }
}

void Solver::wall_forces(double dt) {
  // Each disk against each rigid wall: the contact law with the disk's own springs along the
  // lattice axis (the wall is rigid), the disk's mass, and the wall's or the disk's friction.
  Model& m = model_;
  const bool axisym = case_.geometry == Geometry::Axisymmetric;
  for (std::size_t w = 0; w < case_.walls.size(); ++w) {
    const Wall& wall = case_.walls[w];
    const double nx = wall.normal[0], ny = wall.normal[1];
    // From the disk towards the wall: e = -n; tangent s = (-e_y, e_x).
    const double ex = -nx, ey = -ny, sx = -ey, sy = ex;
    for (std::size_t i = 0; i < m.num_disks(); ++i) {
      const double x = m.x0[i] + m.ux[i], y = m.y0[i] + m.uy[i];
      const double delta = m.contact_r(i) - ((x - wall.point[0]) * nx + (y - wall.point[1]) * ny);
      double& fn = wall_fn_[w][i];
      double& fs = wall_fs_[w][i];
      double& fv = wall_fv_[w][i];
      if (delta <= 0 && fn == 0 && fs == 0 && fv == 0) continue;
      const auto b = static_cast<std::size_t>(m.body[i]);
      const double width = axisym ? m.disk_weight(i) : case_.thickness;
      const double cap = m.wall_contact_cap(i);
      const double mu = wall.friction.value_or(body_materials_[b].material->friction);
      const SpringConstants& K = body_materials_[b].springs;
      const double kn = std::min(K.kn1 * width, cap);
      const double kt = std::min((K.ks1 > 0 ? K.ks1 : 0.5 * K.kn1) * width, cap);
      const laws::LinearContact law{kn, kt, mu, case_.contact.damping};
      const double du_s = dt * (-(m.vx[i] * sx + m.vy[i] * sy) - m.contact_r(i) * m.omega[i]);
      laws::ContactState st{fn, fs, fv};
      const laws::ContactStep step =
          law.update(st, delta, m.vx[i] * ex + m.vy[i] * ey, du_s, law.damping_coefficient(m.mass[i]));
      fn = st.f_n;
      fs = st.f_s;
      fv = st.f_v;
      contact_damping_work_ += step.damping_work(dt);
      contact_friction_work_ += step.friction_dissipation_mid;
      m.fx[i] += fn * ex + fs * sx;
      m.fy[i] += fn * ey + fs * sy;
      m.torque[i] += m.contact_r(i) * fs;
    }
  }
}

double Solver::contact_energy() const {
  double e = 0;
  for (std::size_t w = 0; w < case_.walls.size(); ++w) {
    for (std::size_t i = 0; i < model_.num_disks(); ++i) {
      const double fn = wall_fn_[w][i], fs = wall_fs_[w][i];
      // A contact whose force the cut holds at zero still has its spring compressed.
      if (fn == 0 && fs == 0 && wall_fv_[w][i] == 0) continue;
      const auto b = static_cast<std::size_t>(model_.body[i]);
      const double width = case_.geometry == Geometry::Axisymmetric ? model_.disk_weight(i) : case_.thickness;
      const double cap = model_.wall_contact_cap(i);
      const SpringConstants& K = body_materials_[b].springs;
      const Wall& wall = case_.walls[w];
      const double x = model_.x0[i] + model_.ux[i], y = model_.y0[i] + model_.uy[i];
      const double delta = std::max(
          model_.contact_r(i) - ((x - wall.point[0]) * wall.normal[0] + (y - wall.point[1]) * wall.normal[1]), 0.0);
      // The springs' energy: k_n delta^2 / 2 (f_n also holds the dashpot's force).
      e += 0.5 * std::min(K.kn1 * width, cap) * delta * delta +
           0.5 * fs * fs / std::min((K.ks1 > 0 ? K.ks1 : 0.5 * K.kn1) * width, cap);
    }
  }
  for (const Contact& c : contacts_) {
    if (c.f_n == 0 && c.f_s == 0 && c.f_v == 0) continue;
    const auto i = static_cast<std::size_t>(c.i), j = static_cast<std::size_t>(c.j);
    const std::size_t bi = static_cast<std::size_t>(model_.body[i]), bj = static_cast<std::size_t>(model_.body[j]);
    const double w = case_.geometry == Geometry::Axisymmetric ? 0.5 * (model_.disk_weight(i) + model_.disk_weight(j))
                                                              : case_.thickness;
    const double kn = w * body_kn_[bi] * body_kn_[bj] / (body_kn_[bi] + body_kn_[bj]);
    const double kt = w * body_kt_[bi] * body_kt_[bj] / (body_kt_[bi] + body_kt_[bj]);
    const double cap = model_.contact_cap(i, j);
    const double delta =
        std::max(model_.contact_r(i) + model_.contact_r(j) - std::hypot(px_[j] - px_[i], py_[j] - py_[i]), 0.0);
    if (kn > 0) e += 0.5 * std::min(kn, cap) * delta * delta;
    if (kt > 0) e += 0.5 * c.f_s * c.f_s / std::min(kt, cap);
  }
  return e;
}

}  // namespace hexdem::solver
