// The explicit time loop: the solver's set-up (materials per body, then the boundaries,
// contacts, time step and energy scale of their own files) and the leap-frog central
// differences with mass damping (Eq. 18) that advance it one step.
#include "hexdem/solver/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/meshing/lattice_jitter.hpp"
#include "hexdem/meshing/toml_values.hpp"
#include "hexdem/solver/boundary_checks.hpp"
#include "hexdem/solver/checkpoint.hpp"
#include "hexdem/solver/random_field.hpp"

#include "solver_text.hpp"

namespace hexdem::solver {

using detail::fmt;

meshing::Lattice mesh_case(const Case& c, meshing::GeneratorReport* report) {
  meshing::GeneratorOptions go;
  go.mode = c.geometry == Geometry::Axisymmetric ? meshing::GeometryMode::Axisymmetric
                                                 : meshing::GeometryMode::Plane;
  go.max_disks = c.max_disks;
  go.max_disks_hint = kMaxDisksHint;
  meshing::Lattice lattice = meshing::generate_lattice(c.outline, go, report);
  meshing::jitter_lattice(lattice, c.mesh_jitter, static_cast<std::uint64_t>(c.mesh_jitter_seed));
  meshing::apply_disk_order(lattice, c.disk_order);
  return lattice;
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
  lattice_hash_ = hexdem::solver::lattice_hash(lattice_);
  // The cells' centroids: the build reads the ring radius of axisymmetric models only.
  if (case_.geometry != Geometry::Axisymmetric)
    for (auto* v : {&lattice_.cell_cx, &lattice_.cell_cy}) std::vector<double>().swap(*v);
  // The model takes the lattice's disk and bond arrays (no second copy at any time); the
  // lattice keeps its names and sets, and the arrays only the build needs are released.
  // The contact radii from the lattice as built (its positions: any disk order, any jitter).
  std::vector<double> contact_radii = meshing::contact_radii(lattice_, case_.contact.radius_spread,
                                                             static_cast<std::uint64_t>(case_.mesh_jitter_seed));
  model_ = build_model(std::move(lattice_), case_.geometry, case_.thickness, case_.shear_model, body_materials_);
  model_.contact_damping = case_.contact.damping;
  model_.contact_radius = std::move(contact_radii);
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
      mx[b] = model_.x0[model_.bi[b]] + 0.5 * model_.ref_ax(b);
      my[b] = model_.y0[model_.bi[b]] + 0.5 * model_.ref_ay(b);
    }
    model_.strength_scale = lognormal_field(mx, my, r.seed, r.correlation_length, r.strength_cov);
    if (!model_.hoop_cracks.damage.empty())
      model_.disk_strength_scale = lognormal_field(model_.x0, model_.y0, r.seed, r.correlation_length, r.strength_cov);
    // The stiffness field's factors (the second stream): the criteria's thresholds read them
    // next; the springs take them after the critical step's estimate (apply_random_stiffness).
    if (r.stiffness_cov > 0) {
      for (std::size_t k = 0; k < body_materials_.size(); ++k)
        if (body_materials_[k].material->breakable && body_materials_[k].j2)
          throw InputError(case_.source + ": [random] stiffness_cov = " + fmt(r.stiffness_cov, 6) + ": body '" +
                           case_.outline.bodies[k].name + "' has per-disk plasticity (material '" +
                           body_materials_[k].material->name +
                           "'), whose stress is the material's: the stiffness field scales springs only");
      model_.stiffness_scale = lognormal_field(mx, my, r.seed, r.correlation_length, r.stiffness_cov, 1);
      for (std::size_t b = 0; b < model_.num_bonds(); ++b)
        if (model_.bond_failure_law(b) < 0) model_.stiffness_scale[b] = 1.0;  // an unbreakable body: uniform
    }
  }
  // After the random field: the nonlocal and local bounds read the smallest strength factor.
  setup_nonlocal_strain();
  build_local_criterion(model_);
  lap(setup_times_.random_field);
  setup_boundaries();
  setup_loads();
  setup_reactions();
  check_probes();
  check_walls();
  lap(setup_times_.sets);
  // On the model at rest (the estimate saves no state), before the contacts' structures
  // exist, so that its transient model does not add to theirs in the peak memory.
  const double finite_omega2 = finite_estimate();
  apply_random_stiffness();  // after the estimate, which is the uniform model's
  lap(setup_times_.time_step);
  setup_contacts();
  lap(setup_times_.contacts);
  choose_time_step(finite_omega2);
  setup_initial_velocities();
  setup_contact_resolution();
  setup_energy_scale();
  lap(setup_times_.energy_scale);
}

void Solver::apply_random_stiffness() {
  Model& m = model_;
  if (m.stiffness_scale.empty()) return;
  const std::size_t nb = m.num_bonds();
  if (m.k_n.empty()) {
    // Per-kind stiffnesses become per-bond ones (the kernels read whichever form exists).
    m.k_n.resize(nb);
    m.k_s.resize(nb);
    for (std::size_t b = 0; b < nb; ++b) {
      m.k_n[b] = m.kind_k_n[m.spring_kind[b]];
      m.k_s[b] = m.kind_k_s[m.spring_kind[b]];
    }
    std::vector<double>().swap(m.kind_k_n);
    std::vector<double>().swap(m.kind_k_s);
  }
  double f_max = 1.0;
  for (std::size_t b = 0; b < nb; ++b) {
    const double f = m.stiffness_scale[b];
    f_max = std::max(f_max, f);
    m.k_n[b] *= f;
    m.k_s[b] *= f;
    if (!m.bond_plastic.kh_n.empty()) {
      m.bond_plastic.kh_n[b] *= f;
      m.bond_plastic.kh_s[b] *= f;
    }
  }
  if (m.geometry == Geometry::Axisymmetric && !m.hoop.lambda.empty()) {
    // The hoop term of a breakable body's disk: the field at the disk.
    const RandomField& r = *case_.random;
    const std::vector<double> disk = lognormal_field(m.x0, m.y0, r.seed, r.correlation_length, r.stiffness_cov, 1);
    for (std::size_t i = 0; i < m.num_disks(); ++i) {
      if (m.body_failure_law[static_cast<std::size_t>(m.body[i])] < 0) continue;
      m.hoop.lambda[i] *= disk[i];
      m.hoop.mu[i] *= disk[i];
      f_max = std::max(f_max, disk[i]);
    }
  }
  // Each bond's and each ring's term of the stiffness matrix is positive semi-definite and
  // multiplied by at most f_max: K' <= f_max K, so omega'^2_max <= f_max omega^2_max, and the
  // uniform model's critical step divided by sqrt(f_max) is safe (choose_time_step).
  dt_info_.stiffness_max = f_max;
}

void Solver::setup_nonlocal_strain() {
  // [[material]] nonlocal_radius: the softening criteria read strains averaged over R.
  std::vector<double> radius(body_materials_.size(), 0.0);
  bool any = false;
  for (std::size_t b = 0; b < body_materials_.size(); ++b) {
    const Material& mat = *body_materials_[b].material;
    if (!(mat.nonlocal_radius > 0) || !(mat.fracture_energy > 0) || !mat.breakable) continue;
    const double r = case_.outline.bodies[b].radius.value_or(0.0);
    // The nearest neighbours are 2r apart: a radius at or below that averages a disk alone.
    if (!(mat.nonlocal_radius > 2 * r * (1 + 1e-9)))
      throw InputError(case_.source + ": [[material]] '" + mat.name + "': nonlocal_radius = " +
                       fmt(mat.nonlocal_radius, 6) + " m is not larger than the spacing 2r = " + fmt(2 * r, 6) +
                       " m of body '" + case_.outline.bodies[b].name +
                       "': the average would hold each disk alone; use a radius of several spacings (docs/model.md, "
                       "\"Nonlocal criterion\")");
    radius[b] = mat.nonlocal_radius;
    any = true;
  }
  if (!any) return;
  // The rows hold, per disk, the disks of its body within R (12 bytes each): refuse a radius
  // whose rows would not fit before building them. An interior disk's row holds about
  // pi R^2 / (2 sqrt(3) r^2) disks, at most its body's.
  std::vector<double> body_disks(body_materials_.size(), 0.0);
  for (std::size_t i = 0; i < model_.num_disks(); ++i) body_disks[static_cast<std::size_t>(model_.body[i])] += 1;
  double entries = 0;
  for (std::size_t b = 0; b < radius.size(); ++b) {
    if (!(radius[b] > 0)) continue;
    const double r = case_.outline.bodies[b].radius.value_or(0.0);
    const double cell = 2 * std::sqrt(3.0) * r * r;
    const double row = std::min(std::acos(-1.0) * radius[b] * radius[b] / cell, body_disks[b]);
    entries += row * body_disks[b];
    const std::string& name = body_materials_[b].material->name;
    if (row > NonlocalStrain::kMaxRow)
      throw InputError(case_.source + ": [[material]] '" + name + "': nonlocal_radius = " + fmt(radius[b], 6) +
                       " m averages each disk of body '" + case_.outline.bodies[b].name + "' over about " +
                       fmt(row, 3) + " disks, more than " + fmt(NonlocalStrain::kMaxRow, 6) + " (at this spacing R <= " +
                       fmt(std::sqrt(NonlocalStrain::kMaxRow * cell / std::acos(-1.0)), 3) +
                       " m; docs/model.md, \"Nonlocal criterion\")");
    if (entries > NonlocalStrain::kMaxEntries)
      throw InputError(case_.source + ": [[material]] '" + name + "': nonlocal_radius = " + fmt(radius[b], 6) +
                       " m: the averages would hold about " + fmt(entries, 3) + " entries (12 bytes each), more than " +
                       fmt(NonlocalStrain::kMaxEntries, 6) + "; use a smaller radius or a coarser lattice (docs/model.md, "
                       "\"Nonlocal criterion\")");
  }
  build_nonlocal_strain(model_, radius);
}

std::size_t probe_disk(const Model& m, const Probe& p) {
  std::size_t best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    const double d = std::hypot(m.x0[i] - p.point[0], m.y0[i] - p.point[1]);
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  // A probe outside every body would record a disk far from where it was asked for.
  if (m.num_disks() == 0 || !(best_d <= 2 * m.radius[best])) {
    throw InputError(p.where + ": probe '" + p.name + "' selects no disk: its point lies " +
                     meshing::format_number(best_d) + " m from the nearest disk centre (radius " +
                     meshing::format_number(m.num_disks() == 0 ? 0.0 : m.radius[best]) + " m), outside every body");
  }
  return best;
}

void Solver::check_probes() const {
  const Model& m = model_;
  for (const Probe& p : case_.probes) (void)probe_disk(m, p);
  for (const std::string& b : case_.output.body_history) {
    const auto at = std::find(lattice_.body_names.begin(), lattice_.body_names.end(), b);
    if (at == lattice_.body_names.end())
      throw InputError(case_.source + ": output.body_history: unknown body '" + b + "'");
    const auto index = static_cast<std::int32_t>(at - lattice_.body_names.begin());
    if (std::find(m.body.begin(), m.body.end(), index) == m.body.end())
      throw InputError(case_.source + ": output.body_history: body '" + b + "' selects no disk (it has none)");
  }
}

void Solver::check_walls() const {
  const Model& m = model_;
  for (const Wall& wall : case_.walls) {
    // The disk that reaches farthest into the wall at t = 0 (wall_forces' overlap delta).
    double worst = 0;
    std::size_t worst_i = 0;
    bool any = false;
    for (std::size_t i = 0; i < m.num_disks(); ++i) {
      const double delta =
          m.radius[i] - ((m.x0[i] - wall.point[0]) * wall.normal[0] + (m.y0[i] - wall.point[1]) * wall.normal[1]);
      if (delta > 1e-9 * m.radius[i] && (!any || delta > worst)) {
        worst = delta;
        worst_i = i;
        any = true;
      }
    }
    if (!any) continue;
    const double x = m.x0[worst_i], y = m.y0[worst_i];
    throw InputError(wall.where + ": the wall through (" + fmt(wall.point[0], 6) + ", " + fmt(wall.point[1], 6) +
                     ") m with normal (" + fmt(wall.normal[0], 6) + ", " + fmt(wall.normal[1], 6) +
                     ") overlaps the disk at (" + fmt(x, 6) + ", " + fmt(y, 6) + ") m by " + fmt(worst, 6) +
                     " m (radius " + fmt(m.radius[worst_i], 6) +
                     " m) at t = 0: every disk must lie on the side the normal points to, its centre at least "
                     "its radius from the wall; move the wall or flip its normal");
  }
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
      const bool per_disk = model == PlasticityModel::J2 || model == PlasticityModel::DruckerPrager;
      const std::string named = std::string("plasticity = \"") + plasticity_model_name(model) + "\"";
      if (per_disk && case_.geometry == Geometry::PlaneStress)
        throw InputError(what + ": " + named + " is available in plane strain and axisymmetry only");
      if (per_disk && case_.shear_model != ShearModel::LocalStrain)
        throw InputError(what + ": " + named + " needs [case] shear_model = \"local-strain\"");
      bm.j2 = per_disk;
      body_materials_.back().j2 = bm.j2;
      std::string line = "material '" + mat->name + "' (id " + std::to_string(mat->id) + "): plasticity ";
      if (model == PlasticityModel::DruckerPrager) {
        const Material::DruckerPragerCone dp = mat->drucker_prager();
        line += "drucker-prager (per disk, q <= k - alpha p), k " + fmt(dp.k / 1e6) + " MPa, alpha " + fmt(dp.alpha) +
                ", E_t " + fmt(mat->tangent_modulus / 1e9) + " GPa";
      } else {
        line += (bm.j2 ? "j2 (von Mises per disk, linear kinematic hardening" : "spring (bilinear springs, Eq. 16") +
                (mat->plasticity == PlasticityModel::Auto
                     ? std::string(", chosen by auto: k_s ") + (positive ? "> 0)" : "<= 0)")
                     : std::string(")")) +
                ", sigma_y " + fmt(mat->yield_stress / 1e6) + " MPa, E_t " + fmt(mat->tangent_modulus / 1e9) + " GPa";
      }
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
        wn = free_w ? (wo * c_old + m.torque[i] / m.disk_inertia(i) * dt) * c_new : 0.0;
      } else {  // c_old = c_new = 1
        vxn = free_x ? vxo + fx / mass * dt : 0.0;
        vyn = free_y ? vyo + fy / mass * dt : 0.0;
        wn = free_w ? wo + m.torque[i] / m.disk_inertia(i) * dt : 0.0;
      }
      m.vx[i] = vxn;
      m.vy[i] = vyn;
      m.omega[i] = wn;
      s.kinetic += 0.5 * (mass * (vxo * vxn + vyo * vyn) + m.disk_inertia(i) * wo * wn);
      s.kinetic_sq += 0.25 * (mass * (vxo * vxo + vyo * vyo + vxn * vxn + vyn * vyn) +
                              m.disk_inertia(i) * (wo * wo + wn * wn));
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
          const double fd = alpha * m.disk_inertia(i) * 0.5 * (wo + wn);
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
