/// \file stability.cpp
/// Bloch-wave analysis of the infinite hexagonal lattice (physics.md sections 4-5). The
/// dynamical matrices are those of the independent reference script
/// (shared/reference/lattice_reference.py: dyn_rotation, dyn_local_strain), written in an
/// equivalent real form, on the same k-grid, so that the numbers agree to round-off.

#include "hexdem/solver/stability.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "hexdem/error.hpp"

namespace hexdem::solver {
namespace {

/// Relative tolerance of the stability test: stable if omega2_min >= -kTolerance omega2_max
/// (round-off of the eigensolver at k = 0, where the rigid-body modes have omega = 0).
constexpr double kTolerance = 1e-9;

/// One of the 6 bonds of an interior disk: unit vector n (i to j), s = (-n_y, n_x), and the
/// springs of its direction class (class 1 along the lattice axis, 0 and 180 degrees).
struct Bond {
  double nx, ny, sx, sy, kn, ks;
};

std::array<Bond, 6> bonds(const SpringConstants& K) {
  std::array<Bond, 6> out{};
  for (int b = 0; b < 6; ++b) {
    const double angle = b * std::numbers::pi / 3.0;
    const double nx = std::cos(angle), ny = std::sin(angle);
    const bool axial = b % 3 == 0;
    out[b] = {nx, ny, -ny, nx, axial ? K.kn1 : K.kn2, axial ? K.ks1 : K.ks2};
  }
  return out;
}

/// D += w beta beta^T. Written out by element: these small loops run 2304 times per analysis
/// and stay fast in unoptimised builds.
template <int N>
void add_outer(Eigen::Matrix<double, N, N>& D, const std::array<double, N>& beta, double w) {
  for (int a = 0; a < N; ++a)
    for (int c = 0; c < N; ++c) D(a, c) += w * beta[a] * beta[c];
}

// The dynamical matrices in real form. With the Bloch amplitude u and p = exp(i phi),
// phi = k . d n, a bond's elongation and shear are b . u with b carrying the factors (p - 1)
// and (1 + p); its energy is k |b . u|^2 / 2, so D = sum_bonds 0.5 k conj(b) b^T (each bond is
// shared by two disks). Multiplying b by the phase p^(-1/2) leaves conj(b) b^T unchanged and
// turns the factors into 2i sin(phi/2) and 2 cos(phi/2); scaling the spin amplitude by i (a
// unitary change of variables, which keeps the eigenvalues) then makes every b equal to i
// times a real vector beta, and D = sum_bonds 0.5 k beta beta^T is real symmetric. This is
// the same matrix as lattice_reference.py's complex Hermitian one, at a fraction of the cost.

/// Rotation (paper) model, Eqs. 1-4: dofs (ux, uy, theta). The shear spring sees
/// du_s = (u_j - u_i) . s - r (theta_i + theta_j).
Eigen::Matrix3d dyn_rotation(const std::array<Bond, 6>& nb, const std::array<double, 6>& phi,
                             double r) {
  Eigen::Matrix3d D = Eigen::Matrix3d::Zero();
  for (int b = 0; b < 6; ++b) {
    const Bond& bond = nb[b];
    const double two_sin = 2.0 * std::sin(0.5 * phi[b]), two_cos = 2.0 * std::cos(0.5 * phi[b]);
    add_outer<3>(D, {two_sin * bond.nx, two_sin * bond.ny, 0.0}, 0.5 * bond.kn);
    add_outer<3>(D, {two_sin * bond.sx, two_sin * bond.sy, -r * two_cos}, 0.5 * bond.ks);
  }
  return D;
}

/// Energy-consistent local-strain model (physics.md section 4): dofs (ux, uy). The shear
/// spring sees du_s = d s . (eps_i + eps_j)/2 . n with eps the least-squares strain of the
/// disk over its 6 bonds, grad u = sum_k (u_k - u_i) a_k^T / (3 d^2).
Eigen::Matrix2d dyn_local_strain(const std::array<Bond, 6>& nb, const std::array<double, 6>& phi,
                                 double d) {
  // grad u per unit amplitude of component c is U_c h^T with h = sum_k (p_k - 1) n_k / (3 d);
  // the bonds come in pairs +-n, so h = i g with g = sum_k sin(phi_k) n_k / (3 d), and the
  // strains are eps_c = i sym(U_c g^T).
  double gx = 0.0, gy = 0.0;
  for (int b = 0; b < 6; ++b) {
    gx += std::sin(phi[b]) * nb[b].nx;
    gy += std::sin(phi[b]) * nb[b].ny;
  }
  gx /= 3.0 * d;
  gy /= 3.0 * d;

  Eigen::Matrix2d D = Eigen::Matrix2d::Zero();
  for (int b = 0; b < 6; ++b) {
    const Bond& bond = nb[b];
    const double two_sin = 2.0 * std::sin(0.5 * phi[b]);
    // s . eps_c . n for eps_0 = [[gx, gy/2], [gy/2, 0]] and eps_1 = [[0, gx/2], [gx/2, gy]].
    const double sn0 = bond.sx * (gx * bond.nx + 0.5 * gy * bond.ny) + bond.sy * 0.5 * gy * bond.nx;
    const double sn1 = bond.sx * 0.5 * gx * bond.ny + bond.sy * (0.5 * gx * bond.nx + gy * bond.ny);
    // (eps_i + eps_j)/2 carries (1 + p)/2, i.e. cos(phi/2) after the phase.
    const double shear = d * std::cos(0.5 * phi[b]);
    add_outer<2>(D, {two_sin * bond.nx, two_sin * bond.ny}, 0.5 * bond.kn);
    add_outer<2>(D, {shear * sn0, shear * sn1}, 0.5 * bond.ks);
  }
  return D;
}

}  // namespace

BlochResult bloch_analysis(const SpringConstants& K, double rho, double r, ShearModel model,
                           int nk) {
  HEXDEM_VERIFY(rho > 0.0 && r > 0.0 && nk > 0, "bloch_analysis needs rho > 0, r > 0, nk > 0");
  const double d = 2.0 * r;
  const double m = rho * 2.0 * std::sqrt(3.0) * r * r;  // cell-area mass (Eq. 9's hexagon)
  const double inertia = 0.5 * m * r * r;
  const auto nb = bonds(K);

  // Reciprocal lattice vectors of the hexagonal lattice with spacing d.
  const double g = 2.0 * std::numbers::pi / d;
  const double b1x = g, b1y = -g / std::sqrt(3.0);
  const double b2x = 0.0, b2y = 2.0 * g / std::sqrt(3.0);

  // M^-1/2 D M^-1/2 is symmetric with the eigenvalues omega^2 of M^-1 D.
  const double scale_u = 1.0 / std::sqrt(m), scale_theta = 1.0 / std::sqrt(inertia);
  const Eigen::Vector3d scale3(scale_u, scale_u, scale_theta);
  double w2_min = std::numeric_limits<double>::infinity();
  double w2_max = 0.0;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver3;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver2;
  std::array<double, 6> phi{};
  for (int i = 0; i < nk; ++i) {
    for (int j = 0; j < nk; ++j) {
      const double fi = static_cast<double>(i) / nk, fj = static_cast<double>(j) / nk;
      const double kx = fi * b1x + fj * b2x, ky = fi * b1y + fj * b2y;
      for (int b = 0; b < 6; ++b) phi[b] = d * (kx * nb[b].nx + ky * nb[b].ny);
      double lo = 0.0, hi = 0.0;
      if (model == ShearModel::Rotation) {
        Eigen::Matrix3d D = dyn_rotation(nb, phi, r);
        for (int a = 0; a < 3; ++a)
          for (int c = 0; c < 3; ++c) D(a, c) *= scale3(a) * scale3(c);
        solver3.computeDirect(D, Eigen::EigenvaluesOnly);  // closed form, ascending
        lo = solver3.eigenvalues()(0);
        hi = solver3.eigenvalues()(2);
      } else {
        Eigen::Matrix2d D = dyn_local_strain(nb, phi, d);
        D *= 1.0 / m;
        solver2.computeDirect(D, Eigen::EigenvaluesOnly);
        lo = solver2.eigenvalues()(0);
        hi = solver2.eigenvalues()(1);
      }
      w2_min = std::min(w2_min, lo);
      w2_max = std::max(w2_max, hi);
    }
  }

  BlochResult result;
  result.omega2_min = w2_min;
  result.omega2_max = w2_max;
  result.stable = w2_min >= -kTolerance * w2_max;
  result.dt_critical =
      w2_max > 0.0 ? 2.0 / std::sqrt(w2_max) : std::numeric_limits<double>::infinity();
  // An unstable mode grows like exp(sqrt(-omega^2) t).
  result.growth_time = result.stable ? 0.0 : 1.0 / std::sqrt(-w2_min);
  return result;
}

double eq24_time_step(const SpringConstants& K, double rho, double r) {
  // Eq. 24: omega = sqrt(k_max / m) with the stiffest normal spring; dt = 2 / omega.
  const double m = rho * 2.0 * std::sqrt(3.0) * r * r;
  return 2.0 / std::sqrt(std::max(K.kn1, K.kn2) / m);
}

}  // namespace hexdem::solver
