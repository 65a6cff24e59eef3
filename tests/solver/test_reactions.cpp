// Reaction forces of boundary sets (`[output] reactions`, Solver::reaction,
// `<case>.reactions.csv`): a plate on a fixed base carries its pressure and weight (static
// equilibrium, and the momentum balance of the leap-frog update at every step), a bar pulled
// quasi-statically gives equal and opposite end forces E A strain, an axisymmetric cylinder
// gives the force per radian p R^2 / 2, and `hexdem run` writes the file and refuses bad
// set names with one line and exit code 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "../cli/cli_runner.hpp"
#include "hexdem/error.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;
using hexdem::testing::count_lines;
using hexdem::testing::Result;
using hexdem::testing::run_hexdem;
using hexdem::testing::slurp;
using hexdem::testing::test_dir;
namespace fs = std::filesystem;

constexpr double kSqrt3 = 1.7320508075688772935;

Case parse(const std::string& text) { return parse_case(text, "test.toml", HEXDEM_SOURCE_DIR); }

std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

/// Runs a solver to its end time, calling `each` at every step's t_n.
void run(Solver& s, const std::function<void(const Solver&)>& each) {
  const std::int64_t steps = s.total_steps();
  for (std::int64_t n = 0; n <= steps; ++n) ASSERT_TRUE(s.advance(false, each)) << s.blow_up().reason;
}

/// Sum over all disks of m (v(t+dt/2) - v(t-dt/2)) / dt plus, on the free components, the
/// mass damping force alpha m (v(t-dt/2) + v(t+dt/2)) / 2 that Eq. 18 subtracts from F: by
/// the update of each free disk it equals the sum of F over the free disks, so with the
/// internal forces summing to zero (plane, no contacts) it equals the external loads plus the
/// constraint forces of all held disks.
std::array<double, 2> momentum_rate(const Solver& s) {
  const Model& m = s.model();
  const double dt = s.dt(), alpha = s.case_data().time.mass_damping;
  std::array<double, 2> sum{0, 0};
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    sum[0] += m.mass[i] * (m.vx[i] - m.vx_old[i]) / dt;
    sum[1] += m.mass[i] * (m.vy[i] - m.vy_old[i]) / dt;
    if (!(m.constraint[i] & kFixX)) sum[0] += alpha * m.mass[i] * 0.5 * (m.vx[i] + m.vx_old[i]);
    if (!(m.constraint[i] & kFixY)) sum[1] += alpha * m.mass[i] * 0.5 * (m.vy[i] + m.vy_old[i]);
  }
  return sum;
}

std::array<double, 2> external_load(const Solver& s) {
  const Model& m = s.model();
  std::array<double, 2> sum{0, 0};
  if (m.fx_ext.empty()) return sum;  // allocated only when the case has loads
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    sum[0] += m.fx_ext[i];
    sum[1] += m.fy_ext[i];
  }
  return sum;
}

const char* kConcrete = R"(
[[material]]
id = 1
name = "concrete"
density = 2400.0
E = 30e9
nu = 0.2
)";

// ---- (1) static equilibrium of a plate on a fixed base ------------------------------------

/// A 10 x 5 mm concrete plate (plane stress, thickness 0.02 m) on a fixed base, pressed on its
/// top by p = 1 MPa and pulled down by a body force of 1e5 m/s^2 (weight and pressure of
/// similar size), both ramped over 10 us and held, with mass damping alpha = 1e6 1/s to
/// t = 60 us: a mode above alpha / 2 = 5e5 rad/s (the plate's axial one is near
/// pi c / (2 H) = 1.1e6 rad/s) decays as exp(-alpha t / 2), to 1e-11 in the 50 us of hold.
TEST(Reactions, PlateOnFixedBaseCarriesPressureAndWeight) {
  const double p = 1e6, g = 1e5, width = 0.01, height = 0.005, thickness = 0.02;
  const std::string text = "[case]\ngeometry = \"plane-stress\"\nthickness = " + num(thickness) +
                           "\n[lattice]\nradius = 0.5e-3\n[[body]]\nname = \"plate\"\n[[body.shape]]\n"
                           "type = \"rectangle\"\nmin = [0, 0]\nmax = [" + num(width) + ", " + num(height) +
                           "]\nboundary = { bottom = \"base\", top = \"top\", left = \"side\", right = \"side\" }\n" +
                           kConcrete +
                           "[[boundary]]\nset = \"base\"\ntype = \"fixed\"\n"
                           "[[load]]\ntype = \"pressure\"\nset = \"top\"\np0 = " + num(p) +
                           "\nfunction = { type = \"ramp-hold\", t1 = 10e-6, t2 = 1.0 }\n"
                           "[[load]]\ntype = \"body-force\"\nacceleration = [0.0, " + num(-g) +
                           "]\nfunction = { type = \"ramp-hold\", t1 = 10e-6, t2 = 1.0 }\n"
                           "[time]\nend = 60e-6\nmass_damping = 1e6\n"
                           "[output]\nreactions = [\"base\", \"top\"]\n";
  const Case c = parse(text);
  Solver s(c, mesh_case(c));
  ASSERT_EQ(s.num_reaction_sets(), 2u);
  double mass = 0;
  for (double mi : s.model().mass) mass += mi;
  EXPECT_NEAR(mass, 2400.0 * width * height * thickness, 1e-9 * mass) << "the cells tile the plate";
  const double load_y = -p * width * thickness - mass * g;  // the applied total, held
  double worst_balance = 0, worst_top = 0;
  std::array<double, 2> base{0, 0}, top{0, 0};
  run(s, [&](const Solver& sv) {
    base = sv.reaction(0);
    top = sv.reaction(1);
    // Every step, static or not: the momentum balance of the update.
    const std::array<double, 2> rate = momentum_rate(sv), ext = external_load(sv);
    for (int k = 0; k < 2; ++k) worst_balance = std::max(worst_balance, std::abs(rate[k] - ext[k] - base[k]));
    // The top carries no condition: it reports the pressure it applies, -p w t f(t).
    const double f = std::min(sv.time() / 10e-6, 1.0);
    worst_top = std::max({worst_top, std::abs(top[0]), std::abs(top[1] + p * width * thickness * f)});
  });
  std::printf("base reaction (%.6g, %.6g) N, applied load (0, %.6g) N: %+.2e relative\n", base[0], base[1], load_y,
              (base[1] + load_y) / -load_y);
  EXPECT_LT(worst_balance, 1e-9 * std::abs(load_y)) << "the reaction is the force of the leap-frog update at t_n";
  EXPECT_LT(worst_top, 1e-12 * std::abs(load_y));
  // Static equilibrium: the base carries minus the applied total.
  EXPECT_NEAR(base[1], -load_y, 1e-3 * std::abs(load_y));
  EXPECT_NEAR(base[0], 0.0, 1e-3 * std::abs(load_y));
}

// ---- (2) a bar pulled quasi-statically ----------------------------------------------------

/// A 20 mm wide concrete bar (plane stress, thickness 1 m), 40 lattice rows long between its
/// held end rows, held in y on its bottom row ("fixed" end: a roller, so that the ends do not
/// hold the lateral contraction and the stress is uniaxial) and pulled at 0.1 m/s on its top
/// row (ramped over 40 us). After 400 us (35 transit times L/c) the dynamic part of the end
/// forces is below 1 % of the static one (a linear velocity ramp leaves a free vibration of
/// strain at most (V/c) 2L/(pi c t1), 0.5 % of V (T - t1/2) / L here). Both end forces must
/// be E A strain, with the strain from the held rows' displacement and distance.
TEST(Reactions, PulledBarEndsCarryEAStrain) {
  const double r = 0.5e-3, h = kSqrt3 * r, width = 0.02, rows = 40, v = 0.1;
  const double length = rows * h, E = 30e9;
  const std::string text = "[case]\ngeometry = \"plane-stress\"\n[lattice]\nradius = " + num(r) +
                           "\n[[body]]\nname = \"bar\"\n[[body.shape]]\ntype = \"rectangle\"\nmin = [0, 0]\nmax = [" +
                           num(width) + ", " + num(length) +
                           "]\nboundary = { bottom = \"fixed_end\", top = \"pulled_end\" }\n" + kConcrete +
                           "[[boundary]]\nset = \"fixed_end\"\ntype = \"roller\"\ncomponent = \"y\"\n"
                           "[[boundary]]\nset = \"pulled_end\"\ntype = \"velocity\"\nvy = " + num(v) +
                           "\nfunction = { type = \"ramp-hold\", t1 = 40e-6, t2 = 1.0 }\n"
                           "[time]\nend = 400e-6\n"
                           "[output]\nreactions = [\"fixed_end\", \"pulled_end\"]\n";
  const Case c = parse(text);
  Solver s(c, mesh_case(c));
  const Model& m = s.model();
  // The held rows: their reference distance is the bar's length.
  double y_low = 1e9, y_high = -1e9;
  std::vector<std::size_t> top_row;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    if (!(m.constraint[i] & kFixY)) continue;
    y_low = std::min(y_low, m.y0[i]);
    y_high = std::max(y_high, m.y0[i]);
  }
  for (std::size_t i = 0; i < m.num_disks(); ++i)
    if ((m.constraint[i] & kFixY) && m.y0[i] > 0.5 * (y_low + y_high)) top_row.push_back(i);
  ASSERT_NEAR(y_high - y_low, length, 1e-9 * length) << "both ends on lattice rows";
  ASSERT_GT(top_row.size(), 10u);
  double worst_balance = 0, scale = 0;
  std::array<double, 2> low{0, 0}, high{0, 0};
  double stretch = 0;
  bool uniform = true;  // the held row moves as one
  run(s, [&](const Solver& sv) {
    low = sv.reaction(0);
    high = sv.reaction(1);
    stretch = sv.model().uy[top_row.front()];
    for (std::size_t i : top_row) uniform = uniform && sv.model().uy[i] == stretch;
    const std::array<double, 2> rate = momentum_rate(sv);
    scale = std::max(scale, std::abs(high[1]));
    worst_balance = std::max(worst_balance, std::abs(rate[1] - low[1] - high[1]));
  });
  EXPECT_TRUE(uniform);
  const double strain = stretch / length;
  const double expected = E * width * 1.0 * strain;
  std::printf("pulled bar: strain %.4g, ends %.6g N and %.6g N, E A strain %.6g N (%+.3f %%, %+.3f %%)\n", strain,
              low[1], high[1], expected, 100 * (-low[1] / expected - 1), 100 * (high[1] / expected - 1));
  EXPECT_LT(worst_balance, 1e-9 * scale) << "the end forces are those of the leap-frog update";
  EXPECT_NEAR(high[1], expected, 0.02 * expected);
  EXPECT_NEAR(-low[1], expected, 0.02 * expected);
  // Equal and opposite, up to the bar's inertia (the dynamic part, below 1 %).
  EXPECT_NEAR(high[1] + low[1], 0.0, 0.01 * expected);
  // Nothing holds x: no force there.
  EXPECT_EQ(low[0], 0.0);
  EXPECT_EQ(high[0], 0.0);
}

// ---- (3) axisymmetry: per radian -----------------------------------------------------------

/// A steel cylinder of radius R = 5 mm and height 10 mm on its axis, fixed at its base and
/// pressed on its top by p = 10 MPa (ramped over 10 us), with mass damping to t = 60 us. The
/// axial force per radian on a disc of radius R is p int_0^R r dr = p R^2 / 2 (the plane
/// formula p A with the area per radian, R^2 / 2 in place of the width times thickness): the
/// top set reports it as its load, the base carries it, and the axis (a symmetry plane) holds
/// nothing axially.
TEST(Reactions, AxisymmetricForcesArePerRadian) {
  const double p = 10e6, radius = 0.005;
  const std::string text = R"([case]
geometry = "axisymmetric"
[lattice]
radius = 0.5e-3
[[body]]
name = "cylinder"
[[body.shape]]
type = "rectangle"
min = [0, 0]
max = [0.005, 0.01]
boundary = { left = "axis", bottom = "base", top = "top" }
[[material]]
id = 1
name = "steel"
density = 7850.0
E = 210e9
nu = 0.3
[[boundary]]
set = "axis"
type = "symmetry"
component = "x"
[[boundary]]
set = "base"
type = "fixed"
[[load]]
type = "pressure"
set = "top"
p0 = )" + num(p) + R"(
function = { type = "ramp-hold", t1 = 10e-6, t2 = 1.0 }
[time]
end = 60e-6
mass_damping = 1e6
[output]
reactions = ["top", "base", "axis"]
)";
  const Case c = parse(text);
  Solver s(c, mesh_case(c));
  std::array<double, 2> top{0, 0}, base{0, 0}, axis{0, 0};
  run(s, [&](const Solver& sv) {
    top = sv.reaction(0);
    base = sv.reaction(1);
    axis = sv.reaction(2);
  });
  const double per_radian = p * radius * radius / 2;
  std::printf("cylinder: top %.6g N/rad, base %.6g N/rad, axis (%.4g, %.4g) N/rad, p R^2/2 = %.6g N/rad\n", top[1],
              base[1], axis[0], axis[1], per_radian);
  // The faces' ring radii weight the pressure: sum L b = int_0^R r dr, up to the clipped
  // cells' geometry (3e-8 relative measured).
  EXPECT_NEAR(top[1], -per_radian, 1e-6 * per_radian);
  EXPECT_EQ(top[0], 0.0);
  EXPECT_NEAR(base[1], per_radian, 1e-3 * per_radian);
  EXPECT_EQ(axis[1], 0.0) << "a symmetry plane x = 0 holds r only";
}

// ---- (4), (5) hexdem run: the file and its refusals ---------------------------------------

std::string plate_case(const std::string& output) {
  return std::string(R"([case]
name = "plate"
geometry = "plane-stress"
[lattice]
radius = 0.5e-3
[[body]]
name = "plate"
[[body.shape]]
type = "rectangle"
min = [0, 0]
max = [0.01, 0.005]
boundary = { bottom = "base", right = "right", top = "load", left = "left" }
)") + kConcrete + R"(
[[boundary]]
set = "base"
type = "fixed"
[[boundary]]
set = "left"
type = "roller"
component = "x"
[[load]]
type = "pressure"
set = "load"
p0 = 1e6
function = { type = "ramp-hold", t1 = 2e-6, t2 = 1.0 }
[time]
end = 10e-6
[output]
interval = 2e-6
)" + output;
}

std::vector<std::vector<std::string>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> row;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

TEST(ReactionsCli, FileHasTheListedSetsInOrderAtTheProbeRows) {
  const fs::path d = test_dir("reactions", true);
  std::ofstream(d / "plate.toml") << plate_case("reactions = [\"load\", \"base\", \"left\"]\n");
  Result r = run_hexdem(d, "run " + (d / "plate.toml").string() + " -o " + (d / "out").string() + " -j 1");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("reactions: " + (d / "out" / "plate.reactions.csv").string()), std::string::npos) << r.out;
  const auto rows = read_csv(d / "out" / "plate.reactions.csv");
  const auto energy = read_csv(d / "out" / "plate.energy.csv");
  ASSERT_GE(rows.size(), 3u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"time", "load.fx", "load.fy", "base.fx", "base.fy", "left.fx",
                                               "left.fy"}));
  // One row every probe_interval (here every step), from the first to the last step.
  ASSERT_GT(rows.size(), energy.size()) << "one row per probe row";
  EXPECT_EQ(rows[1][0], energy[1][0]) << "the first step";
  EXPECT_EQ(rows.back()[0], energy.back()[0]) << "the last step";
  for (std::size_t k = 1; k < rows.size(); ++k) {
    ASSERT_EQ(rows[k].size(), 7u) << k;
    if (k > 1) {
      EXPECT_GT(std::stod(rows[k][0]), std::stod(rows[k - 1][0])) << k;
    }
    // The loaded set reports its pressure, -p w t f(t) (thickness 1 m, width 10 mm).
    const double t = std::stod(rows[k][0]);
    // Time and force are printed with 10 significant digits: 1e-9 of the value.
    const double expected = -1e6 * 0.01 * std::min(t / 2e-6, 1.0);
    EXPECT_NEAR(std::stod(rows[k][2]), expected, 1e-9 * std::abs(expected) + 1e-6) << k;
    EXPECT_EQ(std::stod(rows[k][1]), 0.0);
    EXPECT_EQ(std::stod(rows[k][6]), 0.0) << "a roller in x holds no y";
  }
  EXPECT_GT(std::stod(rows.back()[4]), 0.0) << "the base pushes the plate up";
  EXPECT_EQ(slurp(d / "out" / "plate.status"), "completed\n");

  // Without the key: no file.
  std::ofstream(d / "plain.toml") << plate_case("");
  r = run_hexdem(d, "run " + (d / "plain.toml").string() + " -o " + (d / "plain").string() + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(d / "plain" / "plate.reactions.csv"));
  EXPECT_TRUE(fs::exists(d / "plain" / "plate.energy.csv"));
}

/// Bad `[output] reactions` values: exit 2, one line naming the file, the key and the value,
/// before any output.
TEST(ReactionsCli, BadSetsAreRefusedWithOneLine) {
  const fs::path d = test_dir("reactions", true);
  // "plate.toml:LINE: " of the reactions key.
  const std::string probe = plate_case("reactions = []\n");
  const std::string at =
      "plate.toml:" + std::to_string(1 + std::count(probe.begin(), probe.begin() + probe.find("reactions"), '\n')) + ": ";
  struct Bad {
    std::string output, expect;
  };
  const std::vector<Bad> cases{
      {"reactions = [\"base\", \"nowhere\"]\n",
       at + "output.reactions[1]: unknown boundary set 'nowhere' (sets: base, left, load, right)"},
      {"reactions = [\"base\", \"base\"]\n", at + "output.reactions[1]: duplicate boundary set 'base'"},
      {"reactions = []\n", at + "output.reactions: expected a non-empty array of names"},
      {"reactions = \"base\"\n", at + "output.reactions: expected a non-empty array of names"},
      {"reactions = [\"right\"]\n",
       "plate.toml: output.reactions: boundary set 'right' has no [[boundary]] condition and no pressure [[load]]"},
  };
  for (const Bad& b : cases) {
    std::ofstream(d / "plate.toml") << plate_case(b.output);
    const Result r = run_hexdem(d, "run " + (d / "plate.toml").string() + " -o " + (d / "out").string() + " -q");
    EXPECT_EQ(r.code, 2) << b.output << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(b.expect), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "out" / "plate.reactions.csv")) << b.output;
  }
  // A condition on a set that selects no disk is refused as before: the plate's top edge
  // (y = 5 mm) lies 0.67 mm, more than a radius, above its highest row of centres.
  std::string text = plate_case("reactions = [\"load\"]\n");
  const std::string left = "set = \"left\"\ntype = \"roller\"";
  text.replace(text.find(left), left.size(), "set = \"load\"\ntype = \"roller\"");
  std::ofstream(d / "plate.toml") << text;
  const Result r = run_hexdem(d, "run " + (d / "plate.toml").string() + " -o " + (d / "out").string() + " -q");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("boundary set 'load' selects no disk"), std::string::npos) << r.err;
}

}  // namespace
