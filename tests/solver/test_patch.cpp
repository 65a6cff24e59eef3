// Patch tests of the bonded lattice (physics.md sections 3, 4, 6): under an imposed
// homogeneous strain, interior disks are in equilibrium, and the Love-Weber stress of an
// interior disk gives back the input stiffness c11, c12, c22, c66.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "common/square_patch.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/solver/model.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;

/// Effective stiffness [c11, c12, c22, c66] measured from the Love-Weber stress at the centre
/// disk under three strain states; also returns the largest interior force relative to the
/// force scale (equilibrium).
struct Measured {
  std::array<double, 4> c{};
  double interior_force = 0;
};

Measured measure(const Material& mat, Geometry geometry, ShearModel model) {
  const double r = 0.5e-3;
  const meshing::Lattice lat = hexdem::testing::square_patch(r, 30);
  std::vector<BodyMaterial> bm(1);
  bm[0].material = &mat;
  bm[0].springs = spring_constants(mat.stiffness(geometry));
  Model m = build_model(lat, geometry, 1.0, model, bm);
  // The disk nearest the centre and the interior (two spacings from the edges).
  const double L = 30 * 2 * r, mid = 0.5 * L;
  std::size_t centre = 0;
  double best = 1e9;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    const double d = std::hypot(m.x0[i] - mid, m.y0[i] - mid);
    if (d < best) { best = d; centre = i; }
  }
  auto interior = [&](std::size_t i) {
    return m.x0[i] > 4 * r && m.x0[i] < L - 4 * r && m.y0[i] > 4 * r && m.y0[i] < L - 4 * r;
  };
  Measured out;
  const double e = 1e-5;
  const std::array<std::array<double, 3>, 3> strains{{{e, 0, 0}, {0, e, 0}, {0, 0, e}}};  // exx, eyy, exy
  std::array<Stress, 3> s{};
  for (int k = 0; k < 3; ++k) {
    const auto [exx, eyy, exy] = strains[k];
    for (std::size_t i = 0; i < m.num_disks(); ++i) {
      m.ux[i] = exx * m.x0[i] + exy * m.y0[i];
      m.uy[i] = exy * m.x0[i] + eyy * m.y0[i];
      m.theta[i] = 0.0;  // symmetric strain: no continuum rotation
      m.vx[i] = m.ux[i];  // rotation model: one "step" of size 1 from zero
      m.vy[i] = m.uy[i];
      m.omega[i] = 0.0;
    }
    std::fill(m.f_s.begin(), m.f_s.end(), 0.0);
    compute_internal_forces(m, 1.0);
    s[k] = disk_stress(m, centre);
    const double scale = mat.stiffness(geometry).c11 * e * 2 * r;  // a typical bond force
    for (std::size_t i = 0; i < m.num_disks(); ++i) {
      if (!interior(i)) continue;
      out.interior_force = std::max(out.interior_force, std::hypot(m.fx[i], m.fy[i]) / scale);
    }
  }
  // sigma_xx = c11 exx + c12 eyy, sigma_yy = c12 exx + c22 eyy, sigma_xy = 2 c66 exy.
  out.c = {s[0].xx / e, s[0].yy / e, s[1].yy / e, s[2].xy / (2 * e)};
  return out;
}

void expect_stiffness(const Measured& got, const Stiffness2D& want, double tol) {
  std::printf("%s: c11 %+.4f %%, c12 %+.4f %% (of c11), c22 %+.4f %%, c66 %+.4f %%, interior force %.2g\n",
              ::testing::UnitTest::GetInstance()->current_test_info()->name(),
              100 * (got.c[0] / want.c11 - 1), 100 * (got.c[1] - want.c12) / want.c11,
              100 * (got.c[2] / want.c22 - 1), 100 * (got.c[3] / want.c66 - 1), got.interior_force);
  EXPECT_NEAR(got.c[0], want.c11, tol * want.c11) << "c11";
  EXPECT_NEAR(got.c[1], want.c12, tol * want.c11) << "c12";
  EXPECT_NEAR(got.c[2], want.c22, tol * want.c22) << "c22";
  EXPECT_NEAR(got.c[3], want.c66, tol * want.c66) << "c66";
  EXPECT_LT(got.interior_force, 1e-9) << "interior disks are not in equilibrium";
}

Material isotropic(double E, double nu, double rho) {
  Material m;
  m.name = "iso";
  m.isotropic = true;
  m.E = E;
  m.nu = nu;
  m.density = rho;
  return m;
}

Material material_b() {
  Material m;
  m.name = "material-B";
  m.isotropic = false;
  m.c = {5.0961e9, 1.2256e9, 3.5359e9, 1.2198e9};
  m.density = 1244.0;
  return m;
}

TEST(PatchTest, IsotropicLocalStrainPlaneStress) {
  const Material mat = isotropic(30e9, 0.2, 2400);
  expect_stiffness(measure(mat, Geometry::PlaneStress, ShearModel::LocalStrain),
                   mat.stiffness(Geometry::PlaneStress), 0.005);
}

TEST(PatchTest, IsotropicLocalStrainPlaneStrainHighPoisson) {
  // nu = 0.45: beyond the rotation model's reach (k_s < 0 makes it unstable), exact here.
  const Material mat = isotropic(10e9, 0.45, 1000);
  expect_stiffness(measure(mat, Geometry::PlaneStrain, ShearModel::LocalStrain),
                   mat.stiffness(Geometry::PlaneStrain), 0.005);
}

TEST(PatchTest, IsotropicRotationModel) {
  const Material mat = isotropic(30e9, 0.2, 2400);
  expect_stiffness(measure(mat, Geometry::PlaneStress, ShearModel::Rotation),
                   mat.stiffness(Geometry::PlaneStress), 0.005);
}

TEST(PatchTest, MaterialBLocalStrain) {
  const Material mat = material_b();
  expect_stiffness(measure(mat, Geometry::PlaneStress, ShearModel::LocalStrain), mat.c, 0.005);
}

}  // namespace
