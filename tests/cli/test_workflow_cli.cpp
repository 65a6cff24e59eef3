// End-to-end tests of the researcher's workflow: checkpoint and restart (`[output]
// checkpoint_interval`, `hexdem run --restart`), overrides (`--set`) and the effective case,
// `hexdem check`, and parameter studies (`hexdem sweep`).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_runner.hpp"
#include "common/edge_band_plate.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hexdem::testing;

fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name) << text;
  return dir / name;
}

// ---- cases -------------------------------------------------------------------------------

/// A plate under a pressure ramp (plane stress or plane strain), with probes and a body
/// history, frames every 1 us and a checkpoint every 5 us of 10 us.
std::string plate_case(const std::string& geometry) {
  return R"([case]
name = "plate"
geometry = ")" + geometry + R"("
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
[output]
interval = 1e-6
checkpoint_interval = 5e-6
body_history = ["plate"]
)";
}

/// An axisymmetric cylinder on its axis, fixed at its base, pressed on its top.
std::string cylinder_case() {
  return R"([case]
name = "cylinder"
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
p0 = 10e6
function = { type = "ramp-hold", t1 = 1e-6, t2 = 1.0 }
[[probe]]
name = "centre"
point = [0.0, 0.01]
[time]
end = 6e-6
[output]
interval = 0.5e-6
checkpoint_interval = 2.5e-6
reactions = ["top", "base", "axis"]
)";
}

/// Plane strain: a J2-plastic steel striker hits a breakable concrete block: fracture,
/// contacts (between the bodies and across broken bonds) and J2 plasticity before the
/// checkpoint at 6 us.
std::string impact_case() {
  return R"([case]
name = "impact"
geometry = "plane-strain"
[lattice]
radius = 0.5e-3
[[body]]
name = "target"
material = 1
[[body.shape]]
type = "rectangle"
min = [0, 0]
max = [0.012, 0.005]
boundary = { bottom = "base" }
[[body]]
name = "striker"
material = 2
[[body.shape]]
type = "rectangle"
min = [0.004, 0.0054]
max = [0.008, 0.0084]
[[material]]
id = 1
name = "concrete"
density = 2400.0
E = 30e9
nu = 0.2
tensile_strength = 4e6
compressive_strength = 40e6
cohesion = 11.5e6
friction_angle = 30.0
friction = 0.5
[[material]]
id = 2
name = "steel"
density = 7850.0
E = 210e9
nu = 0.3
friction = 0.3
yield_stress = 400e6
tangent_modulus = 2.1e9
plasticity = "j2"
[[boundary]]
set = "base"
type = "fixed"
[[initial_velocity]]
body = "striker"
velocity = [0.0, -200.0]
[contact]
damping = 0.1
[time]
end = 12e-6
[output]
interval = 1e-6
checkpoint_interval = 6e-6
body_history = ["striker", "target"]
reactions = ["base"]
)";
}

std::map<std::string, std::string> read_row(const fs::path& csv) {
  std::ifstream in(csv);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  std::stringstream h(header), r(row);
  std::map<std::string, std::string> out;
  std::string k, v;
  while (std::getline(h, k, ',') && std::getline(r, v, ',')) out[k] = v;
  return out;
}

std::vector<std::string> files_under(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out.push_back(fs::relative(e.path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

// ---- checkpoint and restart ---------------------------------------------------------------

/// Runs the case to the end with checkpoints (the reference), then restarts from its last
/// checkpoint in a copy of its folder made to look like a run killed after that checkpoint:
/// later frames deleted, the CSVs holding rows past it, the .pvd and summary gone. Every
/// file of the restarted folder must equal the reference byte for byte.
void expect_restart_identical(const std::string& text, const std::string& name, const std::string& extra = "") {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path c = write(d, name + ".toml", text);
  const fs::path full = d / "full", cut = d / "cut";
  Result r = run_hexdem(d, "run " + c.string() + " -o " + full.string() + " -j 1 -q" + extra);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(full / (name + ".chk")));
  EXPECT_FALSE(fs::exists(full / (name + ".chk.tmp"))) << "the temporary checkpoint is renamed into place";
  fs::copy(full, cut, fs::copy_options::recursive);
  // The interrupted run: frames after the checkpoint partly missing, CSVs longer than at it.
  std::vector<fs::path> frames;
  for (const auto& e : fs::directory_iterator(cut / name)) frames.push_back(e.path());
  std::sort(frames.begin(), frames.end());
  ASSERT_GE(frames.size(), 4u);
  fs::remove(frames.back());
  fs::remove(cut / (name + ".pvd"));
  fs::remove(cut / (name + ".summary.csv"));
  std::ofstream(cut / (name + ".energy.csv"), std::ios::app) << "9,9,9,half a row";
  if (fs::exists(cut / (name + ".reactions.csv")))
    std::ofstream(cut / (name + ".reactions.csv"), std::ios::app) << "9,9,half a row";

  r = run_hexdem(d, "run " + c.string() + " --restart " + (cut / (name + ".chk")).string() + " -j 2" + extra);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("restart from"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("at step 0 "), std::string::npos) << "the checkpoint is mid-run: " << r.out;
  EXPECT_NE(r.out.find("series: " + (cut / (name + ".pvd")).string()), std::string::npos)
      << "a restart writes into the checkpoint's folder: " << r.out;
  const std::vector<std::string> want = files_under(full), got = files_under(cut);
  EXPECT_EQ(want, got);
  for (const std::string& f : want) {
    EXPECT_TRUE(slurp(full / f) == slurp(cut / f)) << f << " differs after the restart";
  }
}

TEST(Restart, PlaneStressIsBitIdentical) { expect_restart_identical(plate_case("plane-stress"), "plate"); }

TEST(Restart, PlaneStrainIsBitIdentical) { expect_restart_identical(plate_case("plane-strain"), "plate"); }

TEST(Restart, AxisymmetricIsBitIdentical) { expect_restart_identical(cylinder_case(), "cylinder"); }

TEST(Restart, FractureContactAndJ2AreBitIdentical) {
  expect_restart_identical(impact_case(), "impact");
  // The run does break bonds, touch and yield before and after the checkpoint.
  const fs::path d = test_dir("cli_workflow", false);
  const auto row = read_row(d / "full" / "impact.summary.csv");
  EXPECT_GT(std::stod(row.at("broken_bonds")), 10);
  EXPECT_GT(std::stod(row.at("plastic")), 0);
  EXPECT_GT(std::stod(row.at("contact_damping")), 0);
}

TEST(Restart, WithOverridesNeedsTheSameOverrides) {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path c = write(d, "plate.toml", plate_case("plane-stress"));
  Result r = run_hexdem(d, "run " + c.string() + " -o " + (d / "a").string() + " -q --set load.0.p0=2e6");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string chk = (d / "a" / "plate.chk").string();
  r = run_hexdem(d, "run " + c.string() + " -q --restart " + chk);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("checkpoint of another case"), std::string::npos) << r.err;
  r = run_hexdem(d, "run " + c.string() + " -q --restart " + chk + " --set load.0.p0=2e6");
  EXPECT_EQ(r.code, 0) << r.err;
  // The effective case carries the overrides: it restarts the checkpoint alone.
  r = run_hexdem(d, "run " + (d / "a" / "plate.case.toml").string() + " -q --restart " + chk);
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(Restart, BadCheckpointsAreRefused) {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path c = write(d, "plate.toml", plate_case("plane-stress"));
  Result r = run_hexdem(d, "run " + c.string() + " -o " + (d / "a").string() + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string good = slurp(d / "a" / "plate.chk");
  auto expect_refused = [&](const std::string& content, const std::string& message) {
    fs::remove_all(d / "b");
    fs::copy(d / "a", d / "b", fs::copy_options::recursive);
    {
      std::ofstream out(d / "b" / "plate.chk", std::ios::binary | std::ios::trunc);
      out << content;
    }
    const std::string energy = slurp(d / "b" / "plate.energy.csv");
    const Result res = run_hexdem(d, "run " + c.string() + " -q --restart " + (d / "b" / "plate.chk").string());
    EXPECT_EQ(res.code, 2) << message << ": " << res.err;
    EXPECT_EQ(count_lines(res.err), 1) << res.err;
    EXPECT_NE(res.err.find(message), std::string::npos) << res.err;
    EXPECT_NE(res.err.find("plate.chk"), std::string::npos) << "the message names the file: " << res.err;
    EXPECT_EQ(slurp(d / "b" / "plate.energy.csv"), energy) << "a refused restart leaves the output alone";
  };
  expect_refused("hello", "not a hexdem checkpoint");
  expect_refused(good.substr(0, good.size() / 2), "checksum");
  std::string version = good;
  const int current = static_cast<unsigned char>(good[8]);  // the format version follows the 8-byte magic
  version[8] = static_cast<char>(current + 1);
  expect_refused(version, "checkpoint format version " + std::to_string(current + 1) + ", this hexdem reads version " +
                              std::to_string(current));
  std::string flipped = good;
  flipped[flipped.size() / 2] ^= 1;
  expect_refused(flipped, "damaged or truncated checkpoint");

  // A checkpoint of another case (another material).
  r = run_hexdem(d, "run " + c.string() + " -o " + (d / "e").string() + " -q --set material.1.E=31e9");
  ASSERT_EQ(r.code, 0) << r.err;
  expect_refused(slurp(d / "e" / "plate.chk"), "checkpoint of another case");

  // The output it continues must be there.
  fs::remove_all(d / "b");
  fs::copy(d / "a", d / "b", fs::copy_options::recursive);
  fs::remove(d / "b" / "plate.probes.csv");
  r = run_hexdem(d, "run " + c.string() + " -q --restart " + (d / "b" / "plate.chk").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("plate.probes.csv: missing"), std::string::npos) << r.err;
  r = run_hexdem(d, "run " + c.string() + " -q --restart " + (d / "nothing.chk").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("nothing.chk: cannot open checkpoint"), std::string::npos) << r.err;
}

TEST(Restart, AFailedCheckpointWriteLeavesThePreviousCheckpoint) {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path c = write(d, "plate.toml", plate_case("plane-stress"));
  Result r = run_hexdem(d, "run " + c.string() + " -o " + (d / "a").string() + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string before = slurp(d / "a" / "plate.chk");
  // The temporary file cannot be created (a folder has its name): the next checkpoint fails
  // before anything touches plate.chk.
  fs::create_directory(d / "a" / "plate.chk.tmp");
  r = run_hexdem(d, "run " + c.string() + " -o " + (d / "a").string() + " -q --set load.0.p0=3e6");
  EXPECT_EQ(r.code, 2) << "an output that cannot be written: " << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("plate.chk.tmp: cannot write checkpoint"), std::string::npos) << r.err;
  EXPECT_TRUE(slurp(d / "a" / "plate.chk") == before) << "the previous checkpoint was changed";
  fs::remove(d / "a" / "plate.chk.tmp");
  // Another complete run (no checkpoints) rewrites the CSVs: the old checkpoint does not
  // continue them.
  r = run_hexdem(d, "run " + c.string() + " -o " + (d / "a").string() +
                        " -q --set load.0.p0=3e6 --set output.checkpoint_interval=0");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(slurp(d / "a" / "plate.chk") == before);
  r = run_hexdem(d, "run " + c.string() + " -q --restart " + (d / "a" / "plate.chk").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("plate.energy.csv: its first 783 bytes are not the ones the checkpoint's run wrote"),
            std::string::npos) << r.err;
  // ... and it still restarts (its own case, the output folder of its run copied back).
  r = run_hexdem(d, "run " + c.string() + " -o " + (d / "b").string() + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  fs::copy_file(d / "a" / "plate.chk", d / "b" / "plate.chk", fs::copy_options::overwrite_existing);
  r = run_hexdem(d, "run " + c.string() + " -q --restart " + (d / "b" / "plate.chk").string());
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(Restart, BadCheckpointIntervalIsRefused) {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path c = write(d, "plate.toml", plate_case("plane-stress"));
  const Result r = run_hexdem(d, "run " + c.string() + " -q --set output.checkpoint_interval=-1");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("output.checkpoint_interval"), std::string::npos) << r.err;
}

// ---- --set --------------------------------------------------------------------------------

TEST(Overrides, ValuesReachTheRunAndTheEffectiveCase) {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path c = write(d, "plate.toml", plate_case("plane-stress"));
  Result r = run_hexdem(d, "run " + c.string() + " -o " + (d / "a").string() +
                               " -q --set time.end=5e-6 --set material.concrete.E=32e9 --set 'probe.top.point=[0.002,0.0]'"
                               " --set output.checkpoint_interval=0");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto row = read_row(d / "a" / "plate.summary.csv");
  EXPECT_DOUBLE_EQ(std::stod(row.at("time")), 5e-6);
  const std::string eff = slurp(d / "a" / "plate.case.toml");
  EXPECT_NE(eff.find("E = 32000000000.0"), std::string::npos) << eff;
  EXPECT_NE(eff.find("name = 'plate'"), std::string::npos) << eff;
  EXPECT_NE(eff.find("point = [ 0.002, 0.0 ]"), std::string::npos) << eff;
  EXPECT_FALSE(fs::exists(d / "a" / "plate.chk"));
  // The effective case runs alone and repeats the run exactly.
  r = run_hexdem(d, "run " + (d / "a" / "plate.case.toml").string() + " -o " + (d / "b").string() + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"plate.energy.csv", "plate.probes.csv", "plate.summary.csv", "plate.case.toml"})
    EXPECT_EQ(slurp(d / "a" / f), slurp(d / "b" / f)) << f;
  // Without --set the run differs (the override did something).
  r = run_hexdem(d, "run " + c.string() + " -o " + (d / "c").string() + " -q --set time.end=5e-6");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(slurp(d / "a" / "plate.energy.csv"), slurp(d / "c" / "plate.energy.csv"));
  // Material by id, and by name, give the same run.
  r = run_hexdem(d, "run " + c.string() + " -o " + (d / "e").string() +
                        " -q --set time.end=5e-6 --set material.1.E=32e9 --set 'probe.top.point=[0.002,0.0]'"
                        " --set output.checkpoint_interval=0");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(d / "a" / "plate.energy.csv"), slurp(d / "e" / "plate.energy.csv"));
}

TEST(Overrides, EachSetTakesOneValueAnywhereOnTheLine) {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path c = write(d, "plate.toml", plate_case("plane-stress"));
  const Result r = run_hexdem(d, "run --set time.end=3e-6 --set output.checkpoint_interval=0 " + c.string() + " -q -o " +
                                     (d / "a").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string eff = slurp(d / "a" / "plate.case.toml");
  EXPECT_NE(eff.find("end = 3.0000000000000001e-06"), std::string::npos) << eff;
  EXPECT_NE(eff.find("checkpoint_interval = 0\n"), std::string::npos) << eff;
  const Result chk = run_hexdem(d, "check --set time.end=3e-6 " + c.string() + " --set time.dt=1e-7");
  ASSERT_EQ(chk.code, 0) << chk.err;
  EXPECT_NE(chk.out.find("30 steps to t = 3e-06 s"), std::string::npos) << chk.out;
}

TEST(Overrides, BadOverridesGiveOneLineAndNoOutput) {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path c = write(d, "plate.toml", plate_case("plane-stress"));
  const std::vector<std::pair<std::string, std::string>> cases{
      {"time.end=-1", "plate.toml: --set time.end=-1: time.end: must be > 0 (got -1)"},
      {"material.1.E=abc", "--set material.1.E=abc: material[0].E: expected a number (got \"abc\")"},
      {"material.7.E=3", "--set material.7.E=3: no [[material]] table '7' (id 1, name 'concrete')"},
      {"material.1.youngs=3", "--set material.1.youngs=3: material[0]: unknown key 'youngs'"},
      {"noise.seed=3", "--set noise.seed=3: unknown key 'noise'"},
      {"time.end", "--set time.end: expected KEY=VALUE"},
      {"time..end=1", "bad key 'time..end'"},
      {"time.end=", "missing value"},
      {"time.end.x=1", "'time.end' is a value (1e-05), not a table"},
      {"material.1=3", "'material.1' selects a whole [[material]] table"},
      {"boundary.3.type=fixed", "no [[boundary]] table '3' (select by position 0 to 0)"},
      {"case.geometry=cubic", "case.geometry"},
  };
  for (const auto& [spec, message] : cases) {
    const Result r = run_hexdem(d, "run " + c.string() + " -o " + (d / "out").string() + " -q --set '" + spec + "'");
    EXPECT_EQ(r.code, 2) << spec;
    EXPECT_EQ(count_lines(r.err), 1) << spec << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << spec << ": " << r.err;
    EXPECT_FALSE(fs::exists(d / "out")) << spec << ": no output for a refused case";
  }
  // Tables without id or name are chosen by position; strings need no quotes.
  const Result r = run_hexdem(d, "run " + c.string() + " -o " + (d / "out").string() +
                                     " -q --set boundary.0.type=roller --set boundary.0.component=y --set time.end=2e-6");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(slurp(d / "out" / "plate.case.toml").find("type = 'roller'"), std::string::npos);
}

TEST(Overrides, PlusEqualsAddsTablesToAnArrayOfTables) {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path c = write(d, "plate.toml", plate_case("plane-stress"));
  // One table, then two at once; the new probes get their columns and the effective case
  // repeats the run alone.
  Result r = run_hexdem(d, "run " + c.string() + " -o " + (d / "a").string() +
                               " -q --set time.end=3e-6 --set output.checkpoint_interval=0"
                               " --set 'probe+={name = \"mid\", point = [0.004, 0.0]}'"
                               " --set 'probe+=[{name = \"p1\", point = [0.001, 0.001]}, {name = \"p2\", point = [0.003, 0.001]}]'");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string probes = slurp(d / "a" / "plate.probes.csv");
  const std::string header = probes.substr(0, probes.find('\n'));
  for (const char* name : {"top.", "mid.", "p1.", "p2."}) EXPECT_NE(header.find(name), std::string::npos) << name << ": " << header;
  r = run_hexdem(d, "run " + (d / "a" / "plate.case.toml").string() + " -o " + (d / "b").string() + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(probes, slurp(d / "b" / "plate.probes.csv"));
  // A table into a missing array creates it (walls: none in the file).
  r = run_hexdem(d, "check " + c.string() + " --set 'wall+={point = [0.0, -1.0], normal = [0.0, 1.0]}'");
  EXPECT_EQ(r.code, 0) << r.err;
  // Refused with one line, nothing written.
  const std::vector<std::pair<std::string, std::string>> bad{
      {"probe+=3", "--set probe+=3: expected an inline table such as {name = \"tip\", point = [0, 0.01]} after '+=' (got 3)"},
      {"probe+={name = ", "expected an inline table such as"},
      {"time.end+={a = 1}", "'time.end' is not an array of tables"},
      {"material.1.foo+={a = 1}", "--set material.1.foo+={a = 1}: material[0]: unknown key 'foo'"},
      {"probe.p9.point=[0.0, 0.0]", "no [[probe]] table 'p9' (name 'top'); 'probe+={...}' adds one"},
      {"wall.w.point=[0.0, 0.0]", "expected [[wall]] tables (got "},
      {"probe+={name = \"top\", point = [0.004, 0.0]}", "top"},  // a second probe of one name
  };
  for (const auto& [spec, message] : bad) {
    r = run_hexdem(d, "run " + c.string() + " -o " + (d / "out").string() + " -q --set '" + spec + "'");
    EXPECT_EQ(r.code, 2) << spec;
    EXPECT_EQ(count_lines(r.err), 1) << spec << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << spec << ": " << r.err;
    EXPECT_FALSE(fs::exists(d / "out")) << spec << ": no output for a refused case";
  }
  r = run_hexdem(d, "run " + c.string() + " -o " + (d / "out").string() + " -q --set 'wall.w.point=[0.0, 0.0]'");
  EXPECT_NE(r.err.find("--set 'wall+={...}' adds a table"), std::string::npos) << r.err;
}

// ---- check --------------------------------------------------------------------------------

TEST(Check, PrintsTheSummaryWithoutRunning) {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path c = write(d, "impact.toml", impact_case());
  const Result r = run_hexdem(d, "check " + c.string());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* s : {"hexdem check: ", ": ok", "disks 88", "body target", "75 disks", "body striker", "13 disks",
                        "set  base", "time step", "stability: dt / critical = 0.897", "106 steps", "plasticity j2",
                        "0 warnings"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s << " missing from:\n" << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_FALSE(fs::exists(d / "impact-output")) << "check writes nothing";
}

TEST(Check, NamesTheModelOfTheCriticalStepEstimate) {
  const fs::path d = test_dir("cli_workflow", true);
  // A small case: the whole model.
  const fs::path c = write(d, "impact.toml", impact_case());
  Result r = run_hexdem(d, "check " + c.string() + " --whole-model-step");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("finite model: Lanczos on the whole model ("), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("whole model: finite model"), std::string::npos) << "nothing to compare: " << r.out;
  // A 40 x 40 mm plate of r = 0.1 mm (44,739 disks) whose edge mode lies 12 % above the
  // bulk's top: the edge band, and with --whole-model-step both estimates.
  const fs::path band = write(d, "band.toml", edge_band_plate_case("plane-strain", "local-strain"));
  r = run_hexdem(d, "check " + band.string() + " --whole-model-step");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("finite model: Lanczos on the edge band, 17035 of 44739 disks"), std::string::npos) << r.out;
  const auto at = r.out.find("whole model: finite model ");
  ASSERT_NE(at, std::string::npos) << r.out;
  // "... against the band's X s (+1.82e-10)": the relative difference, within 1e-8.
  const auto open = r.out.find('(', at), close = r.out.find(')', at);
  ASSERT_TRUE(open != std::string::npos && close != std::string::npos) << r.out;
  EXPECT_LT(std::abs(std::stod(r.out.substr(open + 1, close - open - 1))), 1e-8) << r.out;
  EXPECT_NE(r.out.find("24736 steps"), std::string::npos) << r.out;
}

TEST(Check, RefusesWhatRunRefuses) {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path c = write(d, "plate.toml", plate_case("plane-stress"));
  Result r = run_hexdem(d, "check " + c.string() + " --set time.dt=1e-6");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("exceeds the critical time step"), std::string::npos) << r.err;
  r = run_hexdem(d, "check " + c.string() + " --set time.dt=1e-6 --set time.allow_unstable=true");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("ABOVE the critical step"), std::string::npos) << r.out;
  r = run_hexdem(d, "check " + c.string() + " --set boundary.0.set=nowhere");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown boundary set 'nowhere'"), std::string::npos) << r.err;
}

// ---- sweep --------------------------------------------------------------------------------

std::vector<std::string> lines(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST(Sweep, GridRunsEveryMemberInItsFolder) {
  const fs::path d = test_dir("cli_workflow", true);
  write(d, "plate.toml", plate_case("plane-stress"));
  const fs::path study = write(d, "study.toml", R"([study]
case = "plate.toml"
name = "loads"
set = ["time.end=4e-6", "output.checkpoint_interval=0"]
outputs = ["kinetic", "elastic", "external_work", "broken_bonds", "fragments", "plate.vy"]
[[parameter]]
key = "load.0.p0"
values = [1e6, 2e6]
[[parameter]]
key = "material.concrete.E"
from = 30e9
to = 40e9
count = 2
)");
  const Result r = run_hexdem(d, "sweep " + study.string() + " --jobs 2 -j 1 -o " + (d / "out").string());
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const std::vector<std::string> rows = lines(slurp(d / "out" / "loads.csv"));
  ASSERT_EQ(rows.size(), 5u) << slurp(d / "out" / "loads.csv");
  EXPECT_EQ(rows[0], "member,load.0.p0,material.concrete.E,exit_code,kinetic,elastic,external_work,broken_bonds,fragments,plate.vy");
  EXPECT_EQ(rows[1].rfind("1,1e+06,3e+10,0,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("2,1e+06,4e+10,0,", 0), 0u) << rows[2];
  EXPECT_EQ(rows[3].rfind("3,2e+06,3e+10,0,", 0), 0u) << rows[3];
  EXPECT_EQ(rows[4].rfind("4,2e+06,4e+10,0,", 0), 0u) << rows[4];
  for (int k = 1; k <= 4; ++k) {
    const fs::path m = d / "out" / ("member-00" + std::to_string(k));
    EXPECT_EQ(slurp(m / "exit_code"), "0\n") << m;
    EXPECT_TRUE(fs::exists(m / "plate.pvd")) << m;
    EXPECT_TRUE(fs::exists(m / "plate.case.toml")) << m;
  }
  // Twice the load: twice the external work in the linear range.
  const auto m1 = read_row(d / "out" / "member-001" / "plate.summary.csv");
  const auto m3 = read_row(d / "out" / "member-003" / "plate.summary.csv");
  // (to 1e-5 measured: the normal springs' geometric nonlinearity)
  EXPECT_NEAR(std::stod(m3.at("external_work")) / std::stod(m1.at("external_work")), 4.0, 2e-4)
      << "work of a linear response grows with the load squared";
  EXPECT_NE(rows[1].find(",0,1,"), std::string::npos) << "no bond breaks, one fragment: " << rows[1];

  // Each member runs alone from its command line (e.g. in a cluster's job array).
  const std::vector<std::string> commands = lines(slurp(d / "out" / "commands.txt"));
  ASSERT_EQ(commands.size(), 4u);
  EXPECT_NE(commands[2].find("--set load.0.p0=2e+06 --set material.concrete.E=3e+10"), std::string::npos)
      << commands[2];
  fs::rename(d / "out" / "member-003", d / "out" / "first-003");
  const int code = std::system(("cd " + d.string() + " && sh -c \"$(sed -n 3p out/commands.txt)\"").c_str());
  EXPECT_EQ(code, 0);
  EXPECT_EQ(slurp(d / "out" / "member-003" / "plate.summary.csv"), slurp(d / "out" / "first-003" / "plate.summary.csv"));
  EXPECT_EQ(slurp(d / "out" / "member-003" / "exit_code"), "0\n") << "the line records its exit code";
  // --collect builds the same table from the folders without running anything.
  const std::string table = slurp(d / "out" / "loads.csv");
  fs::remove(d / "out" / "loads.csv");
  const Result c = run_hexdem(d, "sweep " + study.string() + " --collect -q -o " + (d / "out").string());
  EXPECT_EQ(c.code, 0) << c.err;
  EXPECT_EQ(slurp(d / "out" / "loads.csv"), table);
}

TEST(Sweep, DocumentedExampleStudyIsValid) {
  const fs::path d = test_dir("cli_workflow", true);
  const std::string study = std::string(HEXDEM_SOURCE_DIR) + "/cases/narrow_plate/study.toml";
  const Result r = run_hexdem(d, "sweep " + study + " --dry-run -o " + (d / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(count_lines(r.out), 6) << r.out;
  EXPECT_NE(r.out.find("--set load.0.p0=1e+07 --set load.0.function.t1=1e-04"), std::string::npos) << r.out;
}

TEST(Sweep, ListModeDryRunAndFailingMembers) {
  const fs::path d = test_dir("cli_workflow", true);
  write(d, "plate.toml", plate_case("plane-stress"));
  // Two members: a stable step and an unstable one that blows up (exit 4).
  const fs::path study = write(d, "steps.toml", R"([study]
case = "plate.toml"
combine = "list"
set = ["time.allow_unstable=true", "output.checkpoint_interval=0"]
[[parameter]]
key = "time.dt"
values = [1e-7, 1e-6]
[[parameter]]
key = "case.name"
values = ["small", "large"]
)");
  Result r = run_hexdem(d, "sweep " + study.string() + " --dry-run -o " + (d / "dry").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(count_lines(r.out), 2) << r.out;
  EXPECT_NE(r.out.find("--set time.dt=1e-06 --set 'case.name=\"large\"'"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(d / "dry" / "member-001")) << "a dry run runs nothing";
  EXPECT_EQ(slurp(d / "dry" / "commands.txt"), r.out);
  // Nothing ran: --collect finds no member (exit code -1 each) and reports failure.
  r = run_hexdem(d, "sweep " + study.string() + " --collect -q -o " + (d / "dry").string());
  EXPECT_EQ(r.code, 4);
  EXPECT_NE(slurp(d / "dry" / "steps.csv").find("\n2,1e-06,\"\"\"large\"\"\",-1,,"), std::string::npos)
      << slurp(d / "dry" / "steps.csv");

  r = run_hexdem(d, "sweep " + study.string() + " --jobs 2 -q -o " + (d / "out").string());
  EXPECT_EQ(r.code, 4) << "a member failed: " << r.err;
  EXPECT_EQ(slurp(d / "out" / "member-001" / "exit_code"), "0\n");
  EXPECT_EQ(slurp(d / "out" / "member-002" / "exit_code"), "4\n");
  EXPECT_NE(slurp(d / "out" / "member-002" / "run.log").find("numerical blow-up"), std::string::npos);
  const std::vector<std::string> rows = lines(slurp(d / "out" / "steps.csv"));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].rfind("member,time.dt,case.name,exit_code,time,step,kinetic,", 0), 0u) << rows[0];
  EXPECT_EQ(rows[1].rfind("1,1e-07,\"\"\"small\"\"\",0,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("2,1e-06,\"\"\"large\"\"\",4,,", 0), 0u) << "no values for a failed member: " << rows[2];
  EXPECT_TRUE(fs::exists(d / "out" / "member-001" / "small.summary.csv"));
}

TEST(Sweep, AMemberThatWarnsKeepsItsRowAndTheSweepExitsThree) {
  const fs::path d = test_dir("cli_workflow", true);
  write(d, "plate.toml", plate_case("plane-stress"));
  // The same plate twice: the default warning level, and one below the run's own round-off
  // error (which is above 1e-15 of the input), so that the second run warns and exits 3.
  const fs::path study = write(d, "warn.toml", R"([study]
case = "plate.toml"
combine = "list"
set = ["output.checkpoint_interval=0"]
[[parameter]]
key = "time.energy_warning"
values = [0.01, 1e-15]
)");
  const Result r = run_hexdem(d, "sweep " + study.string() + " --jobs 1 -o " + (d / "out").string());
  EXPECT_EQ(r.code, 3) << r.out << r.err;
  EXPECT_NE(r.out.find("2 of 2 members ran to the end, 1 of them with a warning"), std::string::npos) << r.out;
  EXPECT_EQ(slurp(d / "out" / "member-001" / "exit_code"), "0\n");
  EXPECT_EQ(slurp(d / "out" / "member-002" / "exit_code"), "3\n");
  EXPECT_EQ(slurp(d / "out" / "member-002" / "plate.status").rfind("completed with warning: energy error", 0), 0u)
      << slurp(d / "out" / "member-002" / "plate.status");
  const std::vector<std::string> rows = lines(slurp(d / "out" / "warn.csv"));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[2].rfind("2,1e-15,3,", 0), 0u) << rows[2];
  EXPECT_GT(rows[2].size(), std::string("2,1e-15,3,").size() + 5) << "a member that warned has its values: " << rows[2];
  // --collect reads the same exit codes.
  const Result c = run_hexdem(d, "sweep " + study.string() + " --collect -q -o " + (d / "out").string());
  EXPECT_EQ(c.code, 3) << c.err;
}

TEST(Sweep, BadStudiesAreRefusedBeforeAnythingRuns) {
  const fs::path d = test_dir("cli_workflow", true);
  write(d, "plate.toml", plate_case("plane-stress"));
  const std::string head = "[study]\ncase = \"plate.toml\"\n";
  const std::vector<std::pair<std::string, std::string>> cases{
      {head + "[[parameter]]\nkey = \"noise.seed\"\nvalues = [1, 2]\n",
       "plate.toml: --set noise.seed=1: unknown key 'noise'"},
      {head + "[[parameter]]\nkey = \"material.1.E\"\nvalues = [30e9, -1]\n", "member 2: "},
      {head + "outputs = [\"speed\"]\n[[parameter]]\nkey = \"time.end\"\nvalues = [1e-6]\n",
       "study.outputs: unknown output 'speed'"},
      {head + "combine = \"list\"\n[[parameter]]\nkey = \"time.end\"\nvalues = [1e-6, 2e-6]\n"
              "[[parameter]]\nkey = \"load.0.p0\"\nvalues = [1]\n",
       "needs as many values"},
      {head + "[[parameter]]\nkey = \"time.end\"\n", "give values, or from, to and count"},
      {head, "expected [[parameter]] tables"},
      {"[study]\ncase = \"none.toml\"\n", "cannot open case file"},
      {head + "jobs = 3\n", "study.jobs: unknown key 'jobs'"},
  };
  for (const auto& [text, message] : cases) {
    const fs::path study = write(d, "study.toml", text);
    const Result r = run_hexdem(d, "sweep " + study.string() + " -o " + (d / "out").string());
    EXPECT_EQ(r.code, 2) << text;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << text << "\n" << r.err;
    EXPECT_FALSE(fs::exists(d / "out")) << "nothing written for a refused study";
  }
}

/// A study of the plate with short members and no frames or checkpoints.
fs::path short_study(const fs::path& d, const std::string& name, const std::string& parameters,
                     const std::string& outputs = "[\"kinetic\", \"elastic\"]") {
  write(d, "plate.toml", plate_case("plane-stress"));
  return write(d, name, "[study]\ncase = \"plate.toml\"\noutputs = " + outputs +
                            "\nset = [\"time.end=2e-6\", \"output.frames=false\", \"output.checkpoint_interval=0\"]\n" +
                            parameters);
}

TEST(Sweep, EachMemberIsReadUnderItsOwnCaseName) {
  // A study that varies case.name: member k writes <its name>.summary.csv, and the table
  // takes its values from there (it read plate.summary.csv, and had empty outputs).
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path study = short_study(d, "names.toml", "[[parameter]]\nkey = \"case.name\"\nvalues = [\"a\", \"b\"]\n");
  const Result r = run_hexdem(d, "sweep " + study.string() + " -q -o " + (d / "out").string());
  EXPECT_EQ(r.code, 0) << r.err;
  const std::vector<std::string> rows = lines(slurp(d / "out" / "names.csv"));
  ASSERT_EQ(rows.size(), 3u);
  const auto a = read_row(d / "out" / "member-001" / "a.summary.csv");
  const auto b = read_row(d / "out" / "member-002" / "b.summary.csv");
  EXPECT_EQ(rows[1], "1,\"\"\"a\"\"\",0," + a.at("kinetic") + "," + a.at("elastic"));
  EXPECT_EQ(rows[2], "2,\"\"\"b\"\"\",0," + b.at("kinetic") + "," + b.at("elastic"));
  EXPECT_NE(rows[1].substr(rows[1].size() - 2), ",,") << rows[1];
}

TEST(Sweep, CollectCountsAMemberWithoutAWholeSummaryAsFailed) {
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path study =
      short_study(d, "bad.toml", "[[parameter]]\nkey = \"load.0.p0\"\nvalues = [1e6, 2e6, 3e6, 4e6, 5e6]\n");
  Result r = run_hexdem(d, "sweep " + study.string() + " -q -o " + (d / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const fs::path out = d / "out";
  // Exit code 0, but the summary is missing, only a header, or a short row; and a summary
  // without an exit code (the member's task did not end).
  fs::remove(out / "member-001" / "plate.summary.csv");
  const std::string header = lines(slurp(out / "member-002" / "plate.summary.csv"))[0];
  write(out / "member-002", "plate.summary.csv", header + "\n");
  write(out / "member-003", "plate.summary.csv", header + "\n1,2,3\n");
  fs::remove(out / "member-005" / "exit_code");
  r = run_hexdem(d, "sweep " + study.string() + " --collect -o " + out.string());
  EXPECT_EQ(r.code, 4) << "not every member ran to its end: " << r.out << r.err;
  EXPECT_NE(r.out.find("1 of 5 members ran to the end"), std::string::npos) << r.out;
  EXPECT_EQ(count_lines(r.err), 3) << r.err;
  EXPECT_NE(r.err.find("member-001: exit code 0, but its summary " + (out / "member-001" / "plate.summary.csv").string() +
                       " is missing"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("member-002: exit code 0, but its summary"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("member-003: exit code 0, but its summary"), std::string::npos) << r.err;
  const std::vector<std::string> rows = lines(slurp(out / "bad.csv"));
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[1], "1,1e+06,0,,");
  EXPECT_EQ(rows[2], "2,2e+06,0,,");
  EXPECT_EQ(rows[3], "3,3e+06,0,,");
  EXPECT_EQ(rows[4].rfind("4,4e+06,0,", 0), 0u);
  EXPECT_GT(rows[4].size(), std::string("4,4e+06,0,,").size()) << rows[4];
  EXPECT_EQ(rows[5], "5,5e+06,-1,,") << "a member without an exit code has not run: no values";
}

TEST(Sweep, ARerunLeavesNoStaleOutputsOfAMemberRefusedAtSetUp) {
  const fs::path d = test_dir("cli_workflow", true);
  fs::path study = short_study(d, "steps.toml", "[[parameter]]\nkey = \"time.dt\"\nvalues = [1e-7, 5e-8]\n");
  Result r = run_hexdem(d, "sweep " + study.string() + " -q -o " + (d / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(d / "out" / "member-002" / "plate.summary.csv"));
  // The same study again, member 2 now above the critical step: refused at set-up (exit 2),
  // it writes nothing, and the previous run's values must not appear in its row.
  study = short_study(d, "steps.toml", "[[parameter]]\nkey = \"time.dt\"\nvalues = [1e-7, 1e-6]\n");
  r = run_hexdem(d, "sweep " + study.string() + " -q -o " + (d / "out").string());
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_EQ(slurp(d / "out" / "member-002" / "exit_code"), "2\n");
  const std::vector<std::string> rows = lines(slurp(d / "out" / "steps.csv"));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[2], "2,1e-06,2,,") << "no values for a member refused at set-up";
  for (const char* f : {"plate.summary.csv", "plate.status", "plate.case.toml"})
    EXPECT_FALSE(fs::exists(d / "out" / "member-002" / f)) << f << ": the previous run's file is left";
  // A job array's line removes them too before the run.
  const std::vector<std::string> commands = lines(slurp(d / "out" / "commands.txt"));
  ASSERT_EQ(commands.size(), 2u);
  EXPECT_NE(commands[1].find("rm -f " + (d / "out" / "member-002" / "exit_code").string() + " " +
                             (d / "out" / "member-002" / "plate.summary.csv").string()),
            std::string::npos)
      << commands[1];
}

/// Starts `hexdem ARGS` in its own process group with its output in files of `dir`.
pid_t start_hexdem(const fs::path& dir, const std::vector<std::string>& args) {
  std::vector<std::string> all{HEXDEM_BINARY};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string out = (dir / "stdout.txt").string(), err = (dir / "stderr.txt").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(o, 1);
    ::dup2(e, 2);
    ::execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

/// The child process of `pid` (waits up to 30 s for one to start); 0 if none.
pid_t child_of(pid_t pid) {
  const fs::path children = "/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children";
  for (int k = 0; k < 3000; ++k) {
    std::ifstream in(children);
    pid_t child = 0;
    if (in >> child && child > 0) return child;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return 0;
}

/// A study of one long plate run per member (some 20 s each), two members one at a time.
fs::path long_study(const fs::path& d, const std::string& values) {
  write(d, "plate.toml", plate_case("plane-stress"));
  return write(d, "long.toml",
               "[study]\ncase = \"plate.toml\"\noutputs = [\"kinetic\"]\n"
               "set = [\"time.end=0.1\", \"output.frames=false\", \"output.checkpoint_interval=0\"]\n"
               "[[parameter]]\nkey = \"load.0.p0\"\nvalues = " +
                   values + "\n");
}

TEST(Sweep, ASignalIsForwardedToTheRunningMemberAndRecorded) {
  // SIGTERM to the sweep alone: the running member stops too (it ran on as an orphan and had
  // no exit code), the sweep records its exit code 143, starts no other member, writes the
  // table and ends by SIGTERM.
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path study = long_study(d, "[1e6, 2e6]");
  const pid_t sweep = start_hexdem(d, {"sweep", study.string(), "--jobs", "1", "-j", "1", "-o", (d / "out").string()});
  ASSERT_GT(sweep, 0);
  const pid_t member = child_of(sweep);
  ASSERT_GT(member, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(sweep, SIGTERM);
  int status = 0;
  ASSERT_EQ(::waitpid(sweep, &status, 0), sweep);
  const bool member_left = ::kill(member, 0) == 0;
  if (member_left) ::kill(member, SIGKILL);  // the orphan of a broken sweep
  EXPECT_FALSE(member_left) << "the member runs on after the sweep ended";
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "status " << status;
  EXPECT_EQ(slurp(d / "out" / "member-001" / "exit_code"), "143\n");
  EXPECT_FALSE(fs::exists(d / "out" / "member-002" / "exit_code")) << "no member starts after the signal";
  const std::string err = slurp(d / "stderr.txt");
  EXPECT_NE(err.find("interrupted by SIGTERM: 1 running member(s) stopped, 1 not run"), std::string::npos) << err;
  const std::vector<std::string> rows = lines(slurp(d / "out" / "long.csv"));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1], "1,1e+06,143,");
  EXPECT_EQ(rows[2], "2,2e+06,-1,");
  // --collect reads the same.
  const Result c = run_hexdem(d, "sweep " + study.string() + " --collect -q -o " + (d / "out").string());
  EXPECT_EQ(c.code, 4) << c.err;
}

TEST(Sweep, AMemberThatCrashesIsAnInternalError) {
  // A member that crashes (here SIGABRT, exit code 134 as a shell reports it: a failed
  // assertion; SIGSEGV would be caught by the sanitizers' handler of the ASan build, which
  // aborts) met an internal error: the sweep exits 1 (it exited 4, as for a numerical failure).
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path study = long_study(d, "[1e6]");
  const pid_t sweep = start_hexdem(d, {"sweep", study.string(), "-j", "1", "-o", (d / "out").string()});
  ASSERT_GT(sweep, 0);
  const pid_t member = child_of(sweep);
  ASSERT_GT(member, 0);
  ::kill(member, SIGABRT);
  int status = 0;
  ASSERT_EQ(::waitpid(sweep, &status, 0), sweep);
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_EQ(slurp(d / "out" / "member-001" / "exit_code"), "134\n");
  EXPECT_NE(slurp(d / "stdout.txt").find("1 met an internal error or crashed"), std::string::npos)
      << slurp(d / "stdout.txt");
  const Result c = run_hexdem(d, "sweep " + study.string() + " --collect -q -o " + (d / "out").string());
  EXPECT_EQ(c.code, 1) << c.err;
}

TEST(Sweep, OutputFolderAndCaseProblemsAreInputErrors) {
  // These were "internal error" (exit 1).
  const fs::path d = test_dir("cli_workflow", true);
  const fs::path study = short_study(d, "s.toml", "[[parameter]]\nkey = \"load.0.p0\"\nvalues = [1e6]\n");
  const fs::path file = write(d, "afile", "x\n");
  const std::vector<std::pair<std::string, std::string>> cases{
      {"-o " + file.string(), file.string() + ": cannot create the output folder (a file of that name exists)"},
      {"-o " + (file / "sub").string() + " --dry-run", (file / "sub").string() + ": cannot create the output folder ("},
      {"-o /proc/hexdem-sweep-test", "/proc/hexdem-sweep-test: cannot create the output folder ("},
      {"-o ''", "-o: expected an output folder (got \"\")"},
  };
  for (const auto& [options, message] : cases) {
    const Result r = run_hexdem(d, "sweep " + study.string() + " " + options);
    EXPECT_EQ(r.code, 2) << options << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << options << "\n" << r.err;
  }
  EXPECT_EQ(slurp(file), "x\n");
  const fs::path empty = write(d, "empty.toml", "[study]\ncase = \"\"\n[[parameter]]\nkey = \"time.end\"\nvalues = [1e-6]\n");
  const Result r = run_hexdem(d, "sweep " + empty.string() + " -o " + (d / "out").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("empty.toml:2: study.case: expected the path of the case file (got \"\")"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(d / "out"));
}

TEST(Sweep, StudyNameMustBeAPlainFileNameStem) {
  const fs::path d = test_dir("cli_workflow", true);
  write(d, "plate.toml", plate_case("plane-stress"));
  const std::string tail = "[[parameter]]\nkey = \"time.end\"\nvalues = [1e-6]\n";
  const std::vector<std::pair<std::string, std::string>> names{
      {"a\\nb", "must not hold control characters (got \"a\\nb\")"},
      {"..", "must be a plain file name stem, not '.' or '..' (got \"..\")"},
      {".", "must be a plain file name stem, not '.' or '..' (got \".\")"},
      {".hidden", "must not start with '.'"},
      {"", "must not be empty"},
      {"a/b", "must be a plain file name stem, without '/'"},
  };
  for (const auto& [name, message] : names) {
    const fs::path study = write(d, "study.toml", "[study]\ncase = \"plate.toml\"\nname = \"" + name + "\"\n" + tail);
    const Result r = run_hexdem(d, "sweep " + study.string() + " -o " + (d / "out").string());
    EXPECT_EQ(r.code, 2) << name << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("study.toml:3: study.name: " + message), std::string::npos) << name << "\n" << r.err;
    EXPECT_FALSE(fs::exists(d / "out")) << name;
  }
  // The default name, the study file's stem, is checked too: "..toml" has the stem ".".
  const fs::path dots = write(d, "..toml", "[study]\ncase = \"plate.toml\"\n" + tail);
  const Result r = run_hexdem(d, "sweep " + dots.string() + " --dry-run");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("the study file's stem \".\" does not make a study name"), std::string::npos) << r.err;
}

}  // namespace
