// What one brittle break releases when the strain is carried across the change of fit
// (docs/model.md, "Energy at a break"): the disks keep their strains, the neighbours' springs
// keep their energy, and with the lattice at rest the release is exactly the energy the broken
// bond's springs stored, k_n delta^2 / 2 + k_s u_s^2 / 2 (an independent number: the bond's
// own springs), never less.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/solver.hpp"

#include "common/plate_impact.hpp"

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

/// A smooth, non-affine displacement field (an affine one has no local-strain shear).
void deform(Model& m) {
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    const double x = m.x0[i] / 0.02, y = m.y0[i] / 0.02;
    m.ux[i] = 1e-6 * (x * x + 0.5 * std::sin(3 * y));
    m.uy[i] = 1e-6 * (x * y - 0.3 * std::cos(2 * x));
  }
}

void check_break(const std::string& angle) {
  std::string text = kPlate;
  text.replace(text.find("ANGLE"), 5, angle);
  const Case c = parse_case(text, "plate.toml", ".");
  Solver s(c, mesh_case(c));
  Model m = s.model();  // a copy at rest: velocities 0, so no half-step term
  const double dt = s.dt();
  deform(m);
  ASSERT_EQ(compute_internal_forces(m, dt), 0u);
  // An interior bond with two complete neighbourhoods.
  std::size_t b = m.num_bonds();
  for (std::size_t k = 0; k < m.num_bonds() && b == m.num_bonds(); ++k)
    if (m.initial_bonds(m.bi[k]) == 6 && m.initial_bonds(m.bj[k]) == 6 && std::abs(m.x0[m.bi[k]] - 0.01) < 0.003 &&
        std::abs(m.y0[m.bi[k]] - 0.01) < 0.003)
      b = k;
  ASSERT_LT(b, m.num_bonds());
  const auto i = static_cast<std::size_t>(m.bi[b]), j = static_cast<std::size_t>(m.bj[b]);
  const double stored = 0.5 * m.f_n[b] * m.f_n[b] / m.kn(b) + 0.5 * m.f_s[b] * m.f_s[b] / m.ks(b);
  ASSERT_GT(m.f_n[b], 0.0) << "the bond is stretched: its contact carries no force";
  const double eps_i[3] = {m.strain.eps_xx[i], m.strain.eps_yy[i], m.strain.eps_xy[i]}, eps_j[3] = {m.strain.eps_xx[j], m.strain.eps_yy[j], m.strain.eps_xy[j]};
  const double before = elastic_energy(m);
  m.newly_broken[b] = 2;  // tension
  ASSERT_EQ(settle_broken_bonds(m, dt), 1u);
  EXPECT_FALSE(m.bond_intact(b));
  // The disks' strains are carried over exactly.
  EXPECT_EQ(m.strain.eps_xx[i], eps_i[0]);
  EXPECT_EQ(m.strain.eps_yy[i], eps_i[1]);
  EXPECT_EQ(m.strain.eps_xy[i], eps_i[2]);
  EXPECT_EQ(m.strain.eps_xx[j], eps_j[0]);
  EXPECT_EQ(m.strain.eps_yy[j], eps_j[1]);
  EXPECT_EQ(m.strain.eps_xy[j], eps_j[2]);
  // The release is the bond's own springs' energy, and the model lost exactly that.
  EXPECT_NEAR(m.bond_fracture_energy(b), stored, 1e-12 * stored) << angle;
  EXPECT_NEAR(before - elastic_energy(m), stored, 1e-9 * stored) << angle;
  // From now on the disks' strains follow their new fits: one more increment moves them.
  for (std::size_t k = 0; k < m.num_disks(); ++k) m.ux[k] += 1e-7 * m.y0[k] / 0.02;
  compute_internal_forces(m, dt);
  EXPECT_NE(m.strain.eps_xy[i], eps_i[2]);
}

TEST(BreakEnergy, ABreakReleasesExactlyItsBondsEnergyAtEveryLatticeAngle) {
  for (const char* angle : {"0.0", "10.0", "30.0"}) check_break(angle);
}

TEST(BreakEnergy, ADiskThatLosesItsFitKeepsItsStrainAndEachBreakReleasesItsBondsEnergy) {
  std::string text = kPlate;
  text.replace(text.find("ANGLE"), 5, "10.0");
  const Case c = parse_case(text, "plate.toml", ".");
  Solver s(c, mesh_case(c));
  Model m = s.model();
  const double dt = s.dt();
  deform(m);
  ASSERT_EQ(compute_internal_forces(m, dt), 0u);
  std::size_t i = m.num_disks();
  for (std::size_t k = 0; k < m.num_disks() && i == m.num_disks(); ++k)
    if (m.initial_bonds(k) == 6 && std::abs(m.x0[k] - 0.01) < 0.003 && std::abs(m.y0[k] - 0.01) < 0.003) i = k;
  ASSERT_LT(i, m.num_disks());
  // Break five of its six bonds, one at a time; the last two breaks leave it without a fit.
  int broken = 0;
  for (auto k = m.adj_offset[i]; k < m.adj_offset[i + 1] && broken < 5; ++k, ++broken) {
    const auto b = m.adj_bond(k);
    const double stored = 0.5 * m.f_n[b] * m.f_n[b] / m.kn(b) + 0.5 * m.f_s[b] * m.f_s[b] / m.ks(b);
    const bool stretched_now = m.f_n[b] > 0;
    const double eps[3] = {m.strain.eps_xx[i], m.strain.eps_yy[i], m.strain.eps_xy[i]};
    const double before = elastic_energy(m);
    m.newly_broken[b] = 2;
    ASSERT_EQ(settle_broken_bonds(m, dt), 1u);
    // A stretched bond releases all its springs held; one in compression leaves its overlap's
    // energy to the contact that replaces it. Either way the model loses exactly the release.
    if (stretched_now) {
      EXPECT_NEAR(m.bond_fracture_energy(b), stored, 1e-12 * stored) << "break " << broken;
    }
    EXPECT_NEAR(before - elastic_energy(m), m.bond_fracture_energy(b), 1e-9 * std::max(stored, 1e-3 * before))
        << "break " << broken;
    EXPECT_GE(m.bond_fracture_energy(b), 0.0);
    EXPECT_LE(m.bond_fracture_energy(b), stored * (1 + 1e-12));
    EXPECT_EQ(m.strain.eps_xx[i], eps[0]);
    EXPECT_EQ(m.strain.eps_yy[i], eps[1]);
    EXPECT_EQ(m.strain.eps_xy[i], eps[2]);
  }
  EXPECT_EQ(m.strain.minv_xx[i], 0.0) << "one bond left: no fit";
  EXPECT_EQ(m.strain.minv_yy[i], 0.0);
  // Frozen: a further displacement of its neighbours does not move it.
  const double frozen = m.strain.eps_xx[i];
  for (std::size_t k = 0; k < m.num_disks(); ++k) m.ux[k] += 1e-7 * m.y0[k] / 0.02;
  compute_internal_forces(m, dt);
  EXPECT_EQ(m.strain.eps_xx[i], frozen);
}

// The issue's reproducer, a steel disk at 50 m/s on a concrete plate with strengths, at
// r = 1 mm: the integrator's share of the breaks halves with the step while the fracture
// energy stays. The contacts keep their stiffness at both steps: the cap is
// m_eff (resolution / dt_c)^2 with dt_c the default step.
struct ImpactResult {
  double fracture = 0, break_kinetic = 0, max_error = 0, min_bond = 0;
};

ImpactResult impact(double safety, bool softening) {
  std::string text = hexdem::testing::plate_impact_case("", softening ? "fracture_energy = 100.0\n" : "");
  // 0.225 / dt_c, dt_c = 0.9 x critical, is the cap 0.2 / dt at safety 0.8: the contacts'
  // stiffness refers to the default step whatever the step used.
  text += "resolution = 0.225\n[time]\nend = 80e-6\nsafety = " + std::to_string(safety) + "\n";
  const Case c = parse_case(text, "impact.toml", ".");
  Solver s(c, mesh_case(c));
  ImpactResult r;
  for (std::int64_t n = 0; n <= s.total_steps(); ++n) {
    if (!s.advance(true)) return r;
    r.max_error = std::max(r.max_error, std::abs(s.energy().relative_error()));
  }
  r.fracture = s.energy().fracture;
  r.break_kinetic = s.energy().break_kinetic;
  for (std::size_t b = 0; b < s.model().num_bonds(); ++b) r.min_bond = std::min(r.min_bond, s.model().bond_fracture_energy(b));
  return r;
}

TEST(BreakEnergy, TheIntegratorsShareOfBreaksIsFirstOrderInTheStep) {
  // Which bond breaks first can change with the step, and with it the later cracks: over
  // safety 0.1-0.8 the softening plate's fracture energy scatters by +-15 % around 0.116 J with
  // no trend (docs/validation.md, "Convergence in the time step"). The fracture energy is
  // therefore compared as the mean over four coarse steps against the mean over four fine
  // ones; the integrator's share of the breaks (break_kinetic) is first order in the step on
  // every run and is compared run against run.
  const double coarse_safety[] = {0.8, 0.7, 0.6, 0.5}, fine_safety[] = {0.4, 0.35, 0.3, 0.25};
  for (bool softening : {false, true}) {
    double coarse_mean = 0, fine_mean = 0;
    for (int k = 0; k < 4; ++k) {
      const ImpactResult coarse = impact(coarse_safety[k], softening), fine = impact(fine_safety[k], softening);
      std::printf("%s: fracture %.4e / %.4e J, break_kinetic %+.3e / %+.3e J, max |Err| %.2e / %.2e (safety %.2f / %.2f)\n",
                  softening ? "softening" : "brittle", coarse.fracture, fine.fracture, coarse.break_kinetic,
                  fine.break_kinetic, coarse.max_error, fine.max_error, coarse_safety[k], fine_safety[k]);
      ASSERT_GT(coarse.fracture, 0.0);
      EXPECT_GE(coarse.min_bond, 0.0);
      EXPECT_GE(fine.min_bond, 0.0);
      const double ratio = fine.break_kinetic / coarse.break_kinetic;
      EXPECT_GT(ratio, 0.3) << "first order: about 1/2";
      EXPECT_LT(ratio, 0.7) << "first order: about 1/2";
      EXPECT_LT(std::abs(fine.break_kinetic), 0.05 * fine.fracture);
      coarse_mean += 0.25 * coarse.fracture;
      fine_mean += 0.25 * fine.fracture;
    }
    EXPECT_NEAR(fine_mean, coarse_mean, 0.1 * coarse_mean) << "the fracture energy converges";
  }
}

}  // namespace
