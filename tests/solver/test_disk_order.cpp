// A case run with its disks on a Hilbert curve ([mesh] order = "hilbert") is the same run as
// with the generator's rows: the same time step, and at the end the same displacement of every
// disk (matched by position), the same energies and the same reactions, to round-off (the
// forces on a disk are summed in another order).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;

/// A 12 x 6 mm concrete plate with a hole on a lattice turned by 13 degrees, fixed at its base,
/// pressed on its top (ramped), local-strain or rotation shear model, plane strain.
std::string plate_case(const std::string& order, const std::string& shear_model) {
  return "[case]\ngeometry = \"plane-strain\"\nshear_model = \"" + shear_model +
         "\"\n[mesh]\norder = \"" + order +
         "\"\n[lattice]\nradius = 0.1e-3\nangle = 13.0\n[[body]]\nname = \"plate\"\n"
         "[[body.shape]]\ntype = \"rectangle\"\nmin = [0, 0]\nmax = [0.012, 0.006]\n"
         "boundary = { bottom = \"base\", top = \"top\", left = \"side\", right = \"side\" }\n"
         "[[body.shape]]\ntype = \"circle\"\nrole = \"hole\"\ncenter = [0.005, 0.003]\nradius = 0.0015\n"
         "[[material]]\nid = 1\nname = \"concrete\"\ndensity = 2400.0\nE = 30e9\nnu = 0.2\n"
         "[[boundary]]\nset = \"base\"\ntype = \"fixed\"\n"
         "[[load]]\ntype = \"pressure\"\nset = \"top\"\np0 = 5e6\n"
         "function = { type = \"ramp-hold\", t1 = 4e-6, t2 = 1.0 }\n"
         "[time]\nend = 12e-6\n[output]\nreactions = [\"base\"]\n";
}

struct Outcome {
  double dt = 0;
  std::int64_t steps = 0;
  EnergyBalance energy;
  std::array<double, 2> base{0, 0};
  std::map<std::pair<double, double>, std::pair<double, double>> u;  ///< (x0, y0) -> (ux, uy)
  double u_max = 0;
};

Outcome run(const std::string& order, const std::string& shear_model) {
  const Case c = parse_case(plate_case(order, shear_model), "order.toml", HEXDEM_SOURCE_DIR);
  EXPECT_EQ(c.disk_order, order == "hilbert" ? meshing::DiskOrder::Hilbert : meshing::DiskOrder::Rows);
  Solver s(c, mesh_case(c));
  Outcome o;
  o.dt = s.dt();
  o.steps = s.total_steps();
  for (std::int64_t n = 0; n <= o.steps; ++n) {
    EXPECT_TRUE(s.advance(n == o.steps)) << s.blow_up().reason;
  }
  o.energy = s.energy();
  o.base = s.reaction(0);
  const Model& m = s.model();
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    o.u[{m.x0[i], m.y0[i]}] = {m.ux[i], m.uy[i]};
    o.u_max = std::max(o.u_max, std::hypot(m.ux[i], m.uy[i]));
  }
  EXPECT_EQ(o.u.size(), m.num_disks()) << "every disk at its own place";
  return o;
}

void compare(const std::string& shear_model) {
  const Outcome rows = run("rows", shear_model), hilbert = run("hilbert", shear_model);
  EXPECT_EQ(hilbert.dt, rows.dt) << "the critical-step estimate does not depend on the disks' order";
  EXPECT_EQ(hilbert.steps, rows.steps);
  ASSERT_EQ(hilbert.u.size(), rows.u.size());
  ASSERT_GT(rows.u_max, 1e-7) << "the plate is loaded";
  double worst = 0;
  for (const auto& [p, ur] : rows.u) {
    const auto it = hilbert.u.find(p);
    ASSERT_NE(it, hilbert.u.end()) << "disk at (" << p.first << ", " << p.second << ")";
    worst = std::max(worst, std::hypot(it->second.first - ur.first, it->second.second - ur.second));
  }
  std::printf("%s: %zu disks, %lld steps, largest displacement %.6g m, largest difference %.3g of it; "
              "elastic %.12g / %.12g J, base reaction %.12g / %.12g N\n",
              shear_model.c_str(), rows.u.size(), static_cast<long long>(rows.steps), rows.u_max, worst / rows.u_max,
              rows.energy.elastic, hilbert.energy.elastic, rows.base[1], hilbert.base[1]);
  // Round-off of a different summation order, grown over a few hundred steps.
  EXPECT_LT(worst, 1e-10 * rows.u_max);
  EXPECT_NEAR(hilbert.energy.elastic, rows.energy.elastic, 1e-10 * rows.energy.elastic);
  EXPECT_NEAR(hilbert.energy.kinetic, rows.energy.kinetic, 1e-10 * rows.energy.elastic);
  EXPECT_NEAR(hilbert.energy.external_work, rows.energy.external_work, 1e-10 * rows.energy.external_work);
  EXPECT_NEAR(hilbert.base[1], rows.base[1], 1e-10 * std::abs(rows.base[1]));
}

TEST(DiskOrder, HilbertOrderGivesTheSameRunLocalStrain) { compare("local-strain"); }
TEST(DiskOrder, HilbertOrderGivesTheSameRunRotation) { compare("rotation"); }

TEST(DiskOrder, UnknownOrderIsRefused) {
  try {
    (void)parse_case(plate_case("morton", "rotation"), "order.toml", HEXDEM_SOURCE_DIR);
    FAIL() << "accepted [mesh] order = \"morton\"";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("order"), std::string::npos) << what;
    EXPECT_NE(what.find("morton"), std::string::npos) << what;
  }
}

}  // namespace
