// End-to-end tests of `hexdem run`: outputs, exit codes (0 ok, 1 numerical blow-up, 2 bad
// input) and one-line messages.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

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
                         "friction,input,total,relative_error\n", 0), 0u);
  EXPECT_GE(count_lines(energy), 4);
  const std::string probes = slurp(d / "out" / "plate.probes.csv");
  EXPECT_NE(probes.find("top.velocity_y"), std::string::npos);
  EXPECT_NE(probes.find("top.stress_yy"), std::string::npos);
  EXPECT_GT(count_lines(probes), 10);
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

TEST(RunCli, BlowUpExitsOneAndKeepsTheLastGoodFrame) {
  const fs::path d = work_dir();
  const fs::path c = write(d, "blowup.toml", plate_case("dt = 3e-7\nallow_unstable = true"));
  const Result r = run(d, "run " + c.string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("numerical blow-up"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("last good frame"), std::string::npos) << r.err;
  const std::string pvd = slurp(d / "out" / "plate.pvd");
  EXPECT_NE(pvd.find("</VTKFile>"), std::string::npos);
}

}  // namespace
