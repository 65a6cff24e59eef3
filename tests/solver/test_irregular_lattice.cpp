// The solver on an irregular lattice ([mesh] jitter; docs/model.md, "Irregular lattice"):
// its elastic stiffness after the disks relax, the local strain of a disk whose bonds nearly
// line up, and where the disks of a broken bond touch.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "common/square_patch.hpp"
#include "hexdem/meshing/lattice_jitter.hpp"
#include "hexdem/solver/model.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;

constexpr double kR = 0.5e-3;
constexpr int kCells = 40;  // the patch is kCells x 2r square

meshing::Lattice square_lattice(double jitter, std::uint64_t seed, double angle_deg) {
  meshing::Lattice lat = hexdem::testing::square_patch(kR, kCells, angle_deg);
  meshing::jitter_lattice(lat, jitter, seed);
  return lat;
}

Material concrete() {
  Material m;
  m.name = "concrete";
  m.isotropic = true;
  m.E = 30e9;
  m.nu = 0.2;
  m.density = 2400;
  return m;
}

Model model_of(const meshing::Lattice& lat, const Material& mat) {
  std::vector<BodyMaterial> bm(1);
  bm[0].material = &mat;
  bm[0].springs = spring_constants(mat.stiffness(Geometry::PlaneStress));
  return build_model(lat, Geometry::PlaneStress, 1.0, ShearModel::LocalStrain, bm);
}

/// The patch's stiffness [c11, c12, c22, c66] after its disks relax: the disks within 3r of
/// the edge follow a homogeneous strain, the others are found in static equilibrium (conjugate
/// gradients on the force kernel, which is linear at this strain), and the stress is the
/// area-weighted mean of the disks' stresses more than 8r inside the edge.
std::array<double, 4> relaxed_stiffness(const meshing::Lattice& lat, const Material& mat) {
  Model m = model_of(lat, mat);
  const std::size_t n = m.num_disks();
  const double L = kCells * 2 * kR;
  const auto inside = [&](std::size_t i, double d) {
    return m.x0[i] > d && m.x0[i] < L - d && m.y0[i] > d && m.y0[i] < L - d;
  };
  std::vector<std::size_t> free;
  for (std::size_t i = 0; i < n; ++i)
    if (inside(i, 3 * kR)) free.push_back(i);
  const std::size_t nf = 2 * free.size();
  // -F at displacement u on the free disks plus `base` (the boundary's), restricted to them.
  std::vector<double> bx(n), by(n);
  const auto residual = [&](const std::vector<double>& u, std::vector<double>& out, bool with_base) {
    for (std::size_t i = 0; i < n; ++i) {
      m.ux[i] = with_base ? bx[i] : 0.0;
      m.uy[i] = with_base ? by[i] : 0.0;
    }
    for (std::size_t k = 0; k < free.size(); ++k) {
      m.ux[free[k]] += u[2 * k];
      m.uy[free[k]] += u[2 * k + 1];
    }
    compute_internal_forces(m, 1.0);
    for (std::size_t k = 0; k < free.size(); ++k) {
      out[2 * k] = -m.fx[free[k]];
      out[2 * k + 1] = -m.fy[free[k]];
    }
  };
  const double e = 1e-6;
  const std::array<std::array<double, 3>, 3> strains{{{e, 0, 0}, {0, e, 0}, {0, 0, e}}};
  std::array<Stress, 3> s{};
  for (int c = 0; c < 3; ++c) {
    const auto [exx, eyy, exy] = strains[c];
    for (std::size_t i = 0; i < n; ++i) {
      const bool held = !inside(i, 3 * kR);
      bx[i] = held ? exx * m.x0[i] + exy * m.y0[i] : 0.0;
      by[i] = held ? exy * m.x0[i] + eyy * m.y0[i] : 0.0;
    }
    // K u = b with b = F(boundary only) (the force the held disks put on the free ones).
    std::vector<double> u(nf, 0.0), r(nf), p(nf), Ap(nf), zero(nf, 0.0);
    residual(zero, r, true);
    for (double& v : r) v = -v;
    p = r;
    double rr = 0, rr0;
    for (double v : r) rr += v * v;
    rr0 = rr;
    for (int it = 0; it < 4000 && rr > 1e-24 * rr0; ++it) {
      // A p from the kernel at a small displacement (it is linear in u to round-off there).
      double pn = 0;
      for (double v : p) pn = std::max(pn, std::abs(v));
      const double scale = 1e-9 / pn;
      std::vector<double> ps(nf);
      for (std::size_t k = 0; k < nf; ++k) ps[k] = p[k] * scale;
      residual(ps, Ap, false);
      for (double& v : Ap) v /= scale;
      double pAp = 0;
      for (std::size_t k = 0; k < nf; ++k) pAp += p[k] * Ap[k];
      const double alpha = rr / pAp;
      double rr_new = 0;
      for (std::size_t k = 0; k < nf; ++k) {
        u[k] += alpha * p[k];
        r[k] -= alpha * Ap[k];
        rr_new += r[k] * r[k];
      }
      for (std::size_t k = 0; k < nf; ++k) p[k] = r[k] + (rr_new / rr) * p[k];
      rr = rr_new;
    }
    EXPECT_LT(rr, 1e-16 * rr0) << "conjugate gradients did not converge";
    std::vector<double> f(nf);
    residual(u, f, true);  // sets the relaxed state and its forces
    double sxx = 0, syy = 0, sxy = 0, area = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!inside(i, 8 * kR)) continue;
      const Stress si = disk_stress(m, i);
      sxx += si.xx * m.cell_area[i];
      syy += si.yy * m.cell_area[i];
      sxy += si.xy * m.cell_area[i];
      area += m.cell_area[i];
    }
    s[c] = {sxx / area, syy / area, sxy / area, 0.0};
  }
  return {s[0].xx / e, s[0].yy / e, s[1].yy / e, s[2].xy / (2 * e)};
}

// The regular lattice gives the input stiffness; the irregular one (f = 0.25 and the largest,
// 0.3, at two angles and two seeds) is softer by its disks' relaxation, isotropic: measured
// 1.1-1.5 % (f = 0.25) and 1.6-2.2 % (0.3) below the input, bounded here at 2.5 % and 3.5 %
// (docs/model.md, "Irregular lattice").
TEST(IrregularLattice, RelaxedStiffnessStaysNearTheInputAndIsotropic) {
  const Material mat = concrete();
  const Stiffness2D want = mat.stiffness(Geometry::PlaneStress);
  struct Row { double jitter; std::uint64_t seed; double angle; double tol; };
  for (const Row& row : {Row{0.0, 1, 0.0, 0.005}, Row{0.25, 1, 0.0, 0.025}, Row{0.25, 2, 17.0, 0.025},
                         Row{0.3, 3, 30.0, 0.035}}) {
    const std::array<double, 4> c = relaxed_stiffness(square_lattice(row.jitter, row.seed, row.angle), mat);
    std::printf("jitter %.2f seed %d angle %4.1f: c11 %+.2f %%, c12 %+.2f %% (of c11), c22 %+.2f %%, c66 %+.2f %%\n",
                row.jitter, static_cast<int>(row.seed), row.angle, 100 * (c[0] / want.c11 - 1),
                100 * (c[1] - want.c12) / want.c11, 100 * (c[2] / want.c22 - 1), 100 * (c[3] / want.c66 - 1));
    EXPECT_NEAR(c[0], want.c11, row.tol * want.c11) << "jitter " << row.jitter;
    EXPECT_NEAR(c[1], want.c12, row.tol * want.c11) << "jitter " << row.jitter;
    EXPECT_NEAR(c[2], want.c22, row.tol * want.c22) << "jitter " << row.jitter;
    EXPECT_NEAR(c[3], want.c66, row.tol * want.c66) << "jitter " << row.jitter;
    // Isotropy: c11 and c22 alike, and c66 = (c11 - c12) / 2, to 0.5 % of c11.
    EXPECT_NEAR(c[0], c[2], 0.005 * want.c11) << "jitter " << row.jitter;
    EXPECT_NEAR(c[3], 0.5 * (c[0] - c[1]), 0.005 * want.c11) << "jitter " << row.jitter;
  }
}

/// Three bonds from a disk at the origin to disks at 2r in the given directions [deg].
Model star(const Material& mat, std::initializer_list<double> degrees) {
  meshing::Lattice lat;
  lat.body_names = {"star"};
  lat.body_region_area = {1.0};
  const auto add = [&lat](double x, double y) {
    lat.x.push_back(x);
    lat.y.push_back(y);
    lat.radius.push_back(kR);
    lat.cell_area.push_back(2 * std::sqrt(3.0) * kR * kR);
    lat.cell_cx.push_back(x);
    lat.cell_cy.push_back(y);
    lat.kind.push_back(0);
    lat.body.push_back(0);
    lat.material.push_back(1);
  };
  add(0, 0);
  std::int32_t k = 1;
  for (const double d : degrees) {
    const double a = d * std::numbers::pi / 180;
    add(2 * kR * std::cos(a), 2 * kR * std::sin(a));
    lat.bond_i.push_back(0);
    lat.bond_j.push_back(k++);
    lat.bond_class.push_back(1);
    lat.bond_on_edge.push_back(0);
  }
  lat.set_offset = {0};
  Model m = model_of(lat, mat);
  // The outer disks have one bond each and so no strain of their own, which takes them out of
  // the centre's fit; here they count, to test the centre's fit alone.
  std::fill(m.strain.ok.begin(), m.strain.ok.end(), 1);
  update_strain_matrix(m, 0);
  return m;
}

// A disk whose bonds nearly line up has no local strain (its fit would be nearly singular);
// two bonds 60 degrees apart, as on a regular lattice, give one.
TEST(IrregularLattice, BondsNearlyInALineGiveNoLocalStrain) {
  const Material mat = concrete();
  EXPECT_NE(star(mat, {0, 60}).strain.minv_xx[0], 0.0);
  EXPECT_NE(star(mat, {0, 140}).strain.minv_xx[0], 0.0);  // 40 degrees off a line
  EXPECT_EQ(star(mat, {0, 150}).strain.minv_xx[0], 0.0);  // 30 degrees off a line
  EXPECT_EQ(star(mat, {0, 177}).strain.minv_xx[0], 0.0);
  EXPECT_EQ(star(mat, {0, 180}).strain.minv_xx[0], 0.0);
  EXPECT_NE(star(mat, {0, 177, 60}).strain.minv_xx[0], 0.0);
}

// The disks of a broken bond touch at the smaller of their rest length and r_i + r_j on an
// irregular lattice (none is pushed apart when its bond breaks), at r_i + r_j on a regular one.
TEST(IrregularLattice, BrokenBondsTouchAtTheRestLengthOrTheRadii) {
  const Material mat = concrete();
  const Model regular = model_of(square_lattice(0.0, 1, 0.0), mat);
  EXPECT_FALSE(regular.touch_at_rest);
  const Model m = model_of(square_lattice(0.25, 1, 0.0), mat);
  ASSERT_TRUE(m.touch_at_rest);
  std::size_t shorter = 0, longer = 0;
  for (std::size_t b = 0; b < m.num_bonds(); ++b) {
    const double sum = m.radius[m.bi[b]] + m.radius[m.bj[b]];
    EXPECT_EQ(m.touch(b), std::min(m.rest(b), sum));
    shorter += m.rest(b) < sum;
    longer += m.rest(b) > sum;
  }
  // About half the bonds of each kind.
  EXPECT_GT(shorter, m.num_bonds() / 3);
  EXPECT_GT(longer, m.num_bonds() / 3);
}

}  // namespace
