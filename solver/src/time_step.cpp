// The time step (physics.md section 5): the Bloch critical step of each body's lattice, the
// finite model's largest eigenfrequency by Lanczos, the contact dashpot's reduction and the
// step that lands on the end time.
#include "hexdem/solver/solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <optional>

#include <Eigen/Dense>
#include <omp.h>

#include "hexdem/error.hpp"
#include "hexdem/solver/case_toml.hpp"

#include "solver_text.hpp"

namespace hexdem::solver {

using detail::fmt;

namespace {

/// Largest omega^2 of model m, M^-1 K, by Lanczos (Solver::finite_omega2_max); the iteration
/// count in `iterations`.
double lanczos_omega2_max(Model& m, int max_iterations, int& iterations) {
  // Lanczos on A = M^-1/2 K M^-1/2 (held degrees of freedom removed), with K applied through
  // the force kernel itself: the largest Ritz value converges in a few tens of iterations,
  // where plain power iteration crawls (the top of a lattice's spectrum is dense and its
  // boundary modes are localised).
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
    sw[i] = (spins && !(m.constraint[i] & kFixRotation)) ? 1.0 / std::sqrt(m.disk_inertia(i)) : 0.0;
  }
  double r_min = std::numeric_limits<double>::infinity();
  for (double r : m.radius) r_min = std::min(r_min, r);
  // The largest displacement that v scales to, for disk i (the spin's by its lever r).
  const auto disk_umax = [&](const double* vi, std::size_t i) {
    const double u = std::max(std::abs(vi[0] * sx[i]), std::abs(vi[1] * sy[i]));
    return spins ? std::max(u, std::abs(vi[2] * sw[i]) * m.radius[i]) : u;
  };
  const auto largest = [&](const std::vector<double>& v) {
    double umax = 0;  // a maximum: the same in any order
#pragma omp parallel for schedule(static) reduction(max : umax)
    for (std::ptrdiff_t i = 0; i < ni; ++i)
      umax = std::max(umax, disk_umax(v.data() + dofs * static_cast<std::size_t>(i), static_cast<std::size_t>(i)));
    return umax;
  };
  // A v, through displacements small enough (1e-6 r) for the kernel to be linear:
  // probe(v, largest(v)) leaves the forces in fx, fy, torque and returns the scale eps (the
  // previous iteration's update of v computes largest(v) on the way). The probe's shear
  // increments are its displacements (compute_probe_forces), so the velocity arrays hold the
  // second vector, u, component by component.
  auto probe = [&](const std::vector<double>& v, double umax) {
    const double eps = umax > 0 ? 1e-6 * r_min / umax : 1.0;
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < ni; ++i) {
      const double* vi = v.data() + dofs * static_cast<std::size_t>(i);
      m.ux[i] = eps * vi[0] * sx[i];
      m.uy[i] = eps * vi[1] * sy[i];
      m.theta[i] = spins ? eps * vi[2] * sw[i] : 0.0;
    }
    reset_force_history(m);  // every spring starts from zero: its increment is the probe
    compute_probe_forces(m);
    return eps;
  };
  // (A v)_k = -f_c[i] / eps * s_c[i], written over the forces f_c = fx, fy, torque.
  double* const y_c[3] = {m.fx.data(), m.fy.data(), m.torque.data()};
  const double* const s_c[3] = {sx, sy, sw};
  // Two vectors: v, and u, which holds the previous v and then, in place, the new residual
  // w = A v - a v - b v_prev (A v is read from the forces, not stored). u's components are
  // the velocity arrays (u_c[i], c = x, y, spin).
  std::vector<double> v(n * dofs);
  double* const u_c[3] = {m.vx.data(), m.vy.data(), m.omega.data()};
  for (auto* a : {&m.vx, &m.vy, &m.omega}) std::fill(a->begin(), a->end(), 0.0);
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
    double umax = largest(v);
    // One thread: each dot product in the same pass as the vector it reads (the same values,
    // summed in the same order as the separate passes of several threads).
    const bool one_thread = omp_get_max_threads() == 1;
    for (int it = 0; it < max_iterations; ++it) {
      iterations = it + 1;
      const double eps = probe(v, umax);
      // The dot products in index order (the estimate, and so the step, do not depend on
      // the thread count); the vector updates in parallel. A v is computed once, in place of
      // the forces (nothing reads them before the next probe). The sums are in locals of
      // their own: a variable that a parallel region shares has its address taken, and the
      // compiler kept it in memory through the whole loop.
      const auto a_v = [&](std::size_t i, std::size_t c) { return -y_c[c][i] / eps * s_c[c][i]; };
      const double a = [&] {
        double sum = 0;
        if (one_thread) {
          for (std::size_t i = 0; i < n; ++i)
            for (std::size_t c = 0; c < dofs; ++c) sum += v[dofs * i + c] * (y_c[c][i] = a_v(i, c));
          return sum;
        }
#pragma omp parallel for schedule(static)
        for (std::ptrdiff_t i = 0; i < ni; ++i)
          for (std::size_t c = 0; c < dofs; ++c) y_c[c][i] = a_v(static_cast<std::size_t>(i), c);
        for (std::size_t i = 0; i < n; ++i)
          for (std::size_t c = 0; c < dofs; ++c) sum += v[dofs * i + c] * y_c[c][i];
        return sum;
      }();
      const auto residual = [&](std::size_t i, std::size_t c) {
        double& uk = u_c[c][i];
        uk = y_c[c][i] - (a * v[dofs * i + c] + beta_prev * uk);
        return uk;
      };
      const double b2 = [&] {
        double sum = 0;
        if (one_thread) {
          for (std::size_t i = 0; i < n; ++i)
            for (std::size_t c = 0; c < dofs; ++c) {
              const double uk = residual(i, c);
              sum += uk * uk;
            }
          return sum;
        }
#pragma omp parallel for schedule(static)
        for (std::ptrdiff_t i = 0; i < ni; ++i)
          for (std::size_t c = 0; c < dofs; ++c) residual(static_cast<std::size_t>(i), c);
        for (std::size_t i = 0; i < n; ++i)
          for (std::size_t c = 0; c < dofs; ++c) sum += u_c[c][i] * u_c[c][i];
        return sum;
      }();
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
      double next_umax = 0;  // largest(v) of the new v, on the way
#pragma omp parallel for schedule(static) reduction(max : next_umax)
      for (std::ptrdiff_t i = 0; i < ni; ++i) {
        for (std::size_t c = 0; c < dofs; ++c) {
          const std::size_t k = dofs * static_cast<std::size_t>(i) + c;
          double& uk = u_c[c][i];
          const double next = uk / b;  // v_prev <- v, v <- w / b
          uk = v[k];
          v[k] = next;
        }
        next_umax = std::max(next_umax, disk_umax(v.data() + dofs * static_cast<std::size_t>(i), static_cast<std::size_t>(i)));
      }
      umax = next_umax;
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

}  // namespace

double finite_model_step(double omega2_max) {
  // Ritz values converge from below: allow 2 % for what the iteration has not reached.
  return omega2_max > 0 ? 2.0 / std::sqrt(1.02 * omega2_max) : std::numeric_limits<double>::infinity();
}

double Solver::finite_omega2_max(int max_iterations) {
  return lanczos_omega2_max(model_, max_iterations, dt_info_.finite_iterations);
}

// The edge band. A lattice's largest eigenfrequency above the Bloch value of its bulk belongs
// to a mode that lives on its irregular disks (free edges, semi-disks, held or mirrored disks,
// disks whose cell is not the whole hexagon)
// and decays into the regular lattice within a few rows, for it lies above the bulk's band
// (docs/benchmarks.md, "Set-up"). The Lanczos estimate on the disks within `width` bonds of
// an irregular disk, with the disks beyond them held, is the largest eigenvalue of a principal
// submatrix of K: never above the whole model's (Cauchy's interlacing theorem), and equal to it
// up to the mode's amplitude at the band's inner edge, squared. Below the Bloch value the
// band's estimate may miss the bulk's modes, and then the Bloch step binds (choose_time_step).
// The estimate costs the band's share of the whole model's: 4 % of it for a square of
// 1,000,000 disks.
std::optional<double> Solver::band_omega2_max(int width, int halo, std::size_t* band_disks, int max_iterations,
                                              const std::function<void(std::size_t)>& before_build) {
  const Model& m = model_;
  // The sub-model needs the bonds' stiffness per spring kind (plane models): an axisymmetric
  // model's rings differ from disk to disk, so its whole model is its band.
  // An irregular lattice ([mesh] jitter: the reference geometry per bond) has no bulk whose
  // Bloch value bounds the interior: the whole model is its band too.
  if (m.geometry == Geometry::Axisymmetric || m.spring_kind.empty() || m.kind_rest.empty()) return std::nullopt;
  const std::size_t n = m.num_disks();
  const std::int32_t reach = width + halo;
  constexpr std::int32_t kFar = std::numeric_limits<std::int32_t>::max();
  std::vector<std::int32_t> dist(n, kFar);  // bonds from the nearest irregular disk
  std::vector<std::int32_t> queue;
  for (std::size_t i = 0; i < n; ++i) {
    const bool mirrored = (!m.mirror.plane.empty() && m.mirror.plane[i]) ||
                          (m.has_mirror_springs() && (m.mirror.kx[i] != 0 || m.mirror.ky[i] != 0));
    // A disk whose cell is not the whole hexagon 2 sqrt(3) r^2 has another mass than the
    // bulk's: a lighter one would carry a mode above the bulk's top. The generator gives cut
    // cells to disks that lose a bond or are semi-disks (a 0.3 r slit across a plate leaves
    // no other), apart from slivers (the notched beam at r = 1 mm: one disk 5e-9 light at the
    // notch's corner), so this is a guard (tests/solver/test_critical_step.cpp).
    const double hexagon = 2 * 1.7320508075688772935 * m.radius[i] * m.radius[i];
    if (m.initial_bonds(i) != 6 || m.kind[i] != static_cast<std::uint8_t>(meshing::DiskKind::Disk) ||
        m.constraint[i] != 0 || mirrored || std::abs(m.cell_area[i] - hexagon) > 1e-9 * hexagon) {
      dist[i] = 0;
      queue.push_back(static_cast<std::int32_t>(i));
    }
  }
  for (std::size_t q = 0; q < queue.size(); ++q) {  // breadth first: each disk once
    const auto i = static_cast<std::size_t>(queue[q]);
    if (dist[i] == reach) continue;
    for (std::int64_t k = m.adj_offset[i]; k < m.adj_offset[i + 1]; ++k) {
      const std::size_t j = m.adj_other(i, k);
      if (dist[j] == kFar) {
        dist[j] = dist[i] + 1;
        queue.push_back(static_cast<std::int32_t>(j));
      }
    }
  }
  if (2 * queue.size() > n) return std::nullopt;  // the band would save little
  if (before_build) before_build(queue.size());
  // The band's disks in the whole model's order (so bi < bj is kept), and which are held.
  std::vector<std::int32_t>& band = queue;
  std::sort(band.begin(), band.end());
  std::vector<std::uint8_t> halo_of(band.size());
  std::size_t free_disks = 0;
  for (std::size_t k = 0; k < band.size(); ++k) {
    halo_of[k] = dist[static_cast<std::size_t>(band[k])] > width ? 1 : 0;
    if (!halo_of[k]) ++free_disks;
  }
  const auto sub_of = [&band](std::int32_t i) {
    return static_cast<std::int32_t>(std::lower_bound(band.begin(), band.end(), i) - band.begin());
  };
  meshing::Lattice lat;
  lat.mode = meshing::GeometryMode::Plane;
  for (std::size_t b = 0; b < m.num_bonds(); ++b) {
    if (dist[static_cast<std::size_t>(m.bi[b])] > reach || dist[static_cast<std::size_t>(m.bj[b])] > reach) continue;
    lat.bond_i.push_back(sub_of(m.bi[b]));
    lat.bond_j.push_back(sub_of(m.bj[b]));
    lat.bond_class.push_back(m.bond_class_of(b));
    lat.bond_on_edge.push_back(static_cast<std::uint8_t>(m.spring_kind[b] & 1));
  }
  std::vector<std::int32_t>().swap(dist);
  for (const std::int32_t d : band) {
    const auto i = static_cast<std::size_t>(d);
    lat.x.push_back(m.x0[i]);
    lat.y.push_back(m.y0[i]);
    lat.radius.push_back(m.radius[i]);
    lat.cell_area.push_back(m.cell_area[i]);
    lat.kind.push_back(m.kind[i]);
    lat.body.push_back(m.body[i]);
    lat.material.push_back(m.disk_material(i));
  }
  lat.cell_cx = lat.x;  // read by axisymmetric models only
  lat.cell_cy = lat.y;
  // The probe applies the lattice's linear operator at rest (1e-6 r, far below any strength
  // or yield), so the band is built elastic: without failure or spring plasticity its force
  // pass is the elastic kernel's (elastic_bond_forces), which gives the same forces at a
  // third to three quarters of the cost per disk of the laws' kernel (docs/benchmarks.md,
  // "Set-up"). J2 and Drucker-Prager disks keep their model: their out-of-plane terms are
  // part of the operator.
  std::vector<Material> elastic(body_materials_.size());
  std::vector<BodyMaterial> elastic_bodies = body_materials_;
  for (std::size_t k = 0; k < body_materials_.size(); ++k) {
    elastic[k] = *body_materials_[k].material;
    elastic[k].breakable = false;
    if (!body_materials_[k].j2) elastic[k].yield_stress = 0;
    elastic_bodies[k].material = &elastic[k];
  }
  Model sub = build_model(std::move(lat), m.geometry, m.thickness, m.shear_model, elastic_bodies);
  // The whole model's conditions; the halo held in full.
  const bool mirror_plane = !m.mirror.plane.empty(), mirror_springs = m.has_mirror_springs();
  if (mirror_plane) sub.mirror.plane.assign(sub.num_disks(), 0);
  if (mirror_springs)
    for (auto* v : {&sub.mirror.kx, &sub.mirror.ky, &sub.mirror.sx, &sub.mirror.sy}) v->assign(sub.num_disks(), 0.0);
  for (std::size_t k = 0; k < band.size(); ++k) {
    const auto i = static_cast<std::size_t>(band[k]);
    sub.constraint[k] = halo_of[k] ? static_cast<std::uint8_t>(kFixX | kFixY | kFixRotation) : m.constraint[i];
    if (mirror_plane) sub.mirror.plane[k] = m.mirror.plane[i];
    if (mirror_springs) {
      sub.mirror.kx[k] = m.mirror.kx[i];
      sub.mirror.ky[k] = m.mirror.ky[i];
      sub.mirror.sx[k] = m.mirror.sx[i];
      sub.mirror.sy[k] = m.mirror.sy[i];
    }
  }
  if (band_disks != nullptr) *band_disks = free_disks;
  return lanczos_omega2_max(sub, max_iterations, dt_info_.finite_iterations);
}

double Solver::finite_estimate() {
  // The band's width: 16 bonds hold the edge modes of the shipped cases to 1e-7 of omega^2
  // (docs/benchmarks.md, "Set-up"); 3 held rings give the local-strain fits of the band's
  // neighbours their whole neighbourhoods.
  constexpr int kBandWidth = 16, kBandHalo = 3;
  // The model is at rest and has no forces yet (the first step computes them; the whole
  // model's estimate leaves its probe's in them): its state, force and strain arrays hold
  // zeros, released while the band's model exists so that it does not add to the run's peak
  // memory, and given back as zeros. Not where the contacts' broad phase follows (set up
  // next, about 170 bytes per disk at 1,000,000 disks) and the band holds at most a fifth of
  // the disks (its model, with its Lanczos vectors, about 70 bytes per disk of the whole
  // model at a tenth): the peak comes later, and giving the arrays back costs their first
  // touches again (0.1-0.2 s at 1,000,000 disks; docs/benchmarks.md, "Set-up").
  Model& m = model_;
  const bool contacts_follow = contacts_wanted();
  std::vector<std::pair<std::vector<double>*, std::size_t>> zeros;
  const auto release = [&](std::size_t band_size) {
    if (contacts_follow && 5 * band_size <= m.num_disks()) return;
    for (auto* a : {&m.ux, &m.uy, &m.theta, &m.vx, &m.vy, &m.omega, &m.vx_old, &m.vy_old, &m.omega_old, &m.fx, &m.fy,
                    &m.torque, &m.f_n, &m.f_s, &m.nx, &m.ny, &m.pair_fx, &m.pair_fy, &m.strain.eps_xx, &m.strain.eps_yy,
                    &m.strain.eps_xy, &m.strain.w_xx, &m.strain.w_xy, &m.strain.w_yx, &m.strain.w_yy}) {
      if (!a->empty() && std::all_of(a->begin(), a->end(), [](double x) { return x == 0.0; })) {
        zeros.emplace_back(a, a->size());
        std::vector<double>().swap(*a);
      }
    }
  };
  std::size_t band = 0;
  std::optional<double> band_w2 = band_omega2_max(kBandWidth, kBandHalo, &band, 200, release);
  for (auto [a, size] : zeros) a->assign(size, 0.0);
  // An edge mode decays into the bulk the more slowly the nearer it lies to the bulk's top
  // (its decay rate goes as the square root of the distance): one within 2 % of the largest
  // Bloch value may reach beyond the band (a plate on a lattice turned by 7 degrees, 0.5 %
  // above it: the band was 7e-6 low), and the whole model is estimated instead.
  constexpr double kEdgeMargin = 1.02;
  double w2_bloch = 0;
  for (const BlochResult& br : bloch_) w2_bloch = std::max(w2_bloch, br.omega2_max);
  if (band_w2 && !(*band_w2 >= kEdgeMargin * w2_bloch)) band_w2.reset();
  finite_disks_ = band_w2 ? band : model_.num_disks();
  return band_w2 ? *band_w2 : finite_omega2_max();
}

void Solver::choose_time_step(double w2) {
  TimeStepInfo& info = dt_info_;
  info.dt_bloch = std::numeric_limits<double>::infinity();
  info.dt_eq24 = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < bloch_.size(); ++b) {
    info.dt_bloch = std::min(info.dt_bloch, bloch_[b].dt_critical);
    const BodyMaterial& bm = body_materials_[b];
    info.dt_eq24 = std::min(info.dt_eq24, eq24_time_step(bm.springs, bm.material->density,
                                                         case_.outline.bodies[b].radius.value_or(0.0)));
  }
  info.dt_finite = finite_model_step(w2);
  // A critical step that is not a positive finite number (a density or stiffness at the
  // ends of the double range: density 1e-300 gives inf) cannot give a step: bad input, not a
  // numerical failure of the run (docs/case-format.md, "Time step").
  for (std::size_t b = 0; b < bloch_.size(); ++b) {
    const double dt_b = bloch_[b].dt_critical;
    if (std::isfinite(dt_b) && dt_b > 0) continue;
    const Material& mat = *body_materials_[b].material;
    const std::string stiffness = mat.E > 0 ? "E = " + fmt(mat.E, 6) + " Pa"
                                            : "c11 = " + fmt(mat.c.c11, 6) + " Pa, c66 = " + fmt(mat.c.c66, 6) + " Pa";
    throw InputError(case_.source + ": [[material]] '" + mat.name + "' (id " + std::to_string(mat.id) +
                     "): density = " + fmt(mat.density, 6) + " kg/m^3, " + stiffness +
                     ": the critical time step of body '" + case_.outline.bodies[b].name + "' is " + fmt(dt_b, 6) +
                     " s, not a positive finite number; check the material's units");
  }
  if (std::isnan(info.dt_finite) || !(info.dt_finite > 0))
    throw InputError(case_.source + ": the finite model's critical time step is " + fmt(info.dt_finite, 6) +
                     " s, not a positive number (case.thickness = " + fmt(case_.thickness, 6) +
                     " m); check the thickness and the materials' units");
  // A random stiffness field (apply_random_stiffness): the uniform model's step / sqrt(f_max).
  info.dt_critical = std::min(info.dt_bloch, info.dt_finite) / std::sqrt(info.stiffness_max);
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
  }
  // The largest step below safety x critical that lands exactly on the end time (the target
  // itself for an end time too short to count one step, which the check below refuses).
  const auto landing_step = [&](double safety) {
    const double target = safety * info.dt_critical;
    const double steps = std::ceil(case_.time.end / target - 1e-9);
    return steps >= 1 ? case_.time.end / steps : target;
  };
  if (!info.user_dt) info.dt = landing_step(case_.time.safety);
  // The step the contacts' stiffness cap refers to: the default step whatever the step used,
  // so that a smaller [time] dt or safety integrates the same contacts (contacts.cpp).
  info.dt_contact = landing_step(kDefaultSafety);
  // An end time shorter than one step: no step would be taken (ceil gives 0, the chosen step
  // -inf), and the run would end at t = 0 or report a blow-up.
  if (!(case_.time.end / info.dt - 1e-9 > 0) || !std::isfinite(info.dt) || !(info.dt > 0)) {
    const double step = info.user_dt ? info.dt : case_.time.safety * info.dt_critical;
    throw InputError(case_.source + ": [time] end = " + fmt(case_.time.end, 6) + " s is shorter than one time step (" +
                     (info.user_dt ? "dt = " : "safety x critical = ") + fmt(step, 6) +
                     " s); raise end" + (info.user_dt ? " or lower dt" : " or check the materials' units"));
  }
  // The step count must fit (Solver::total_steps converts it to an integer): checked here so
  // that `hexdem check` refuses what `hexdem run` refuses.
  if (const double n = case_.time.end / info.dt; !(n <= kMaxSteps))
    throw InputError(case_.source + ": [time] end = " + fmt(case_.time.end, 6) + " s at dt = " + fmt(info.dt, 6) +
                     " s needs " + fmt(n, 6) + " steps, more than " + fmt(kMaxSteps, 6) + "; lower end or raise dt");
}

std::int64_t Solver::total_steps() const {
  return static_cast<std::int64_t>(std::ceil(case_.time.end / dt_info_.dt - 1e-9));
}

}  // namespace hexdem::solver
