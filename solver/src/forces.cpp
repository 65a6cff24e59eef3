// Force kernels of the bonded lattice.
// Ref: Liu, Gao, Tanimura (2004), Eqs. 1-4 (bond kinematics and forces) and Eq. 15
// (axisymmetric scaling); physics.md sections 2, 4 (local-strain shear model) and 10 (hoop).
//
// All passes are gathers over a fixed adjacency order or independent per-bond updates, so the
// forces are bit-identical whatever the number of OpenMP threads.
#include <cmath>

#include "hexdem/solver/model.hpp"

namespace hexdem::solver {
namespace {

/// Pass A: least-squares strain of each disk over its intact bonds,
/// grad u_i = (sum_k (u_k - u_i) a_k^T) (sum_k a_k a_k^T)^-1, eps = sym(grad u).
void compute_disk_strains(Model& m) {
  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
  const double* ux = m.ux.data();
  const double* uy = m.uy.data();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    double gxx = 0, gxy = 0, gyx = 0, gyy = 0;
    for (auto k = m.adj_offset[i]; k < m.adj_offset[i + 1]; ++k) {
      const auto b = static_cast<std::size_t>(m.adj_bond[k]);
      if (!m.bond_intact(b)) continue;
      const double ax = m.adj_ax[k], ay = m.adj_ay[k];
      const auto o = m.adj_other[k];
      const double dux = ux[o] - ux[i], duy = uy[o] - uy[i];
      gxx += dux * ax;
      gxy += dux * ay;
      gyx += duy * ax;
      gyy += duy * ay;
    }
    const double mxx = m.minv_xx[i], mxy = m.minv_xy[i], myy = m.minv_yy[i];
    m.eps_xx[i] = gxx * mxx + gxy * mxy;
    m.eps_yy[i] = gyx * mxy + gyy * myy;
    // On a mirror plane the strain is mirror-symmetric: no shear.
    m.eps_xy[i] = m.mirror_plane[i] ? 0.0 : 0.5 * ((gxx * mxy + gxy * myy) + (gyx * mxx + gyy * mxy));
  }
}

/// Pass B: bond forces. Normal: f_n = k_n (L - L0) with the current length (objective).
/// Shear, rotation model (Eq. 1-2): f_s += k_s [(du_j - du_i).s - (r_i dtheta_i + r_j dtheta_j)]
/// with the increments of the last step. Shear, local-strain model: u_s = d s.(eps_i+eps_j)/2.n
/// in the reference directions, f_s = k_s u_s.
void compute_bond_forces(Model& m, double dt) {
  const auto nb = static_cast<std::ptrdiff_t>(m.num_bonds());
  const bool rotation = m.shear_model == ShearModel::Rotation;
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t b = 0; b < nb; ++b) {
    if (!m.bond_intact(static_cast<std::size_t>(b))) {
      m.f_n[b] = m.f_s[b] = 0.0;
      continue;
    }
    const auto i = static_cast<std::size_t>(m.bi[b]), j = static_cast<std::size_t>(m.bj[b]);
    const double dx = m.ax[b] + (m.ux[j] - m.ux[i]);
    const double dy = m.ay[b] + (m.uy[j] - m.uy[i]);
    const double len = std::sqrt(dx * dx + dy * dy);
    const double nx = dx / len, ny = dy / len;
    m.nx[b] = nx;
    m.ny[b] = ny;
    m.f_n[b] = m.k_n[b] * (len - m.rest_length[b]);
    if (rotation) {
      const double sx = -ny, sy = nx;
      const double du_s = dt * ((m.vx[j] - m.vx[i]) * sx + (m.vy[j] - m.vy[i]) * sy -
                                (m.radius[i] * m.omega[i] + m.radius[j] * m.omega[j]));
      m.f_s[b] += m.k_s[b] * du_s;
    } else {
      // u_s = (d/2) s0.(eps_i + eps_j).n0 = g : (eps_i + eps_j)
      m.u_s[b] = m.g_xx[b] * (m.eps_xx[i] + m.eps_xx[j]) + m.g_yy[b] * (m.eps_yy[i] + m.eps_yy[j]) +
                 2.0 * m.g_xy[b] * (m.eps_xy[i] + m.eps_xy[j]);
      m.f_s[b] = m.k_s[b] * m.u_s[b];
    }
  }
}

/// Pass C: W_i = S_i M_i^-1 with S_i = dE/d(eps_i): the local-strain shear springs
/// (sum over bonds of f_s (d/2) sym(s0 (x) n0)) and, in axisymmetric models, the hoop term
/// E_h = A b [(lambda + 2 mu) eps_tt^2 / 2 + lambda eps_tt (eps_rr + eps_zz)], eps_tt = u_r / b.
void compute_strain_conjugates(Model& m, bool shear_springs, bool hoop) {
  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    double sxx = 0, syy = 0, sxy = 0;
    if (shear_springs) {
      for (auto k = m.adj_offset[i]; k < m.adj_offset[i + 1]; ++k) {
        const auto b = static_cast<std::size_t>(m.adj_bond[k]);
        if (!m.bond_intact(b)) continue;
        const double fs = m.f_s[b];
        sxx += fs * m.g_xx[b];
        syy += fs * m.g_yy[b];
        sxy += fs * m.g_xy[b];
      }
    }
    if (hoop) {
      const double eps_tt = m.ux[i] / m.weight[i];
      const double c = m.cell_area[i] * m.weight[i] * m.hoop_lambda[i] * eps_tt;
      sxx += c;
      syy += c;
    }
    if (m.mirror_plane[i]) sxy = 0.0;  // the projection's adjoint (energy consistency)
    const double mxx = m.minv_xx[i], mxy = m.minv_xy[i], myy = m.minv_yy[i];
    m.w_xx[i] = sxx * mxx + sxy * mxy;
    m.w_xy[i] = sxx * mxy + sxy * myy;
    m.w_yx[i] = sxy * mxx + syy * mxy;
    m.w_yy[i] = sxy * mxy + syy * myy;
  }
}

/// Pass D: gather the forces on each disk. Pair forces (Eq. 3): the force on bi is
/// f_n n + f_s s (rotation model; local strain: f_n n only), the moment on both ends +r f_s.
/// Local-strain and hoop terms: F_i = sum_k (W_i + W_k) a_ik, the gradient of the energy
/// through the strains of i and of its neighbours ("stress divergence"); hoop: -A sigma_tt.
void gather_forces(Model& m, bool pair_shear, bool strain_terms, bool hoop) {
  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    double fx = 0, fy = 0, tq = 0;
    for (auto k = m.adj_offset[i]; k < m.adj_offset[i + 1]; ++k) {
      const auto b = static_cast<std::size_t>(m.adj_bond[k]);
      if (!m.bond_intact(b)) continue;
      const double s = m.adj_sign[k];
      const double nx = m.nx[b], ny = m.ny[b];
      double f_x = m.f_n[b] * nx, f_y = m.f_n[b] * ny;
      if (pair_shear) {
        f_x -= m.f_s[b] * ny;
        f_y += m.f_s[b] * nx;
        tq += m.radius[i] * m.f_s[b];
      }
      fx += s * f_x;
      fy += s * f_y;
      if (strain_terms) {
        const auto o = m.adj_other[k];
        const double ax = m.adj_ax[k], ay = m.adj_ay[k];
        const double wxx = m.w_xx[i] + m.w_xx[o], wxy = m.w_xy[i] + m.w_xy[o];
        const double wyx = m.w_yx[i] + m.w_yx[o], wyy = m.w_yy[i] + m.w_yy[o];
        fx += wxx * ax + wxy * ay;
        fy += wyx * ax + wyy * ay;
      }
    }
    if (hoop) {
      const double eps_tt = m.ux[i] / m.weight[i];
      const double sigma_tt = (m.hoop_lambda[i] + 2 * m.hoop_mu[i]) * eps_tt +
                              m.hoop_lambda[i] * (m.eps_xx[i] + m.eps_yy[i]);
      fx -= m.cell_area[i] * sigma_tt;
    }
    m.fx[i] = fx - m.wall_kx[i] * m.ux[i];
    m.fy[i] = fy - m.wall_ky[i] * m.uy[i];
    m.torque[i] = tq;
  }
}

}  // namespace

void compute_internal_forces(Model& m, double dt) {
  const bool local = m.shear_model == ShearModel::LocalStrain;
  const bool hoop = m.geometry == Geometry::Axisymmetric;
  if (local || hoop) compute_disk_strains(m);
  compute_bond_forces(m, dt);
  if (local || hoop) compute_strain_conjugates(m, local, hoop);
  gather_forces(m, !local, local || hoop, hoop);
}

double elastic_energy(const Model& m) {
  const bool local = m.shear_model == ShearModel::LocalStrain;
  double e = deterministic_sum(
      m.num_bonds(),
      [&](std::size_t b) {
        if (!m.bond_intact(b)) return 0.0;
        double eb = m.k_n[b] != 0 ? 0.5 * m.f_n[b] * m.f_n[b] / m.k_n[b] : 0.0;
        if (local) {
          eb += 0.5 * m.k_s[b] * m.u_s[b] * m.u_s[b];
        } else if (m.k_s[b] != 0) {
          eb += 0.5 * m.f_s[b] * m.f_s[b] / m.k_s[b];
        }
        return eb;
      },
      m.scratch);
  e += deterministic_sum(
      m.num_disks(),
      [&](std::size_t i) { return 0.5 * (m.wall_kx[i] * m.ux[i] * m.ux[i] + m.wall_ky[i] * m.uy[i] * m.uy[i]); },
      m.scratch);
  if (m.geometry == Geometry::Axisymmetric) {
    e += deterministic_sum(
        m.num_disks(),
        [&](std::size_t i) {
          const double eps_tt = m.ux[i] / m.weight[i];
          const double lam = m.hoop_lambda[i], mu = m.hoop_mu[i];
          return m.cell_area[i] * m.weight[i] *
                 ((lam + 2 * mu) * 0.5 * eps_tt * eps_tt + lam * eps_tt * (m.eps_xx[i] + m.eps_yy[i]));
        },
        m.scratch);
  }
  return e;
}

Stress disk_stress(const Model& m, std::size_t i) {
  // Love-Weber: sigma = 1/(A w) sum_c sym(x_c (x) f_c) with x_c = r n and f_c the force on i
  // (physics.md section 6); for either end of a bond this is r [f_n n n + f_s sym(n s)].
  Stress st;
  double sxx = 0, syy = 0, sxy = 0;
  for (auto k = m.adj_offset[i]; k < m.adj_offset[i + 1]; ++k) {
    const auto b = static_cast<std::size_t>(m.adj_bond[k]);
    if (m.f_n[b] == 0.0 && m.f_s[b] == 0.0) continue;
    const double nx = m.nx[b], ny = m.ny[b], sx = -ny, sy = nx;
    const double fn = m.f_n[b], fs = m.f_s[b];
    sxx += fn * nx * nx + fs * nx * sx;
    syy += fn * ny * ny + fs * ny * sy;
    sxy += fn * nx * ny + fs * 0.5 * (nx * sy + ny * sx);
  }
  // The bond to the mirror image (symmetry planes): tension -k u.N along N.
  sxx -= m.wall_kx[i] * m.ux[i] * m.wall_sx[i];
  syy -= m.wall_ky[i] * m.uy[i] * m.wall_sy[i];
  const double scale = m.radius[i] / (m.cell_area[i] * m.weight[i]);
  // Surface loads act on the disk at their own lever arms.
  const double ext = 1.0 / (m.cell_area[i] * m.weight[i]);
  st.xx = sxx * scale + m.ext_mxx[i] * ext;
  st.yy = syy * scale + m.ext_myy[i] * ext;
  st.xy = sxy * scale + m.ext_mxy[i] * ext;
  st.zz = m.nu_zz[i] * (st.xx + st.yy);
  if (m.geometry == Geometry::Axisymmetric) {
    const double eps_tt = m.ux[i] / m.weight[i];
    st.zz = (m.hoop_lambda[i] + 2 * m.hoop_mu[i]) * eps_tt + m.hoop_lambda[i] * (m.eps_xx[i] + m.eps_yy[i]);
    // The hoop term's share of the in-plane stresses: d/d(eps_rr) of lambda eps_tt eps_rr.
    st.xx += m.hoop_lambda[i] * eps_tt;
    st.yy += m.hoop_lambda[i] * eps_tt;
  }
  return st;
}

}  // namespace hexdem::solver
