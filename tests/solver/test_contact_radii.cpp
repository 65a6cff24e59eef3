// Contact radii ([contact] radius_spread; docs/model.md, "Contact radii") through the solver:
// the model takes the generator's radii, broken bonds touch at the smaller of their rest length
// and the two contact radii, a plate impact with softening bonds and contacts keeps its energy
// balance, and without a spread nothing changes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "hexdem/meshing/lattice_jitter.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/solver.hpp"

#include "common/plate_impact.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;

/// The plate impact (common/plate_impact.hpp) with softening bonds and friction 0.5 on an
/// irregular lattice (f = 0.3), with the given spread.
Case plate_impact(double spread, double end) {
  std::string text = hexdem::testing::plate_impact_case("jitter = 0.3\njitter_seed = 4\n", "fracture_energy = 100.0\nfriction = 0.5\n");
  text += "radius_spread = " + std::to_string(spread) + "\n[time]\nend = " + std::to_string(end) + "\n";
  return parse_case(text, "impact.toml", ".");
}

TEST(ContactRadii, TheModelTakesTheGeneratorsRadiiAndBrokenBondsTouchAtThem) {
  const Case c = plate_impact(meshing::kMaxRadiusSpread, 1e-6);
  const meshing::Lattice lattice = mesh_case(c);
  const std::vector<double> expected = meshing::contact_radii(lattice, meshing::kMaxRadiusSpread, 4);
  const Solver s(c, lattice);
  const Model& m = s.model();
  ASSERT_EQ(m.contact_radius, expected);
  std::size_t spread = 0, at_rest = 0;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    EXPECT_EQ(m.contact_r(i), expected[i]);
    EXPECT_EQ(m.radius[i], lattice.radius[i]) << "the disk's own radius (mass, inertia, bonds) stays";
    spread += expected[i] != m.radius[i];
  }
  EXPECT_GT(spread, m.num_disks() / 2);
  for (std::size_t b = 0; b < m.num_bonds(); ++b) {
    const double sum = expected[m.bi[b]] + expected[m.bj[b]];
    EXPECT_EQ(m.touch(b), std::min(m.rest(b), sum)) << b;
    at_rest += m.rest(b) < sum;
  }
  EXPECT_GT(at_rest, m.num_bonds() / 4);
  // Without a spread: no array, every disk touches at its radius.
  const Solver s0(plate_impact(0.0, 1e-6), lattice);
  EXPECT_TRUE(s0.model().contact_radius.empty());
  EXPECT_EQ(s0.model().contact_r(7), s0.model().radius[7]);
}

// Energy: the impact breaks bonds and its broken disks meet new neighbours at their contact
// radii (the spring, the dashpot's and friction's work and the lever arm of the tangential
// force all use them); the balance holds to the 1 % the issue asks, and as closely as the same
// run without a spread.
TEST(ContactRadii, AnImpactWithSpreadRadiiKeepsItsEnergyBalance) {
  double err[2] = {0, 0};
  std::size_t broken[2] = {0, 0};
  const double spreads[2] = {0.0, meshing::kMaxRadiusSpread};
  for (int k = 0; k < 2; ++k) {
    const Case c = plate_impact(spreads[k], 80e-6);
    Solver s(c, mesh_case(c));
    for (std::int64_t n = 0; n <= s.total_steps(); ++n) {
      ASSERT_TRUE(s.advance(true)) << s.blow_up().reason;
      err[k] = std::max(err[k], std::abs(s.energy().relative_error()));
    }
    for (std::size_t b = 0; b < s.model().num_bonds(); ++b) broken[k] += !s.model().bond_intact(b);
    std::printf("radius_spread %.2f: %zu bonds broken, max |Err| %.3g\n", spreads[k], broken[k], err[k]);
  }
  EXPECT_GT(broken[1], 20u);
  EXPECT_LT(err[1], 1e-2);
  EXPECT_LT(err[1], 2 * err[0] + 1e-3);
}

}  // namespace
