// What one brittle break releases when the strain is carried across the change of fit
// (docs/model.md, "Energy at a break"): the disks keep their strains, the neighbours' springs
// keep their energy, and with the lattice at rest the release is exactly the energy the broken
// bond's springs stored, k_n delta^2 / 2 + k_s u_s^2 / 2 (an independent number: the bond's
// own springs), never less.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;

constexpr const char* kPlate = R"(units = "mm"
[case]
name = "plate"
geometry = "plane-strain"
thickness = 0.01
[mesh]
radius = 1.0e-3
angle = ANGLE
[[body]]
name = "plate"
material = 1
  [[body.shape]]
  type = "rectangle"
  min = [0.0, 0.0]
  max = [20.0, 20.0]
[[material]]
id = 1
name = "concrete"
density = 2400.0
E = 30e9
nu = 0.2
tensile_strength = 3e9
compressive_strength = 30e9
cohesion = 6e9
friction_angle = 30.0
[time]
end = 1e-6
)";

void check_break(const std::string& angle) {
  std::string text = kPlate;
  text.replace(text.find("ANGLE"), 5, angle);
  const Case c = parse_case(text, "plate.toml", ".");
  Solver s(c, mesh_case(c));
  Model m = s.model();  // a copy at rest: velocities 0, so no half-step term
  const double dt = s.dt();
  // A smooth, non-affine displacement field (an affine one has no local-strain shear).
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    const double x = m.x0[i] / 0.02, y = m.y0[i] / 0.02;
    m.ux[i] = 1e-6 * (x * x + 0.5 * std::sin(3 * y));
    m.uy[i] = 1e-6 * (x * y - 0.3 * std::cos(2 * x));
  }
  ASSERT_EQ(compute_internal_forces(m, dt), 0u);
  // An interior bond with two complete neighbourhoods.
  std::size_t b = m.num_bonds();
  for (std::size_t k = 0; k < m.num_bonds() && b == m.num_bonds(); ++k)
    if (m.initial_bonds[m.bi[k]] == 6 && m.initial_bonds[m.bj[k]] == 6 && std::abs(m.x0[m.bi[k]] - 0.01) < 0.003 &&
        std::abs(m.y0[m.bi[k]] - 0.01) < 0.003)
      b = k;
  ASSERT_LT(b, m.num_bonds());
  const auto i = static_cast<std::size_t>(m.bi[b]), j = static_cast<std::size_t>(m.bj[b]);
  const double stored = 0.5 * m.f_n[b] * m.f_n[b] / m.k_n[b] + 0.5 * m.f_s[b] * m.f_s[b] / m.k_s[b];
  ASSERT_GT(m.f_n[b], 0.0) << "the bond is stretched: its contact carries no force";
  const double eps_i[3] = {m.eps_xx[i], m.eps_yy[i], m.eps_xy[i]}, eps_j[3] = {m.eps_xx[j], m.eps_yy[j], m.eps_xy[j]};
  const double before = elastic_energy(m);
  m.newly_broken[b] = 2;  // tension
  ASSERT_EQ(settle_broken_bonds(m, dt), 1u);
  EXPECT_FALSE(m.bond_intact(b));
  // The disks' strains are carried over exactly.
  EXPECT_EQ(m.eps_xx[i], eps_i[0]);
  EXPECT_EQ(m.eps_yy[i], eps_i[1]);
  EXPECT_EQ(m.eps_xy[i], eps_i[2]);
  EXPECT_EQ(m.eps_xx[j], eps_j[0]);
  EXPECT_EQ(m.eps_yy[j], eps_j[1]);
  EXPECT_EQ(m.eps_xy[j], eps_j[2]);
  // The release is the bond's own springs' energy, and the model lost exactly that.
  EXPECT_NEAR(m.fracture_energy[b], stored, 1e-12 * stored) << angle;
  EXPECT_NEAR(before - elastic_energy(m), stored, 1e-9 * stored) << angle;
  // From now on the disks' strains follow their new fits: one more increment moves them.
  for (std::size_t k = 0; k < m.num_disks(); ++k) m.ux[k] += 1e-7 * m.y0[k] / 0.02;
  compute_internal_forces(m, dt);
  EXPECT_NE(m.eps_xy[i], eps_i[2]);
}

TEST(BreakEnergy, ABreakReleasesExactlyItsBondsEnergyAtEveryLatticeAngle) {
  for (const char* angle : {"0.0", "10.0", "30.0"}) check_break(angle);
}

}  // namespace
