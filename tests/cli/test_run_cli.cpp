// End-to-end tests of `hexdem run`: outputs, exit codes (0 ok, 1 numerical blow-up, 2 bad
// input) and one-line messages.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hexdem::testing;

fs::path work_dir() { return test_dir("cli_run", true); }

Result run(const fs::path& dir, const std::string& args) { return run_hexdem(dir, args); }

fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name) << text;
  return dir / name;
}

std::string plate_case(const std::string& extra_time) {
  return R"([case]
name = "plate"
geometry = "plane-stress"
[lattice]
radius = 0.5e-3
[[body]]
name = "plate"
[[body.shape]]
type = "rectangle"
min = [0, -0.02]
max = [0.01, 0]
boundary = { bottom = "bottom", right = "right", top = "load", left = "left" }
[[material]]
id = 1
name = "concrete"
density = 2400.0
E = 30e9
nu = 0.2
[[boundary]]
set = "bottom"
type = "fixed"
[[load]]
type = "pressure"
set = "load"
p0 = 1e6
function = { type = "ramp-hold", t1 = 2e-6, t2 = 1.0 }
[[probe]]
name = "top"
point = [0.005, 0.0]
[time]
end = 10e-6
)" + extra_time + "\n[output]\ninterval = 5e-6\n";
}

TEST(RunCli, Help) {
  const fs::path d = work_dir();
  const Result r = run(d, "run --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--out"), std::string::npos);
  EXPECT_NE(r.out.find("--threads"), std::string::npos);
}

TEST(RunCli, GoodCaseWritesSeriesEnergyAndProbes) {
  const fs::path d = work_dir();
  const fs::path c = write(d, "plate.toml", plate_case(""));
  const Result r = run(d, "run " + c.string() + " --out " + (d / "out").string() + " --threads 1");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << "no progress line when stderr is not a terminal: " << r.err;
  const std::string pvd = slurp(d / "out" / "plate.pvd");
  EXPECT_NE(pvd.find("timestep=\"0\""), std::string::npos) << pvd;
  EXPECT_NE(pvd.find("timestep=\"1.0000000000000001e-05\""), std::string::npos) << pvd;
  int frames = 0;
  for (const auto& e : fs::directory_iterator(d / "out" / "plate")) frames += e.path().extension() == ".vtu";
  EXPECT_EQ(frames, 3);
  const std::string energy = slurp(d / "out" / "plate.energy.csv");
  EXPECT_EQ(energy.rfind("time,step,kinetic,elastic,external_work,damping,plastic,fracture,contact_damping,"
                         "friction,break_kinetic,input,total,relative_error\n", 0), 0u);
  EXPECT_GE(count_lines(energy), 4);
  const std::string probes = slurp(d / "out" / "plate.probes.csv");
  EXPECT_NE(probes.find("top.velocity_y"), std::string::npos);
  EXPECT_NE(probes.find("top.stress_yy"), std::string::npos);
  EXPECT_GT(count_lines(probes), 10);
}

/// A CSV file as columns by header name.
std::map<std::string, std::vector<double>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  std::string line, cell;
  std::getline(in, line);
  std::vector<std::string> names;
  for (std::stringstream h(line); std::getline(h, cell, ',');) names.push_back(cell);
  std::map<std::string, std::vector<double>> cols;
  while (std::getline(in, line)) {
    std::stringstream r(line);
    for (const std::string& n : names) {
      std::getline(r, cell, ',');
      cols[n].push_back(std::stod(cell));
    }
  }
  return cols;
}

// A free block dropped at 40 m/s onto a free plate (no supports, no loads): the body
// histories must show the free flight before contact, conserve the total momentum through the
// impact, and add up to the energy balance's kinetic energy.
TEST(RunCli, BodyHistoryOfTwoCollidingBlocks) {
  const fs::path d = work_dir();
  const fs::path c = write(d, "drop.toml", R"([case]
geometry = "plane-stress"
thickness = 0.01
[lattice]
radius = 0.5e-3
[[body]]
name = "plate"
material = 1
[[body.shape]]
type = "rectangle"
min = [0, -0.006]
max = [0.012, 0]
[[body]]
name = "block"
material = 2
[[body.shape]]
type = "rectangle"
min = [0.004, 0.001]
max = [0.008, 0.005]
[[material]]
id = 1
density = 2400.0
E = 30e9
nu = 0.2
[[material]]
id = 2
density = 7850.0
E = 210e9
nu = 0.3
[[initial_velocity]]
body = "block"
velocity = [0.0, -40.0]
[contact]
damping = 0.2
[time]
end = 60e-6
[output]
interval = 5e-6
probe_interval = 5e-6
body_history = ["block", "plate"]
)");
  const Result r = run(d, "run " + c.string() + " --out " + (d / "out").string() + " --threads 2");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("drop.bodies.csv"), std::string::npos) << r.out;
  auto b = read_csv(d / "out" / "drop.bodies.csv");
  auto e = read_csv(d / "out" / "drop.energy.csv");
  ASSERT_GE(b["time"].size(), 13u);
  ASSERT_EQ(b["block.mass"].size(), b["time"].size());
  // Block: 4 mm x 4 mm x 10 mm of steel; the disks' cells tile the rectangle.
  const double m_block = 7850.0 * 0.004 * 0.004 * 0.01;
  EXPECT_NEAR(b["block.mass"][0], m_block, 1e-9 * m_block);
  EXPECT_NEAR(b["plate.mass"][0], 2400.0 * 0.012 * 0.006 * 0.01, 1e-9 * m_block);
  const double y0 = b["block.y"][0];
  EXPECT_NEAR(y0, 0.003, 1e-4);  // the centre of mass of the lattice's cells
  EXPECT_NEAR(b["block.kinetic"][0], 0.5 * m_block * 40.0 * 40.0, 1e-9 * m_block * 800.0);
  // Free flight until the 1 mm gap closes at 25 us.
  for (std::size_t k = 0; k < b["time"].size() && b["time"][k] < 20e-6; ++k) {
    EXPECT_NEAR(b["block.vy"][k], -40.0, 1e-9) << "t = " << b["time"][k];
    EXPECT_NEAR(b["block.y"][k], y0 - 40.0 * b["time"][k], 1e-9) << "t = " << b["time"][k];
    EXPECT_NEAR(b["block.py"][k], -40.0 * b["block.mass"][k], 1e-9 * m_block);
    EXPECT_EQ(b["plate.vy"][k], 0.0);
  }
  // The impact happened: the block slowed down and the plate moved down.
  const std::size_t last = b["time"].size() - 1;
  EXPECT_GT(b["block.vy"][last], -30.0);
  EXPECT_LT(b["plate.vy"][last], -1.0);
  // Momentum: no external force, so the total stays -40 m_block to round-off.
  for (std::size_t k = 0; k < b["time"].size(); ++k) {
    EXPECT_NEAR(b["block.px"][k] + b["plate.px"][k], 0.0, 1e-9 * 40.0 * m_block);
    EXPECT_NEAR(b["block.py"][k] + b["plate.py"][k], -40.0 * m_block, 1e-9 * 40.0 * m_block);
  }
  // Kinetic energy: the bodies add up to the balance's leap-frog kinetic energy at the frames.
  std::size_t matched = 0;
  for (std::size_t k = 0; k < e["time"].size(); ++k)
    for (std::size_t j = 0; j < b["time"].size(); ++j)
      if (b["step"][j] == e["step"][k]) {
        ++matched;
        EXPECT_NEAR(b["block.kinetic"][j] + b["plate.kinetic"][j], e["kinetic"][k], 1e-6 * e["kinetic"][0])
            << "t = " << e["time"][k];
      }
  EXPECT_GE(matched, 13u);
}

TEST(RunCli, MissingCaseFile) {
  const fs::path d = work_dir();
  const Result r = run(d, "run " + (d / "none.toml").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("none.toml"), std::string::npos) << r.err;
}

TEST(RunCli, UnknownKeyNamesFileLineAndKey) {
  const fs::path d = work_dir();
  std::string text = plate_case("");
  text.replace(text.find("density"), 7, "densty");
  const fs::path c = write(d, "typo.toml", text);
  const Result r = run(d, "run " + c.string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("typo.toml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("densty"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "out" / "plate.pvd"));
}

TEST(RunCli, UnstableShearModelIsRefused) {
  const fs::path d = work_dir();
  std::string text = plate_case("");
  text.replace(text.find("geometry = \"plane-stress\""), 25, "geometry = \"plane-stress\"\nshear_model = \"rotation\"");
  text.replace(text.find("E = 30e9\nnu = 0.2"), 17, "E = 30e9\nnu = 0.4");
  const fs::path c = write(d, "unstable.toml", text);
  const Result r = run(d, "run " + c.string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("concrete"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("local-strain"), std::string::npos) << r.err;
}

TEST(RunCli, BlowUpExitsFourAndKeepsTheLastGoodFrame) {
  const fs::path d = work_dir();
  const fs::path c = write(d, "blowup.toml", plate_case("dt = 3e-7\nallow_unstable = true"));
  const Result r = run(d, "run " + c.string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.code, 4) << "a run that stops before its end, not an internal error (1): " << r.out << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("numerical blow-up"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("last good frame"), std::string::npos) << r.err;
  const std::string pvd = slurp(d / "out" / "plate.pvd");
  EXPECT_NE(pvd.find("</VTKFile>"), std::string::npos);
}

TEST(RunCli, ARestartInACopiedFolderNamesItsOwnFrames) {
  // Was: the restart's messages named the last frame by the path stored in the checkpoint,
  // in the folder the checkpoint was written in (here deleted after the copy).
  const fs::path d = work_dir();
  const fs::path c = write(d, "copied.toml", plate_case("dt = 3e-7\nallow_unstable = true") + "checkpoint_interval = 5e-7\n");
  fs::remove_all(d / "first");
  fs::remove_all(d / "copy");
  ASSERT_EQ(run(d, "run " + c.string() + " -q --out " + (d / "first").string()).code, 4);
  ASSERT_TRUE(fs::exists(d / "first" / "plate.chk"));
  fs::copy(d / "first", d / "copy", fs::copy_options::recursive);
  fs::remove_all(d / "first");
  const Result r = run(d, "run " + c.string() + " -q --restart " + (d / "copy" / "plate.chk").string());
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_NE(r.err.find("last good frame: " + (d / "copy" / "plate" / "plate_000000000.vtu").string()), std::string::npos)
      << r.err;
}

}  // namespace
