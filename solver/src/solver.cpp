// The explicit time loop: leap-frog central differences with mass damping (Eq. 18), loads
// (Eqs. 21, 23), boundary conditions, time step (physics.md section 5) and the energy balance
// (Eq. 25).
#include "hexdem/solver/solver.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>

#include <Eigen/Dense>

#include "hexdem/error.hpp"
#include "hexdem/laws/contact.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/solver/boundary_checks.hpp"
#include "hexdem/solver/checkpoint.hpp"
#include "hexdem/solver/random_field.hpp"

namespace hexdem::solver {
namespace {

constexpr double kSqrt3 = 1.7320508075688772935;

std::string fmt(double v, int precision = 4) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

/// Whether a condition on a boundary set acts on the disk of set entry e: only disks whose
/// centre lies closer than their radius to the edge are held (on a symmetry plane that runs
/// across the lattice rows, the disks one radius off it must stay free).
bool held_by_set(const meshing::Lattice& lattice, std::int64_t e, double radius) {
  return lattice.set_distance[static_cast<std::size_t>(e)] < (1 - 1e-6) * radius;
}

/// The velocity components (kFixX, kFixY) a boundary condition holds on its disks.
std::uint8_t held_components(const BoundaryCondition& bc) {
  switch (bc.kind) {
    case BoundaryCondition::Kind::Fixed:
      return kFixX | kFixY;
    case BoundaryCondition::Kind::Roller:
    case BoundaryCondition::Kind::Symmetry:
      return bc.component == 0 ? kFixX : kFixY;
    case BoundaryCondition::Kind::Velocity:
      return static_cast<std::uint8_t>((bc.velocity[0] ? kFixX : 0) | (bc.velocity[1] ? kFixY : 0));
  }
  return 0;
}

}  // namespace

meshing::Lattice mesh_case(const Case& c, meshing::GeneratorReport* report) {
  meshing::GeneratorOptions go;
  go.mode = c.geometry == Geometry::Axisymmetric ? meshing::GeometryMode::Axisymmetric
                                                 : meshing::GeometryMode::Plane;
  go.max_disks = c.max_disks;
  go.max_disks_hint = "[mesh] max_disks = N or --max-disks N";
  return meshing::generate_lattice(c.outline, go, report);
}

Solver::Solver(const Case& c, meshing::Lattice lattice) : case_(c), lattice_(std::move(lattice)) {
  auto clock = std::chrono::steady_clock::now();
  const auto lap = [&clock](double& slot) {
    const auto now = std::chrono::steady_clock::now();
    slot = std::chrono::duration<double>(now - clock).count();
    clock = now;
  };
  check_symmetry_planes(case_, lattice_);
  setup_materials();
  model_ = build_model(lattice_, case_.geometry, case_.thickness, case_.shear_model, body_materials_);
  model_.contact_damping = case_.contact.damping;
  // From here on the model holds the disks and bonds: keep the lattice's names and sets only.
  lattice_hash_ = hexdem::solver::lattice_hash(lattice_);
  for (auto* v : {&lattice_.x, &lattice_.y, &lattice_.radius, &lattice_.cell_area, &lattice_.cell_cx, &lattice_.cell_cy,
                  &lattice_.bond_b})
    std::vector<double>().swap(*v);
  for (auto* v : {&lattice_.body, &lattice_.material, &lattice_.bond_i, &lattice_.bond_j}) std::vector<std::int32_t>().swap(*v);
  for (auto* v : {&lattice_.kind, &lattice_.bond_class, &lattice_.bond_on_edge}) std::vector<std::uint8_t>().swap(*v);
  lap(setup_times_.model);
  if (case_.random && model_.any_breakable) {
    // [random]: the strength field at the bond midpoints and, for hoop cracking, the disks.
    const RandomField& r = *case_.random;
    std::vector<double> mx(model_.num_bonds()), my(model_.num_bonds());
    for (std::size_t b = 0; b < model_.num_bonds(); ++b) {
      mx[b] = model_.x0[model_.bi[b]] + 0.5 * model_.ax[b];
      my[b] = model_.y0[model_.bi[b]] + 0.5 * model_.ay[b];
    }
    model_.strength_scale = lognormal_field(mx, my, r.seed, r.correlation_length, r.strength_cov);
    if (!model_.hoop_damage.empty())
      model_.disk_strength_scale = lognormal_field(model_.x0, model_.y0, r.seed, r.correlation_length, r.strength_cov);
  }
  lap(setup_times_.random_field);
  setup_boundaries();
  setup_loads();
  setup_reactions();
  lap(setup_times_.sets);
  setup_contacts();
  lap(setup_times_.contacts);
  choose_time_step();  // on the model at rest: the estimate saves no state
  lap(setup_times_.time_step);
  setup_initial_velocities();
  setup_contact_resolution();
  setup_energy_scale();
  lap(setup_times_.energy_scale);
}

void Solver::setup_contact_resolution() {
  // Contacts (between bodies, fragments, broken bonds and walls) are one-sided springs:
  // central differences integrate the instant a spring engages or lets go with an error of
  // order (omega dt)^2 of the contact's energy, omega = sqrt(k / m_eff). At the lattice's own
  // step a contact as stiff as a bond has omega dt of 0.6-0.9, and a run with many contacts
  // (fragments) created several % of its input energy that way (docs/model.md, "Energy at
  // contacts"). A contact is therefore made no stiffer than its masses and the step resolve
  // with omega dt <= [contact] resolution, 0.25 by default (about 12 steps per half period; O'Sullivan and Bray, Eng. Comput.
  // 21 (2004) 278, recommend a fraction of the critical step for accuracy), which also
  // keeps it inside the stability bound of the dashpot, omega dt < 2 (sqrt(1 + eta^2) - eta).
  const double eta = case_.contact.damping;
  const double beta = std::min(case_.contact.resolution, 0.9 * (std::sqrt(1.0 + eta * eta) - eta));
  model_.contact_omega2 = (beta / dt_info_.dt) * (beta / dt_info_.dt);
}

void Solver::setup_energy_scale() {
  // The elastic energy of the model at a uniform strain of 1e-9 [J]: far above round-off
  // (about 1e-16 of a run's energies), far below any loading worth simulating.
  constexpr double kStrain = 1e-9;
  std::vector<double> c11;
  for (const BodyMaterial& bm : body_materials_) c11.push_back(bm.material->stiffness(case_.geometry).c11);
  double e = 0;
  for (std::size_t i = 0; i < model_.num_disks(); ++i)
    e += 0.5 * c11[static_cast<std::size_t>(model_.body[i])] * kStrain * kStrain * model_.cell_area[i] * model_.weight[i];
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

void Solver::setup_contacts() {
  wall_fn_.assign(case_.walls.size(), std::vector<double>(model_.num_disks(), 0.0));
  wall_fs_.assign(case_.walls.size(), std::vector<double>(model_.num_disks(), 0.0));
  wall_fv_.assign(case_.walls.size(), std::vector<double>(model_.num_disks(), 0.0));
  // Never-bonded disks can only meet when there are several bodies or bonds can break.
  contacts_on_ = case_.outline.bodies.size() > 1 || model_.any_breakable;
  if (!contacts_on_) return;
  const Model& m = model_;
  const std::size_t n = m.num_disks();
  px_.resize(n);
  py_.resize(n);
  double r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    px_[i] = m.x0[i] + m.ux[i];
    py_[i] = m.y0[i] + m.uy[i];
    r_min = std::min(r_min, m.radius[i]);
  }
  // Contact stiffness per unit thickness of each body: its springs along the lattice axis;
  // a pair uses the series (harmonic) combination of its two bodies.
  for (const BodyMaterial& bm : body_materials_) {
    body_kn_.push_back(bm.springs.kn1);
    body_kt_.push_back(bm.springs.ks1 > 0 ? bm.springs.ks1 : 0.5 * bm.springs.kn1);
    body_mu_.push_back(bm.material->friction);
  }
  sweep_.set_exclusion_pairs(m.bi.data(), m.bj.data(), m.num_bonds(), n);
  sweep_.build(px_.data(), py_.data(), m.radius.data(), n, 0.2 * r_min);
  for (const auto& [i, j] : sweep_.pairs()) {
    const double d = std::hypot(px_[j] - px_[i], py_[j] - py_[i]);
    const double overlap = m.radius[i] + m.radius[j] - d;
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
  const bool changed = sweep_.update(px_.data(), py_.data(), m.radius.data());
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
    const double delta = m.radius[i] + m.radius[j] - d;
    // Apart, with nothing left to release (f_v: the dashpot's second half step).
    if (delta <= 0 && c.f_n == 0 && c.f_s == 0 && c.f_v == 0) continue;
    const double nx = dx / d, ny = dy / d, sx = -ny, sy = nx;
    const std::size_t bi = static_cast<std::size_t>(m.body[i]), bj = static_cast<std::size_t>(m.body[j]);
    // Width: the thickness, or (per radian) the mean ring radius of the two disks, as their
    // masses are weighted: a contact stays no stiffer, for its masses, than the bonds are.
    const double w = axisym ? 0.5 * (m.weight[i] + m.weight[j]) : case_.thickness;
    const double kn = w * body_kn_[bi] * body_kn_[bj] / (body_kn_[bi] + body_kn_[bj]);
    const double kt = w * body_kt_[bi] * body_kt_[bj] / (body_kt_[bi] + body_kt_[bj]);
    if (!(kn > 0) || !(kt > 0)) continue;  // a contact on the axis carries nothing per radian
    const double m_eff = m.mass[i] * m.mass[j] / (m.mass[i] + m.mass[j]);
    const double cap = contact_stiffness_cap(m_eff);
    const laws::LinearContact law{std::min(kn, cap), std::min(kt, cap), std::min(body_mu_[bi], body_mu_[bj]),
                                  case_.contact.damping};
    const double dvx = m.vx[j] - m.vx[i], dvy = m.vy[j] - m.vy[i];
    const double du_s = dt * (dvx * sx + dvy * sy - (m.radius[i] * m.omega[i] + m.radius[j] * m.omega[j]));
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
    m.torque[i] += m.radius[i] * c.f_s;
    m.torque[j] += m.radius[j] * c.f_s;
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
      const double delta = m.radius[i] - ((x - wall.point[0]) * nx + (y - wall.point[1]) * ny);
      double& fn = wall_fn_[w][i];
      double& fs = wall_fs_[w][i];
      double& fv = wall_fv_[w][i];
      if (delta <= 0 && fn == 0 && fs == 0 && fv == 0) continue;
      const auto b = static_cast<std::size_t>(m.body[i]);
      const double width = axisym ? m.weight[i] : case_.thickness;
      const double cap = contact_stiffness_cap(m.mass[i]);
      const double mu = wall.friction.value_or(body_materials_[b].material->friction);
      const SpringConstants& K = body_materials_[b].springs;
      const double kn = std::min(K.kn1 * width, cap);
      const double kt = std::min((K.ks1 > 0 ? K.ks1 : 0.5 * K.kn1) * width, cap);
      const laws::LinearContact law{kn, kt, mu, case_.contact.damping};
      const double du_s = dt * (-(m.vx[i] * sx + m.vy[i] * sy) - m.radius[i] * m.omega[i]);
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
      m.torque[i] += m.radius[i] * fs;
    }
  }
}

double Solver::contact_stiffness_cap(double m_eff) const { return m_eff * model_.contact_omega2; }

double Solver::contact_energy() const {
  double e = 0;
  for (std::size_t w = 0; w < case_.walls.size(); ++w) {
    for (std::size_t i = 0; i < model_.num_disks(); ++i) {
      const double fn = wall_fn_[w][i], fs = wall_fs_[w][i];
      // A contact whose force the cut holds at zero still has its spring compressed.
      if (fn == 0 && fs == 0 && wall_fv_[w][i] == 0) continue;
      const auto b = static_cast<std::size_t>(model_.body[i]);
      const double width = case_.geometry == Geometry::Axisymmetric ? model_.weight[i] : case_.thickness;
      const double cap = contact_stiffness_cap(model_.mass[i]);
      const SpringConstants& K = body_materials_[b].springs;
      const Wall& wall = case_.walls[w];
      const double x = model_.x0[i] + model_.ux[i], y = model_.y0[i] + model_.uy[i];
      const double delta = std::max(
          model_.radius[i] - ((x - wall.point[0]) * wall.normal[0] + (y - wall.point[1]) * wall.normal[1]), 0.0);
      // The springs' energy: k_n delta^2 / 2 (f_n also holds the dashpot's force).
      e += 0.5 * std::min(K.kn1 * width, cap) * delta * delta +
           0.5 * fs * fs / std::min((K.ks1 > 0 ? K.ks1 : 0.5 * K.kn1) * width, cap);
    }
  }
  for (const Contact& c : contacts_) {
    if (c.f_n == 0 && c.f_s == 0 && c.f_v == 0) continue;
    const auto i = static_cast<std::size_t>(c.i), j = static_cast<std::size_t>(c.j);
    const std::size_t bi = static_cast<std::size_t>(model_.body[i]), bj = static_cast<std::size_t>(model_.body[j]);
    const double w = case_.geometry == Geometry::Axisymmetric ? 0.5 * (model_.weight[i] + model_.weight[j])
                                                              : case_.thickness;
    const double kn = w * body_kn_[bi] * body_kn_[bj] / (body_kn_[bi] + body_kn_[bj]);
    const double kt = w * body_kt_[bi] * body_kt_[bj] / (body_kt_[bi] + body_kt_[bj]);
    const double cap = contact_stiffness_cap(model_.mass[i] * model_.mass[j] / (model_.mass[i] + model_.mass[j]));
    const double delta =
        std::max(model_.radius[i] + model_.radius[j] - std::hypot(px_[j] - px_[i], py_[j] - py_[i]), 0.0);
    if (kn > 0) e += 0.5 * std::min(kn, cap) * delta * delta;
    if (kt > 0) e += 0.5 * c.f_s * c.f_s / std::min(kt, cap);
  }
  return e;
}

void Solver::refuse_unless_allowed(const std::string& message, const std::string& remedy) {
  if (!case_.time.allow_unstable) throw InputError(message + "; remedy: " + remedy);
  warnings_.push_back(message + "; running anyway ([time] allow_unstable = true)");
}

void Solver::setup_materials() {
  for (const meshing::BodyOutline& body : case_.outline.bodies) {
    const Material* mat = case_.find_material(body.material);
    if (mat == nullptr) {
      throw InputError(case_.source + ": body '" + body.name + "' uses material " +
                       std::to_string(body.material) + ", which no [[material]] defines");
    }
    BodyMaterial bm;
    bm.material = mat;
    const Stiffness2D c = mat->stiffness(case_.geometry);
    bm.springs = spring_constants(c);
    body_materials_.push_back(bm);

    if (mat->plastic()) {
      // Per-spring plasticity (Eq. 16) needs positive shear springs: with k_s <= 0 the lattice
      // is positive definite only through its elastic normal springs, and once those yield to
      // a small tangent modulus it is not (measured: the warhead's steel blew up on impact).
      // Disk-level J2 keeps every spring elastic on the elastic deformation instead.
      const bool positive = bm.springs.ks1 > 0 && bm.springs.ks2 > 0;
      PlasticityModel model = mat->plasticity;
      if (model == PlasticityModel::Auto)
        model = positive || case_.geometry == Geometry::PlaneStress ? PlasticityModel::Spring : PlasticityModel::J2;
      const std::string what = case_.source + ": material '" + mat->name + "' (id " + std::to_string(mat->id) + ")";
      if (model == PlasticityModel::Spring && !positive) {
        throw InputError(what + ": plasticity = \"" + plasticity_model_name(mat->plasticity) +
                         "\": per-spring plasticity needs positive shear springs, i.e. nu < 1/4 in plane strain and "
                         "axisymmetry or nu < 1/3 in plane stress (nu = " + fmt(mat->nu) +
                         ", k_s = " + fmt(std::min(bm.springs.ks1, bm.springs.ks2)) + " N/m per m); remedy: " +
                         (case_.geometry == Geometry::PlaneStress
                              ? std::string("drop yield_stress (elastic) for this material")
                              : std::string("plasticity = \"j2\" (or \"auto\"), or drop yield_stress")));
      }
      if (model == PlasticityModel::J2 && case_.geometry == Geometry::PlaneStress)
        throw InputError(what + ": plasticity = \"j2\" is available in plane strain and axisymmetry only");
      if (model == PlasticityModel::J2 && case_.shear_model != ShearModel::LocalStrain)
        throw InputError(what + ": plasticity = \"j2\" needs [case] shear_model = \"local-strain\"");
      bm.j2 = model == PlasticityModel::J2;
      body_materials_.back().j2 = bm.j2;
      std::string line =
          "material '" + mat->name + "' (id " + std::to_string(mat->id) + "): plasticity " +
          (bm.j2 ? "j2 (von Mises per disk, linear kinematic hardening" : "spring (bilinear springs, Eq. 16") +
          (mat->plasticity == PlasticityModel::Auto ? std::string(", chosen by auto: k_s ") +
                                                          (positive ? "> 0)" : "<= 0)")
                                                    : std::string(")")) +
          ", sigma_y " + fmt(mat->yield_stress / 1e6) + " MPa, E_t " + fmt(mat->tangent_modulus / 1e9) + " GPa";
      if (std::find(plasticity_report_.begin(), plasticity_report_.end(), line) == plasticity_report_.end())
        plasticity_report_.push_back(std::move(line));
    }
    // Breakable bonds need shear springs that are not negative: with k_s < 0 the local-strain
    // lattice is positive definite only as a whole, and a break takes a negative shear energy
    // out of it together with the neighbours' strain fit, which feeds energy into the body
    // (measured: the warhead case with nu = 0.3 concrete books -25 % of the input as fracture
    // energy and breaks 90 % of its bonds, against 0.6 % and 12 % with nu = 0.2).
    // (The tolerance lets nu = 1/4 exactly, k_s = 0 up to round-off, through.)
    // The same holds for softening materials (fracture_energy): a softening normal spring
    // leaves its neighbours' negative shear springs without the normal stiffness that made
    // the lattice positive definite (measured: a bar of nu = 0.3 in plane strain blew up within
    // 300 steps of its first cracks at lattice angles of 10 and 30 degrees; docs/model.md).
    if (mat->breakable && std::min(bm.springs.ks1, bm.springs.ks2) < -1e-12 * std::max(bm.springs.kn1, bm.springs.kn2)) {
      const std::string message =
          case_.source + ": material '" + mat->name + "' (id " + std::to_string(mat->id) +
          "): breakable bonds need shear springs that are not negative, i.e. nu <= 1/4 in plane strain and "
          "axisymmetry or nu <= 1/3 in plane stress (nu = " + fmt(mat->nu) + ", k_s = " +
          fmt(std::min(bm.springs.ks1, bm.springs.ks2)) + " N/m per m): breaking such bonds releases negative energy";
      refuse_unless_allowed(message, "drop the strengths of this material, or set [time] allow_unstable = true to run anyway");
    }
    // Stability of the chosen shear model for this material (physics.md section 4).
    const double r = body.radius.value_or(0.0);
    const BlochResult br = bloch_analysis(bm.springs, mat->density, r, case_.shear_model);
    bloch_.push_back(br);
    if (!br.stable) {
      std::string why = "the Bloch analysis of the lattice finds omega^2 = " + fmt(br.omega2_min) +
                        " 1/s^2 < 0 (growth e-folding time " + fmt(br.growth_time * 1e6, 3) + " us)";
      if (case_.shear_model == ShearModel::Rotation && c.c66 < c.c12) {
        why += "; the necessary condition k_s1 + 2 k_s2 = 2 sqrt(3) (c66 - c12) >= 0 fails (c66 = " +
               fmt(c.c66 / 1e9) + " GPa < c12 = " + fmt(c.c12 / 1e9) + " GPa)";
      }
      const std::string message =
          case_.source + ": [case] shear_model = \"" + shear_model_name(case_.shear_model) +
          "\" is unstable for material '" + mat->name + "' (id " + std::to_string(mat->id) + ", " +
          geometry_name(case_.geometry) + "): " + why;
      // allow_unstable: a study of the instability itself (the paper's own model).
      refuse_unless_allowed(message, "use shear_model = \"local-strain\"");
    }
  }
}

void Solver::setup_boundaries() {
  const std::size_t n = model_.num_disks();
  std::vector<std::int32_t> owner(n, -1);  // the velocity set that prescribes each disk
  for (const BoundaryCondition& bc : case_.boundaries) {
    const int s = lattice_.find_set(bc.set);
    if (s < 0) throw InputError(bc.where + ": unknown boundary set '" + bc.set + "'");
    VelocitySet vs{&bc, {}};
    std::size_t held = 0;
    double nearest = std::numeric_limits<double>::infinity(), r_nearest = 0;
    for (auto e = lattice_.set_offset[s]; e < lattice_.set_offset[s + 1]; ++e) {
      const auto i = static_cast<std::size_t>(lattice_.set_disk[e]);
      if (lattice_.set_distance[e] < nearest) {
        nearest = lattice_.set_distance[e];
        r_nearest = model_.radius[i];
      }
      if (!held_by_set(lattice_, e, model_.radius[i])) continue;
      ++held;
      std::uint8_t& bits = model_.constraint[i];
      bits |= held_components(bc);
      switch (bc.kind) {
        case BoundaryCondition::Kind::Fixed:
          if (bc.fix_rotation) bits |= kFixRotation;
          break;
        case BoundaryCondition::Kind::Roller:
          break;
        case BoundaryCondition::Kind::Symmetry:
          bits |= kFixRotation;
          if (lattice_.set_distance[e] < 1e-3 * model_.radius[i]) model_.mirror_plane[i] = 1;
          break;
        case BoundaryCondition::Kind::Velocity:
          vs.disks.push_back(static_cast<std::int32_t>(i));
          owner[i] = static_cast<std::int32_t>(velocity_sets_.size());
          break;
      }
    }
    if (held == 0) {
      // A condition that holds nothing would let the run go on as if it did (docs/case-format.md).
      throw InputError(bc.where + ": boundary set '" + bc.set + "' selects no disk: " +
                       (std::isfinite(nearest) ? "the nearest disk centre lies " + fmt(nearest) +
                                                     " m from the edge, and a condition acts on disks whose centre "
                                                     "lies within their radius (" + fmt(r_nearest) + " m) of it"
                                               : std::string("the set has no disks")) +
                       "; move the edge onto a lattice row ([mesh] origin) or change the radius");
    }
    if (bc.kind == BoundaryCondition::Kind::Velocity) velocity_sets_.push_back(std::move(vs));
    if (bc.kind == BoundaryCondition::Kind::Symmetry) setup_mirror_springs(bc, s);
  }
  // A disk in several velocity sets takes the last one.
  for (std::size_t s = 0; s < velocity_sets_.size(); ++s) {
    auto& d = velocity_sets_[s].disks;
    d.erase(std::remove_if(d.begin(), d.end(), [&](std::int32_t i) { return owner[i] != static_cast<std::int32_t>(s); }),
            d.end());
  }
}

void Solver::setup_mirror_springs(const BoundaryCondition& bc, int s) {
  // A mirror plane x = const (component 0) or y = const (component 1). A disk one radius off
  // the plane, whose lattice has a bond direction along the plane's normal, is bonded to its
  // own mirror image in the full model: that bond stretches by twice the disk's normal
  // displacement, so in the half model it is a spring to the plane of stiffness 2 k_n.
  const int c = bc.component;
  for (auto e = lattice_.set_offset[s]; e < lattice_.set_offset[s + 1]; ++e) {
    const auto i = static_cast<std::size_t>(lattice_.set_disk[e]);
    const double normal = c == 0 ? lattice_.set_nx[e] : lattice_.set_ny[e];
    if (std::abs(std::abs(normal) - 1.0) > 1e-6) {
      throw InputError(bc.where + ": symmetry set '" + bc.set + "' must be a straight line " +
                       (c == 0 ? "x" : "y") + " = const (a member's normal is (" + fmt(lattice_.set_nx[e]) + ", " +
                       fmt(lattice_.set_ny[e]) + "))");
    }
    const double r = model_.radius[i];
    if (std::abs(lattice_.set_distance[e] - r) > 1e-6 * r) continue;
    const meshing::BodyOutline& body = case_.outline.bodies[static_cast<std::size_t>(model_.body[i])];
    const double normal_deg = c == 0 ? 0.0 : 90.0;
    double rel = std::fmod(normal_deg - body.angle_deg.value_or(0.0), 180.0);
    if (rel < 0) rel += 180.0;
    const bool class1 = rel < 1e-6 || rel > 180.0 - 1e-6;
    const bool class2 = std::abs(rel - 60.0) < 1e-6 || std::abs(rel - 120.0) < 1e-6;
    if (!class1 && !class2) continue;
    const SpringConstants& K = body_materials_[static_cast<std::size_t>(model_.body[i])].springs;
    double w = case_.thickness;
    if (case_.geometry == Geometry::Axisymmetric) w = c == 0 ? model_.x0[i] + normal * lattice_.set_distance[e] : model_.x0[i];
    const double k = 2.0 * (class1 ? K.kn1 : K.kn2) * w;
    if (!model_.has_mirror_springs())  // allocated for the cases that have mirror springs
      for (auto* v : {&model_.wall_kx, &model_.wall_ky, &model_.wall_sx, &model_.wall_sy}) v->assign(model_.num_disks(), 0.0);
    (c == 0 ? model_.wall_kx : model_.wall_ky)[i] = k;
    (c == 0 ? model_.wall_sx : model_.wall_sy)[i] = normal > 0 ? 1.0 : -1.0;
  }
}

void Solver::setup_loads() {
  std::vector<std::uint8_t> loaded(model_.num_disks(), 0);
  for (const Load& load : case_.loads) {
    LoadSet ls{&load, {}, {}, {}, {}, {}};
    if (load.kind == Load::Kind::Pressure) {
      const int s = lattice_.find_set(load.set);
      if (s < 0) throw InputError(load.where + ": unknown boundary set '" + load.set + "'");
      for (auto e = lattice_.set_offset[s]; e < lattice_.set_offset[s + 1]; ++e) {
        const auto i = static_cast<std::size_t>(lattice_.set_disk[e]);
        if (load.window) {
          const double coord = load.window->axis == 0 ? model_.x0[i] : model_.y0[i];
          if (coord < load.window->min || coord > load.window->max) continue;
        }
        // Pressure (compression positive) on the disk's share of the named edges:
        // F = -p L w n_out, w = thickness or the faces' radius (per radian).
        const double w = case_.geometry == Geometry::Axisymmetric ? lattice_.set_cx[e] : case_.thickness;
        const double lw = lattice_.set_length[e] * w;
        ls.disks.push_back(static_cast<std::int32_t>(i));
        ls.cx.push_back(-load.p0 * lw * lattice_.set_nx[e]);
        ls.cy.push_back(-load.p0 * lw * lattice_.set_ny[e]);
        ls.lx.push_back(lattice_.set_cx[e] - model_.x0[i]);
        ls.ly.push_back(lattice_.set_cy[e] - model_.y0[i]);
      }
      p_max_ = std::max(p_max_, std::abs(load.p0) * load.function.max_abs(case_.time.end));
    } else {
      for (std::size_t i = 0; i < model_.num_disks(); ++i) {
        const std::string& name = lattice_.body_names[model_.body[i]];
        if (!load.bodies.empty() && std::find(load.bodies.begin(), load.bodies.end(), name) == load.bodies.end()) continue;
        ls.disks.push_back(static_cast<std::int32_t>(i));
        ls.cx.push_back(model_.mass[i] * load.acceleration[0]);
        ls.cy.push_back(model_.mass[i] * load.acceleration[1]);
        ls.lx.push_back(0.0);
        ls.ly.push_back(0.0);
      }
    }
    if (ls.disks.empty()) {
      throw InputError(load.where + ": the load selects no disk (" +
                       (load.kind == Load::Kind::Pressure
                            ? "boundary set '" + load.set + "'" + (load.window ? " within its window" : std::string())
                            : std::string("none of the bodies it names has disks")) +
                       ")");
    }
    for (std::int32_t i : ls.disks) loaded[i] = 1;
    loads_.push_back(std::move(ls));
  }
  for (std::size_t i = 0; i < loaded.size(); ++i)
    if (loaded[i]) loaded_disks_.push_back(static_cast<std::int32_t>(i));
  // The loads' lever arms (disk_stress), for the cases that have loads.
  if (!loaded_disks_.empty())
    for (auto* v : {&model_.ext_mxx, &model_.ext_myy, &model_.ext_mxy}) v->assign(model_.num_disks(), 0.0);
}

void Solver::setup_reactions() {
  for (const std::string& name : case_.output.reactions) {
    const std::string what = case_.source + ": output.reactions: boundary set '" + name + "'";
    // Names were checked against the outline by the reader; a set without disks has no row.
    const int s = lattice_.find_set(name);
    if (s < 0) throw InputError(what + " selects no disk (the set has no disks)");
    const std::int64_t first = lattice_.set_offset[s], end = lattice_.set_offset[s + 1];
    ReactionSet rs;
    std::vector<std::uint8_t> held(static_cast<std::size_t>(end - first), 0);
    std::vector<std::uint8_t> spring(held.size(), 0);
    bool conditioned = false;
    for (const BoundaryCondition& bc : case_.boundaries) {
      if (bc.set != name) continue;
      conditioned = true;  // setup_boundaries refused a condition that holds no disk
      const std::uint8_t bits = held_components(bc);
      for (auto e = first; e < end; ++e) {
        const auto i = static_cast<std::size_t>(lattice_.set_disk[e]);
        if (held_by_set(lattice_, e, model_.radius[i])) held[static_cast<std::size_t>(e - first)] |= bits;
        // A mirror plane's springs to the disks one radius off it (setup_mirror_springs)
        // are part of the condition: their force -k u is the plane's on the body.
        const double k = !model_.has_mirror_springs() ? 0.0 : bc.component == 0 ? model_.wall_kx[i] : model_.wall_ky[i];
        if (bc.kind == BoundaryCondition::Kind::Symmetry && k != 0 &&
            std::abs(lattice_.set_distance[e] - model_.radius[i]) <= 1e-6 * model_.radius[i])
          spring[static_cast<std::size_t>(e - first)] |= static_cast<std::uint8_t>(1 << bc.component);
      }
    }
    for (auto e = first; e < end; ++e) {
      const auto k = static_cast<std::size_t>(e - first);
      if (held[k] != 0) {
        rs.disks.push_back(lattice_.set_disk[e]);
        rs.held.push_back(held[k]);
      }
      for (std::uint8_t axis = 0; axis < 2; ++axis) {
        if (!(spring[k] & (1 << axis))) continue;
        rs.spring_disks.push_back(lattice_.set_disk[e]);
        rs.spring_axis.push_back(axis);
      }
    }
    if (!conditioned) {
      // A set that only carries loads reports the force they apply.
      for (std::size_t l = 0; l < loads_.size(); ++l)
        if (loads_[l].load->kind == Load::Kind::Pressure && loads_[l].load->set == name)
          rs.loads.push_back(static_cast<std::int32_t>(l));
      if (rs.loads.empty()) {
        throw InputError(what + " has no [[boundary]] condition and no pressure [[load]]: nothing acts on the "
                                "body there (its reaction would be zero)");
      }
    }
    reaction_sets_.push_back(std::move(rs));
  }
}

std::array<double, 2> Solver::reaction(std::size_t k) const {
  const Model& m = model_;
  const ReactionSet& rs = reaction_sets_[k];
  const double dt = dt_info_.dt;
  double rx = 0, ry = 0;
  // Held components: the force the constraint adds to F(t_n) to give the held disk the
  // leap-frog acceleration (v(t+dt/2) - v(t-dt/2)) / dt it was given (update_velocities).
  for (std::size_t j = 0; j < rs.disks.size(); ++j) {
    const auto i = static_cast<std::size_t>(rs.disks[j]);
    if (rs.held[j] & kFixX) rx += m.mass[i] * (m.vx[i] - m.vx_old[i]) / dt - (m.fx[i] + m.fx_ext[i]);
    if (rs.held[j] & kFixY) ry += m.mass[i] * (m.vy[i] - m.vy_old[i]) / dt - (m.fy[i] + m.fy_ext[i]);
  }
  // Mirror springs, F = -k u at t_n (compute_internal_forces).
  for (std::size_t j = 0; j < rs.spring_disks.size(); ++j) {
    const auto i = static_cast<std::size_t>(rs.spring_disks[j]);
    if (rs.spring_axis[j] == 0) {
      rx -= m.wall_kx[i] * m.ux[i];
    } else {
      ry -= m.wall_ky[i] * m.uy[i];
    }
  }
  // Loads of a set without a condition, at the time of the force pass (apply_external_forces).
  for (std::int32_t l : rs.loads) {
    const LoadSet& ls = loads_[static_cast<std::size_t>(l)];
    const double amp = ls.load->function(m.time);
    for (std::size_t e = 0; e < ls.disks.size(); ++e) {
      rx += amp * ls.cx[e];
      ry += amp * ls.cy[e];
    }
  }
  return {rx, ry};
}

void Solver::setup_initial_velocities() {
  for (const InitialVelocity& iv : case_.initial_velocities) {
    const auto it = std::find(lattice_.body_names.begin(), lattice_.body_names.end(), iv.body);
    if (it == lattice_.body_names.end()) throw InputError(iv.where + ": unknown body '" + iv.body + "'");
    const auto b = static_cast<std::int32_t>(it - lattice_.body_names.begin());
    for (std::size_t i = 0; i < model_.num_disks(); ++i) {
      if (model_.body[i] != b) continue;
      if (!(model_.constraint[i] & kFixX)) model_.vx[i] = iv.velocity[0];
      if (!(model_.constraint[i] & kFixY)) model_.vy[i] = iv.velocity[1];
    }
  }
}

double Solver::finite_omega2_max(int max_iterations) {
  // Lanczos on A = M^-1/2 K M^-1/2 (held degrees of freedom removed), with K applied through
  // the force kernel itself: the largest Ritz value converges in a few tens of iterations,
  // where plain power iteration crawls (the top of a lattice's spectrum is dense and its
  // boundary modes are localised).
  Model& m = model_;
  const std::size_t n = m.num_disks();
  const auto ni = static_cast<std::ptrdiff_t>(n);
  const bool spins = m.shear_model == ShearModel::Rotation;
  const std::size_t dofs = spins ? 3 : 2;
  // Called at set-up, on the initial state: the bonds' history is reset after every probe
  // (the kernel must act as the linear operator), and a state that is not at rest is saved
  // and restored (at set-up it is: the initial velocities are applied after this estimate).
  const auto is_zero = [](const std::vector<double>& a) {
    return std::all_of(a.begin(), a.end(), [](double x) { return x == 0.0; });
  };
  const bool at_rest = is_zero(m.ux) && is_zero(m.uy) && is_zero(m.theta) && is_zero(m.vx) && is_zero(m.vy) &&
                       is_zero(m.omega);
  std::vector<double> ux, uy, th, vx, vy, om;
  if (!at_rest) ux = m.ux, uy = m.uy, th = m.theta, vx = m.vx, vy = m.vy, om = m.omega;
  // M^-1/2 per degree of freedom (0 where held), in the arrays of the velocities before a
  // step: they hold nothing until the first step, and the estimate needs no memory of its own.
  double* const sx = m.vx_old.data();
  double* const sy = m.vy_old.data();
  double* const sw = m.omega_old.data();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < ni; ++i) {
    sx[i] = (m.constraint[i] & kFixX) ? 0.0 : 1.0 / std::sqrt(m.mass[i]);
    sy[i] = (m.constraint[i] & kFixY) ? 0.0 : 1.0 / std::sqrt(m.mass[i]);
    sw[i] = (spins && !(m.constraint[i] & kFixRotation)) ? 1.0 / std::sqrt(m.inertia[i]) : 0.0;
  }
  double r_min = std::numeric_limits<double>::infinity();
  for (double r : m.radius) r_min = std::min(r_min, r);
  // y = A v, through displacements small enough (1e-6 r) for the kernel to be linear.
  auto apply = [&](const std::vector<double>& v, std::vector<double>& y) {
    double umax = 0;  // a maximum: the same in any order
#pragma omp parallel for schedule(static) reduction(max : umax)
    for (std::ptrdiff_t i = 0; i < ni; ++i) {
      const double* vi = v.data() + dofs * static_cast<std::size_t>(i);
      double u = std::max(std::abs(vi[0] * sx[i]), std::abs(vi[1] * sy[i]));
      if (spins) u = std::max(u, std::abs(vi[2] * sw[i]) * m.radius[i]);  // the spin's lever
      umax = std::max(umax, u);
    }
    const double eps = umax > 0 ? 1e-6 * r_min / umax : 1.0;
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < ni; ++i) {
      const double* vi = v.data() + dofs * static_cast<std::size_t>(i);
      m.ux[i] = m.vx[i] = eps * vi[0] * sx[i];
      m.uy[i] = m.vy[i] = eps * vi[1] * sy[i];
      m.theta[i] = m.omega[i] = spins ? eps * vi[2] * sw[i] : 0.0;
    }
    reset_bond_history(m);  // every spring starts from zero: its increment is the probe
    compute_internal_forces(m, 1.0);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < ni; ++i) {
      double* yi = y.data() + dofs * static_cast<std::size_t>(i);
      yi[0] = -m.fx[i] / eps * sx[i];
      yi[1] = -m.fy[i] / eps * sy[i];
      if (spins) yi[2] = -m.torque[i] / eps * sw[i];
    }
  };
  std::vector<double> v(n * dofs), v_prev(n * dofs, 0.0), w(n * dofs);
  const auto nk = static_cast<std::ptrdiff_t>(v.size());
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  double norm = 0;
  for (std::size_t k = 0; k < v.size(); ++k) {
    const std::size_t i = k / dofs, c = k % dofs;
    const double s = c == 0 ? sx[i] : c == 1 ? sy[i] : sw[i];
    v[k] = s > 0 ? uni(rng) : 0.0;
    norm += v[k] * v[k];
  }
  std::vector<double> alpha, beta;
  double lambda = 0;
  if (norm > 0) {
    for (double& x : v) x /= std::sqrt(norm);
    double beta_prev = 0, lambda_prev = 0;
    for (int it = 0; it < max_iterations; ++it) {
      dt_info_.finite_iterations = it + 1;
      apply(v, w);
      // The dot products in index order (the estimate, and so the step, do not depend on
      // the thread count); the vector updates in parallel.
      double a = 0;
      for (std::size_t k = 0; k < w.size(); ++k) a += v[k] * w[k];
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t k = 0; k < nk; ++k) w[k] -= a * v[k] + beta_prev * v_prev[k];
      double b2 = 0;
      for (std::size_t k = 0; k < w.size(); ++k) b2 += w[k] * w[k];
      alpha.push_back(a);
      const double b = std::sqrt(b2);
      if ((it + 1) % 10 == 0 || b == 0 || it + 1 == max_iterations) {
        Eigen::VectorXd diag = Eigen::Map<Eigen::VectorXd>(alpha.data(), static_cast<Eigen::Index>(alpha.size()));
        Eigen::VectorXd off = Eigen::Map<Eigen::VectorXd>(beta.data(), static_cast<Eigen::Index>(beta.size()));
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es;
        es.computeFromTridiagonal(diag, off, Eigen::EigenvaluesOnly);
        lambda = es.eigenvalues().maxCoeff();
        if (b == 0 || (it >= 29 && std::abs(lambda - lambda_prev) < 1e-6 * lambda)) break;
        lambda_prev = lambda;
      }
      beta.push_back(b);
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t k = 0; k < nk; ++k) {
        v_prev[k] = v[k];
        v[k] = w[k] / b;
      }
      beta_prev = b;
    }
  }
  if (at_rest) {
    for (auto* a : {&m.ux, &m.uy, &m.theta, &m.vx, &m.vy, &m.omega}) std::fill(a->begin(), a->end(), 0.0);
  } else {
    m.ux = ux; m.uy = uy; m.theta = th;
    m.vx = vx; m.vy = vy; m.omega = om;
  }
  for (auto* a : {&m.vx_old, &m.vy_old, &m.omega_old}) std::fill(a->begin(), a->end(), 0.0);
  reset_bond_history(m);
  return lambda;
}

void Solver::choose_time_step() {
  TimeStepInfo& info = dt_info_;
  info.dt_bloch = std::numeric_limits<double>::infinity();
  info.dt_eq24 = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < bloch_.size(); ++b) {
    info.dt_bloch = std::min(info.dt_bloch, bloch_[b].dt_critical);
    const BodyMaterial& bm = body_materials_[b];
    info.dt_eq24 = std::min(info.dt_eq24, eq24_time_step(bm.springs, bm.material->density,
                                                         case_.outline.bodies[b].radius.value_or(0.0)));
  }
  // Ritz values converge from below: allow 2 % for what the iteration has not reached.
  const double w2 = finite_omega2_max();
  info.dt_finite = w2 > 0 ? 2.0 / std::sqrt(1.02 * w2) : std::numeric_limits<double>::infinity();
  info.dt_critical = std::min(info.dt_bloch, info.dt_finite);
  // A contact dashpot at a fraction eta of critical damping makes central differences stable
  // only for omega dt < 2 (sqrt(1 + eta^2) - eta) (docs/laws.md): broken bonds become such
  // contacts with the bonds' stiffness.
  if ((model_.any_breakable || contacts_on_ || !case_.walls.empty()) && case_.contact.damping > 0) {
    const double eta = case_.contact.damping;
    info.dt_critical *= std::sqrt(1 + eta * eta) - eta;
  }
  if (case_.time.dt) {
    info.user_dt = true;
    info.dt = *case_.time.dt;
    if (info.dt > info.dt_critical && !case_.time.allow_unstable) {
      throw InputError(case_.source + ": [time] dt = " + fmt(info.dt, 6) + " s exceeds the critical time step " +
                       fmt(info.dt_critical, 6) + " s (Bloch " + fmt(info.dt_bloch, 6) + " s, finite model " +
                       fmt(info.dt_finite, 6) + " s); lower dt, or set allow_unstable = true to study the instability");
    }
  } else {
    // The largest step below safety x critical that lands exactly on the end time.
    const double target = case_.time.safety * info.dt_critical;
    const double steps = std::ceil(case_.time.end / target - 1e-9);
    info.dt = case_.time.end / steps;
  }
}

std::int64_t Solver::total_steps() const {
  return static_cast<std::int64_t>(std::ceil(case_.time.end / dt_info_.dt - 1e-9));
}

void Solver::apply_external_forces(double t) {
  for (std::int32_t i : loaded_disks_) {
    model_.fx_ext[i] = model_.fy_ext[i] = 0.0;
    model_.ext_mxx[i] = model_.ext_myy[i] = model_.ext_mxy[i] = 0.0;
  }
  for (const LoadSet& ls : loads_) {
    const double amp = ls.load->function(t);
    for (std::size_t k = 0; k < ls.disks.size(); ++k) {
      const auto i = static_cast<std::size_t>(ls.disks[k]);
      const double fx = amp * ls.cx[k], fy = amp * ls.cy[k];
      model_.fx_ext[i] += fx;
      model_.fy_ext[i] += fy;
      model_.ext_mxx[i] += ls.lx[k] * fx;
      model_.ext_myy[i] += ls.ly[k] * fy;
      model_.ext_mxy[i] += 0.5 * (ls.lx[k] * fy + ls.ly[k] * fx);
    }
  }
}

template <bool Damping, bool External>
void Solver::update_velocity_blocks(double c_old, double c_new, std::size_t blocks) {
  Model& m = model_;
  const double dt = dt_info_.dt;
  const double alpha = case_.time.mass_damping;
  const std::size_t n = m.num_disks();
  // Eq. 18 for every free degree of freedom; held ones get zero (prescribed values below).
  // Energy terms per disk (see EnergyBalance): leap-frog kinetic energy, and the trapezoid
  // work of external and damping forces split into the halves before and after t_n.
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t blk = 0; blk < static_cast<std::ptrdiff_t>(blocks); ++blk) {
    StepSums s;
    const std::size_t lo = static_cast<std::size_t>(blk) * kSumBlock, hi = std::min(n, lo + kSumBlock);
    for (std::size_t i = lo; i < hi; ++i) {
      const double mass = m.mass[i];
      const std::uint8_t bits = m.constraint[i];
      const double vxo = m.vx[i], vyo = m.vy[i], wo = m.omega[i];
      m.vx_old[i] = vxo;
      m.vy_old[i] = vyo;
      m.omega_old[i] = wo;
      double fx = m.fx[i], fy = m.fy[i];
      if constexpr (External) {
        fx += m.fx_ext[i];
        fy += m.fy_ext[i];
      }
      const bool free_x = !(bits & kFixX);
      const bool free_y = !(bits & kFixY);
      const bool free_w = !(bits & kFixRotation);
      double vxn = 0.0, vyn = 0.0, wn = 0.0;
      if constexpr (Damping) {
        vxn = free_x ? (vxo * c_old + fx / mass * dt) * c_new : 0.0;
        vyn = free_y ? (vyo * c_old + fy / mass * dt) * c_new : 0.0;
        wn = free_w ? (wo * c_old + m.torque[i] / m.inertia[i] * dt) * c_new : 0.0;
      } else {  // c_old = c_new = 1
        vxn = free_x ? vxo + fx / mass * dt : 0.0;
        vyn = free_y ? vyo + fy / mass * dt : 0.0;
        wn = free_w ? wo + m.torque[i] / m.inertia[i] * dt : 0.0;
      }
      m.vx[i] = vxn;
      m.vy[i] = vyn;
      m.omega[i] = wn;
      s.kinetic += 0.5 * (mass * (vxo * vxn + vyo * vyn) + m.inertia[i] * wo * wn);
      s.kinetic_sq += 0.25 * (mass * (vxo * vxo + vyo * vyo + vxn * vxn + vyn * vyn) +
                              m.inertia[i] * (wo * wo + wn * wn));
      if (free_x) {
        if constexpr (External) {
          s.ext_a += 0.5 * dt * m.fx_ext[i] * vxo;
          s.ext_b += 0.5 * dt * m.fx_ext[i] * vxn;
        }
        if constexpr (Damping) {
          const double fd = alpha * mass * 0.5 * (vxo + vxn);  // minus the damping force
          s.damp_a += 0.5 * dt * fd * vxo;
          s.damp_b += 0.5 * dt * fd * vxn;
        }
      }
      if (free_y) {
        if constexpr (External) {
          s.ext_a += 0.5 * dt * m.fy_ext[i] * vyo;
          s.ext_b += 0.5 * dt * m.fy_ext[i] * vyn;
        }
        if constexpr (Damping) {
          const double fd = alpha * mass * 0.5 * (vyo + vyn);
          s.damp_a += 0.5 * dt * fd * vyo;
          s.damp_b += 0.5 * dt * fd * vyn;
        }
      }
      if constexpr (Damping) {
        if (free_w) {
          const double fd = alpha * m.inertia[i] * 0.5 * (wo + wn);
          s.damp_a += 0.5 * dt * fd * wo;
          s.damp_b += 0.5 * dt * fd * wn;
        }
      }
    }
    block_sums_[static_cast<std::size_t>(blk)] = s;
  }
}

Solver::StepSums Solver::update_velocities(double t) {
  Model& m = model_;
  const double dt = dt_info_.dt;
  const double alpha = case_.time.mass_damping;
  const double c_old = 1.0 - 0.5 * alpha * dt, c_new = 1.0 / (1.0 + 0.5 * alpha * dt);
  const std::size_t n = m.num_disks();
  const std::size_t blocks = (n + kSumBlock - 1) / kSumBlock;
  if (block_sums_.size() < blocks) block_sums_.resize(blocks);

  // Mass damping and external forces only where the case has them (a template parameter,
  // not a test per disk): without them their terms are exactly zero.
  const bool damping = alpha != 0.0, external = !loaded_disks_.empty();
  if (damping && external) update_velocity_blocks<true, true>(c_old, c_new, blocks);
  else if (damping) update_velocity_blocks<true, false>(c_old, c_new, blocks);
  else if (external) update_velocity_blocks<false, true>(c_old, c_new, blocks);
  else update_velocity_blocks<false, false>(c_old, c_new, blocks);
  StepSums total;
  for (std::size_t b = 0; b < blocks; ++b) {
    total.kinetic += block_sums_[b].kinetic;
    total.kinetic_sq += block_sums_[b].kinetic_sq;
    total.ext_a += block_sums_[b].ext_a;
    total.ext_b += block_sums_[b].ext_b;
    total.damp_a += block_sums_[b].damp_a;
    total.damp_b += block_sums_[b].damp_b;
  }

  // Prescribed velocities at t + dt/2; the force that imposes them (reaction plus load) does
  // work that enters the balance as external work.
  const double t_half = t + 0.5 * dt;
  for (const VelocitySet& vs : velocity_sets_) {
    const double amp = vs.bc->function(t_half);
    for (std::int32_t i : vs.disks) {
      const double mass = m.mass[i];
      for (int c = 0; c < 2; ++c) {
        if (!vs.bc->velocity[c]) continue;
        double& v = c == 0 ? m.vx[i] : m.vy[i];
        const double vo = c == 0 ? m.vx_old[i] : m.vy_old[i];
        const double f_int = c == 0 ? m.fx[i] : m.fy[i];
        v = *vs.bc->velocity[c] * amp;
        const double g = mass * (v - vo) / dt - f_int;
        total.ext_a += 0.5 * dt * g * vo;
        total.ext_b += 0.5 * dt * g * v;
        total.kinetic += 0.5 * mass * vo * v;
        total.kinetic_sq += 0.25 * mass * (vo * vo + v * v);
      }
    }
  }
  return total;
}

bool Solver::advance(bool diagnostics, const std::function<void(const Solver&)>& at_tn) {
  Model& m = model_;
  const double dt = dt_info_.dt;
  apply_external_forces(time_);
  m.time = time_;
  broken_bonds_ += compute_internal_forces(m, step_ > 0 ? dt : 0.0);
  if (contacts_on_) contact_forces(step_ > 0 ? dt : 0.0);
  if (!case_.walls.empty()) wall_forces(step_ > 0 ? dt : 0.0);
  const StepSums s = update_velocities(time_);

  // Trapezoid sums: the first halves count from step 1 on (the interval before t_0 is none).
  if (step_ > 0) {
    ext_a_ += s.ext_a;
    damp_a_ += s.damp_a;
  }
  energy_.kinetic = s.kinetic;
  energy_.external_work = ext_a_ + ext_b_before_;
  energy_.damping = damp_a_ + damp_b_before_;
  if (diagnostics || step_ == 0) {
    energy_.elastic = elastic_energy(m);
    const BondDissipation d = bond_dissipation(m);
    energy_.plastic = d.plastic;
    energy_.fracture = d.fracture;
    energy_.contact_damping = d.contact_damping + contact_damping_work_;
    energy_.friction = d.friction + contact_friction_work_;
    energy_.break_kinetic = d.break_kinetic;
    if (contacts_on_ || !case_.walls.empty()) energy_.elastic += contact_energy();
  }
  if (step_ == 0) {
    initial_energy_ = energy_.kinetic + energy_.elastic;
  }
  energy_.initial = initial_energy_;

  if (!check_energy(s, diagnostics || step_ == 0)) return false;
  if (at_tn) at_tn(*this);

  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    m.ux[i] += dt * m.vx[i];
    m.uy[i] += dt * m.vy[i];
    m.theta[i] += dt * m.omega[i];
  }
  if (contacts_on_) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      px_[i] = m.x0[i] + m.ux[i];
      py_[i] = m.y0[i] + m.uy[i];
    }
  }
  ext_b_before_ += s.ext_b;
  damp_b_before_ += s.damp_b;
  ++step_;
  time_ = static_cast<double>(step_) * dt;
  return true;
}

}  // namespace hexdem::solver
