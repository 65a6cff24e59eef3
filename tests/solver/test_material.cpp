// Materials and spring constants (physics.md section 3, the paper's Eqs. 6-14), checked
// against the independent reference script and the closed forms.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hexdem/error.hpp"
#include "hexdem/solver/material.hpp"
#include "reference_json.hpp"

namespace hexdem::solver {
namespace {

const double kSqrt3 = std::sqrt(3.0);

Material isotropic(double E, double nu, double rho) {
  Material m;
  m.name = "iso";
  m.density = rho;
  m.isotropic = true;
  m.E = E;
  m.nu = nu;
  return m;
}

/// The paper's "material B" (example 1), orthotropic in the lattice frame.
Material material_b() {
  Material m;
  m.name = "material-B";
  m.density = 1244.0;
  m.isotropic = false;
  m.c = {5.0961e9, 1.2256e9, 3.5359e9, 1.2198e9};
  return m;
}

Material concrete() {
  return isotropic(30e9, 0.2, 2400.0);
}
Material steel() {
  return isotropic(210e9, 0.3, 7850.0);
}

/// |a - b| <= tol |b|.
::testing::AssertionResult near_relative(double a, double b, double tol) {
  if (std::abs(a - b) <= tol * std::abs(b)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << a << " vs " << b << " (relative difference " << std::abs(a - b) / std::abs(b) << ")";
}

/// InputError message of m.validate(where), or "" if it passes.
std::string validation_message(const Material& m, const std::string& where) {
  try {
    m.validate(where);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

struct Row {
  const char* name;
  Material material;
  Geometry geometry;
};

TEST(Material, SpringConstantsMatchReference) {
  const test::Json& springs = test::lattice_reference()["springs_per_unit_thickness"];
  const Row rows[] = {{"material_B", material_b(), Geometry::PlaneStress},
                      {"concrete_plane_stress", concrete(), Geometry::PlaneStress},
                      {"concrete_plane_strain", concrete(), Geometry::PlaneStrain},
                      {"steel_plane_stress", steel(), Geometry::PlaneStress},
                      {"steel_plane_strain", steel(), Geometry::PlaneStrain}};
  for (const Row& row : rows) {
    SCOPED_TRACE(row.name);
    const SpringConstants k = spring_constants(row.material.stiffness(row.geometry));
    const test::Json& ref = springs[row.name];
    EXPECT_TRUE(near_relative(k.kn1, ref["kn1"].num(), 1e-9));
    EXPECT_TRUE(near_relative(k.kn2, ref["kn2"].num(), 1e-9));
    EXPECT_TRUE(near_relative(k.ks1, ref["ks1"].num(), 1e-9));
    EXPECT_TRUE(near_relative(k.ks2, ref["ks2"].num(), 1e-9));
  }
}

TEST(Material, SpringConstantsMatchPrintedTable) {
  // physics.md section 4 and the reference script's printed table [GPa].
  const SpringConstants b = spring_constants(material_b().stiffness(Geometry::PlaneStress));
  EXPECT_NEAR(b.kn1 / 1e9, 4.1002, 5e-5);
  EXPECT_NEAR(b.kn2 / 1e9, 2.7491, 5e-5);
  EXPECT_NEAR(b.ks1 / 1e9, 0.1426, 5e-5);
  EXPECT_NEAR(b.ks2 / 1e9, -0.0813, 5e-5);
  const SpringConstants s = spring_constants(steel().stiffness(Geometry::PlaneStrain));
  EXPECT_NEAR(s.kn1 / 1e9, 233.1607, 5e-5);
  EXPECT_NEAR(s.ks1 / 1e9, -46.6321, 5e-5);
}

TEST(Material, IsotropicPlaneStressClosedForm) {
  // Eq. 14: k_n = sqrt(3)/3 E/(1-nu), k_s = sqrt(3)/3 (1-3nu) E/(1-nu^2), the same in all
  // three bond directions.
  for (const Material& m : {concrete(), steel(), isotropic(70e9, 0.33, 2700.0)}) {
    const SpringConstants k = spring_constants(m.stiffness(Geometry::PlaneStress));
    const double kn = kSqrt3 / 3.0 * m.E / (1.0 - m.nu);
    const double ks = kSqrt3 / 3.0 * (1.0 - 3.0 * m.nu) * m.E / (1.0 - m.nu * m.nu);
    EXPECT_TRUE(near_relative(k.kn1, kn, 1e-12));
    EXPECT_TRUE(near_relative(k.kn2, kn, 1e-12));
    EXPECT_TRUE(near_relative(k.ks1, ks, 1e-12));
    EXPECT_TRUE(near_relative(k.ks2, ks, 1e-12));
  }
}

TEST(Material, IsotropicPlaneStrainClosedForm) {
  // k_n = sqrt(3)/3 E/((1+nu)(1-2nu)), k_s = sqrt(3)/3 (1-4nu) E/((1+nu)(1-2nu)); the
  // axisymmetric meridian plane uses the same constants.
  for (const Material& m : {concrete(), steel(), isotropic(70e9, 0.1, 2700.0)}) {
    for (const Geometry g : {Geometry::PlaneStrain, Geometry::Axisymmetric}) {
      const SpringConstants k = spring_constants(m.stiffness(g));
      const double f = m.E / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu));
      EXPECT_TRUE(near_relative(k.kn1, kSqrt3 / 3.0 * f, 1e-12));
      EXPECT_TRUE(near_relative(k.kn2, kSqrt3 / 3.0 * f, 1e-12));
      EXPECT_TRUE(near_relative(k.ks1, kSqrt3 / 3.0 * (1.0 - 4.0 * m.nu) * f, 1e-12));
      EXPECT_TRUE(near_relative(k.ks2, kSqrt3 / 3.0 * (1.0 - 4.0 * m.nu) * f, 1e-12));
    }
  }
}

TEST(Material, StiffnessPerGeometry) {
  const Material m = concrete();
  const Stiffness2D ps = m.stiffness(Geometry::PlaneStress);
  EXPECT_DOUBLE_EQ(ps.c11, 30e9 / (1.0 - 0.04));
  EXPECT_DOUBLE_EQ(ps.c22, ps.c11);
  EXPECT_DOUBLE_EQ(ps.c12, 0.2 * ps.c11);
  EXPECT_DOUBLE_EQ(ps.c66, 30e9 / 2.4);
  const Stiffness2D pe = m.stiffness(Geometry::PlaneStrain);
  EXPECT_DOUBLE_EQ(pe.c11, 30e9 * 0.8 / (1.2 * 0.6));
  EXPECT_DOUBLE_EQ(pe.c22, pe.c11);
  EXPECT_DOUBLE_EQ(pe.c12, 30e9 * 0.2 / (1.2 * 0.6));
  EXPECT_DOUBLE_EQ(pe.c66, 30e9 / 2.4);
  const Stiffness2D ax = m.stiffness(Geometry::Axisymmetric);
  EXPECT_EQ(ax.c11, pe.c11);
  EXPECT_EQ(ax.c12, pe.c12);
  EXPECT_EQ(ax.c66, pe.c66);
  // An orthotropic c is used as given in every geometry.
  for (const Geometry g : {Geometry::PlaneStress, Geometry::PlaneStrain}) {
    const Stiffness2D c = material_b().stiffness(g);
    EXPECT_EQ(c.c11, 5.0961e9);
    EXPECT_EQ(c.c12, 1.2256e9);
    EXPECT_EQ(c.c22, 3.5359e9);
    EXPECT_EQ(c.c66, 1.2198e9);
  }
}

TEST(Material, LameConstants) {
  const Material m = steel();
  const Stiffness2D pe = m.stiffness(Geometry::PlaneStrain);
  EXPECT_TRUE(near_relative(m.lame_lambda() + 2.0 * m.lame_mu(), pe.c11, 1e-14));
  EXPECT_TRUE(near_relative(m.lame_lambda(), pe.c12, 1e-14));
  EXPECT_TRUE(near_relative(m.lame_mu(), pe.c66, 1e-14));
  EXPECT_TRUE(near_relative(m.lame_mu(), 210e9 / 2.6, 1e-14));
}

TEST(Material, ShearSpringSigns) {
  // k_s1 = 2 sqrt(3)/3 (3 c66 - c22): positive for material B (the paper prints it with the
  // opposite sign); k_s2 < 0 there, and steel in plane strain has k_s < 0.
  const Stiffness2D cb = material_b().stiffness(Geometry::PlaneStress);
  const SpringConstants b = spring_constants(cb);
  EXPECT_GT(b.ks1, 0.0);
  EXPECT_TRUE(near_relative(b.ks1, 2.0 * kSqrt3 / 3.0 * (3.0 * cb.c66 - cb.c22), 1e-14));
  EXPECT_LT(b.ks2, 0.0);
  // Necessary condition of the rotation model (physics.md section 4):
  // k_s1 + 2 k_s2 = 2 sqrt(3) (c66 - c12).
  EXPECT_TRUE(near_relative(b.ks1 + 2.0 * b.ks2, 2.0 * kSqrt3 * (cb.c66 - cb.c12), 1e-9));
  EXPECT_LT(b.ks1 + 2.0 * b.ks2, 0.0);
  EXPECT_GT(spring_constants(concrete().stiffness(Geometry::PlaneStress)).ks1, 0.0);
  EXPECT_LT(spring_constants(steel().stiffness(Geometry::PlaneStrain)).ks1, 0.0);
  EXPECT_GT(spring_constants(steel().stiffness(Geometry::PlaneStress)).ks1, 0.0);
}

TEST(Material, ValidateAcceptsGoodMaterials) {
  EXPECT_NO_THROW(material_b().validate("case.toml:3: material[0]"));
  EXPECT_NO_THROW(concrete().validate("case.toml:3: material[0]"));
  EXPECT_NO_THROW(isotropic(1e9, -0.9, 1.0).validate("x"));
  EXPECT_NO_THROW(isotropic(1e9, 0.49, 1.0).validate("x"));
  EXPECT_FALSE(steel().check().has_value());
}

TEST(Material, ValidateRejectsBadValues) {
  const std::string where = "case.toml:7: material[1]";
  Material m = concrete();
  m.density = -1.0;
  EXPECT_EQ(validation_message(m, where), where + ": density: must be > 0 [kg/m^3] (got -1)");
  m = concrete();
  m.E = 0.0;
  EXPECT_EQ(validation_message(m, where), where + ": E: must be > 0 [Pa] (got 0)");
  m = concrete();
  m.nu = 0.5;
  EXPECT_EQ(validation_message(m, where), where + ": nu: must lie in (-1, 0.5) (got 0.5)");
  m.nu = -1.0;
  EXPECT_EQ(validation_message(m, where), where + ": nu: must lie in (-1, 0.5) (got -1)");
  m.nu = std::nan("");
  EXPECT_NE(validation_message(m, where).find(": nu: "), std::string::npos);

  m = material_b();
  m.c.c11 = -5e9;
  EXPECT_EQ(validation_message(m, where), where + ": c11: must be > 0 [Pa] (got -5e+09)");
  m = material_b();
  m.c.c22 = 0.0;
  EXPECT_EQ(validation_message(m, where), where + ": c22: must be > 0 [Pa] (got 0)");
  m = material_b();
  m.c.c66 = -1.0;
  EXPECT_EQ(validation_message(m, where), where + ": c66: must be > 0 [Pa] (got -1)");
  m = material_b();
  m.c.c12 = 5e9;  // c12^2 > c11 c22
  const std::string message = validation_message(m, where);
  EXPECT_EQ(message.rfind(where + ": c12: stiffness is not positive definite", 0), 0u) << message;
  EXPECT_NE(message.find("(got 5e+09)"), std::string::npos) << message;
  const auto issue = m.check();
  ASSERT_TRUE(issue.has_value());
  EXPECT_EQ(issue->key, "c12");
}

TEST(Material, Names) {
  EXPECT_STREQ(geometry_name(Geometry::PlaneStress), "plane-stress");
  EXPECT_STREQ(geometry_name(Geometry::PlaneStrain), "plane-strain");
  EXPECT_STREQ(geometry_name(Geometry::Axisymmetric), "axisymmetric");
  EXPECT_STREQ(shear_model_name(ShearModel::Rotation), "rotation");
  EXPECT_STREQ(shear_model_name(ShearModel::LocalStrain), "local-strain");
}

}  // namespace
}  // namespace hexdem::solver
