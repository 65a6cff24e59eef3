// Hostile input, round 3: inputs that once ran silently to a wrong result, hung, crashed, or
// were accepted by `hexdem check` and refused by `hexdem run`. Each must exit 2 with one line
// on stderr naming the file (and line or key) and the value, before any output is written.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/types.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hexdem::testing;

fs::path work_dir() { return test_dir("cli_input_checks", true); }

fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name, std::ios::binary) << text;
  return dir / name;
}

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }

/// `hexdem ARGS` with `prefix` before the program (an environment or `timeout 20`).
Result run_with(const fs::path& dir, const std::string& prefix, const std::string& args) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd =
      prefix + " " + std::string(HEXDEM_BINARY) + " " + args + " > " + out.string() + " 2> " + err.string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

/// A 10 x 20 mm plate: sets bottom, top and side; `extra` is appended (conditions, loads).
std::string plate_case(const std::string& extra, const std::string& body_name = "plate",
                       const std::string& time = "end = 1e-6") {
  return "[case]\ngeometry = \"plane-stress\"\n[lattice]\nradius = 0.5e-3\n[[body]]\nname = \"" + body_name +
         "\"\n" + R"([[body.shape]]
type = "rectangle"
min = [0, -0.02]
max = [0.01, 0]
boundary = { bottom = "bottom", top = "top", right = "side" }
[[material]]
id = 1
density = 2400.0
E = 30e9
nu = 0.2
)" + extra + "\n[time]\n" + time + "\n";
}

const std::string kFixedBottom = "[[boundary]]\nset = \"bottom\"\ntype = \"fixed\"\n";

/// Exit 2, one line on stderr starting "hexdem: error: " and containing every needle.
void expect_input_error(const Result& r, std::initializer_list<std::string> needles) {
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("hexdem: error: ", 0), 0U) << r.err;
  for (const std::string& n : needles) EXPECT_NE(r.err.find(n), std::string::npos) << n << " in " << r.err;
}

/// check and run both refuse, with the same line; run writes no output folder.
void expect_check_and_run_refuse(const fs::path& dir, const std::string& args, std::initializer_list<std::string> needles) {
  const Result check = run_hexdem(dir, "check " + args);
  expect_input_error(check, needles);
  const Result run = run_hexdem(dir, "run -q " + args + " -o " + quote(dir / "out"));
  expect_input_error(run, needles);
  EXPECT_EQ(check.err, run.err);
  EXPECT_FALSE(fs::exists(dir / "out" / "c.status"));
}

TEST(InputChecksCli, ContradictoryBoundaryConditionsAreRefused) {
  // Was: a set both fixed and given a velocity (or a roller in x and a velocity in x) ran to
  // "completed" with the velocity winning; the "fixed" set did work on the body.
  const fs::path dir = work_dir();
  const std::string fixed_and_velocity =
      kFixedBottom + "[[boundary]]\nset = \"bottom\"\ntype = \"velocity\"\nvy = 5.0\n";
  expect_check_and_run_refuse(dir, quote(write(dir, "c.toml", plate_case(fixed_and_velocity))),
                              {"c.toml:20: boundary[1]: velocity condition on set 'bottom' contradicts",
                               "c.toml:17: boundary[0] (fixed on set 'bottom')", "y velocity component",
                               "disk at ("});
  const std::string roller_and_velocity = kFixedBottom +
                                          "[[boundary]]\nset = \"side\"\ntype = \"roller\"\ncomponent = \"x\"\n"
                                          "[[boundary]]\nset = \"side\"\ntype = \"velocity\"\nvx = 5.0\n";
  expect_check_and_run_refuse(dir, quote(write(dir, "c.toml", plate_case(roller_and_velocity))),
                              {"boundary[2]: velocity condition on set 'side'", "boundary[1] (roller on set 'side')",
                               "x velocity component"});
  // Two velocity conditions on one disk, even on different components (a disk takes one).
  const std::string two_velocities = kFixedBottom + "[[boundary]]\nset = \"top\"\ntype = \"velocity\"\nvy = 1.0\n"
                                                    "[[boundary]]\nset = \"top\"\ntype = \"velocity\"\nvx = 1.0\n";
  expect_check_and_run_refuse(dir, quote(write(dir, "c.toml", plate_case(two_velocities))),
                              {"boundary[2]", "boundary[1]", "one velocity condition only"});
  // Allowed: conditions that hold the same component at zero (fixed and roller), and a velocity
  // on another component than a roller's.
  const std::string allowed = kFixedBottom +
                              "[[boundary]]\nset = \"bottom\"\ntype = \"roller\"\ncomponent = \"y\"\n"
                              "[[boundary]]\nset = \"side\"\ntype = \"roller\"\ncomponent = \"x\"\n"
                              "[[boundary]]\nset = \"top\"\ntype = \"velocity\"\nvy = -1.0\n";
  const Result ok = run_hexdem(dir, "check " + quote(write(dir, "ok.toml", plate_case(allowed))));
  EXPECT_EQ(ok.code, 0) << ok.err;
}

TEST(InputChecksCli, EndTimeShorterThanOneStepAndBadCriticalStepsAreInputErrors) {
  // Was: dt = -inf, `check` ok and `run` a "numerical blow-up" (exit 4); with a given dt the
  // run "completed" at t = 0.
  const fs::path dir = work_dir();
  const std::string c = quote(write(dir, "c.toml", plate_case(kFixedBottom)));
  expect_check_and_run_refuse(dir, c + " --set time.end=1e-17",
                              {"c.toml: [time] end = 1e-17 s is shorter than one time step (safety x critical"});
  expect_check_and_run_refuse(dir, c + " --set time.end=1e-17 --set time.dt=1e-7",
                              {"[time] end = 1e-17 s is shorter than one time step (dt = 1e-07 s)"});
  expect_check_and_run_refuse(dir, c + " --set material.1.E=1e-300", {"[time] end = 1e-06 s is shorter than one"});
  expect_check_and_run_refuse(dir, c + " --set material.1.density=1e300", {"shorter than one time step"});
  expect_check_and_run_refuse(dir, c + " --set material.1.density=1e-300",
                              {"[[material]] 'material-1' (id 1): density = 1e-300 kg/m^3, E = 3e+10 Pa",
                               "not a positive finite number"});
  for (const std::string t : {"1e-320", "1e308", "1e-300"})
    expect_check_and_run_refuse(dir, c + " --set case.thickness=" + t,
                                {"--set case.thickness=" + t + ": case.thickness: must lie in [1e-100, 1e100] m"});
}

TEST(InputChecksCli, CheckRefusesAProbeThatRunRefuses) {
  // Was: a probe outside the body passed `check` (exit 0, "0 warnings"); `run` refused it.
  const fs::path dir = work_dir();
  const std::string probe = kFixedBottom + "[[probe]]\nname = \"p\"\npoint = [0.05, 0.0]\n";
  expect_check_and_run_refuse(dir, quote(write(dir, "c.toml", plate_case(probe))),
                              {"probe[0]: probe 'p' selects no disk", "outside every body"});
}

TEST(InputChecksCli, WallsOverlappingDisksAndAxisymmetricProbesAtNegativeRadiusAreRefused) {
  // Was: a wall through the plate started the run with megajoules of contact energy (exit 0).
  const fs::path dir = work_dir();
  const std::string through = kFixedBottom + "[[wall]]\npoint = [0.0, -0.01]\nnormal = [0.0, 1.0]\n";
  expect_check_and_run_refuse(dir, quote(write(dir, "c.toml", plate_case(through))),
                              {"c.toml:20: wall[0]: the wall through (0, -0.01) m", "overlaps the disk at ("});
  // The normal pointing away from the body: every disk lies behind the wall.
  const std::string behind = kFixedBottom + "[[wall]]\npoint = [0.0, -0.021]\nnormal = [0.0, -1.0]\n";
  expect_check_and_run_refuse(dir, quote(write(dir, "c.toml", plate_case(behind))), {"wall[0]", "overlaps the disk"});
  // A wall one radius below the semi-disks of the bottom edge touches nothing: accepted.
  const std::string below = "[[wall]]\npoint = [0.0, -0.0205]\nnormal = [0.0, 1.0]\n";
  const Result ok = run_hexdem(dir, "check " + quote(write(dir, "ok.toml", plate_case(below))));
  EXPECT_EQ(ok.code, 0) << ok.err;
  // Axisymmetric: a probe at r < 0.
  const std::string probe = kFixedBottom + "[[probe]]\nname = \"p\"\npoint = [-0.0004, -0.005]\n";
  std::string axi = plate_case(probe);
  axi.replace(axi.find("plane-stress"), 12, "axisymmetric");
  expect_check_and_run_refuse(dir, quote(write(dir, "c.toml", axi)),
                              {"c.toml:22: probe[0].point: axisymmetric probes must lie in r >= 0"});
}

TEST(InputChecksCli, NamesThatBreakCsvHeadersAreRefusedWhereDefined) {
  // Was: a body or set name with a comma went unquoted into the CSV headers (exit 0).
  const fs::path dir = work_dir();
  expect_check_and_run_refuse(dir, quote(write(dir, "c.toml", plate_case(kFixedBottom, "pl,ate"))),
                              {"c.toml:6: body[0].name: a body name must not hold a comma or a double quote",
                               "pl,ate"});
  expect_check_and_run_refuse(dir, quote(write(dir, "c.toml", plate_case(kFixedBottom, "pl\\\"ate"))),
                              {"c.toml:6: body[0].name"});
  std::string set = plate_case("[[boundary]]\nset = \"ba,se\"\ntype = \"fixed\"\n");
  set.replace(set.find("bottom = \"bottom\""), 17, "bottom = \"ba,se\"");
  expect_check_and_run_refuse(dir, quote(write(dir, "c.toml", set)),
                              {"c.toml:11: body[0].shape[0].boundary", "a boundary set name must not hold a comma"});
  // `hexdem mesh` refuses the outline alike.
  const fs::path outline = write(dir, "o.toml",
                                 "[lattice]\nradius = 1e-3\n[[body]]\nname = \"a\\\"b\"\n[[body.shape]]\n"
                                 "type = \"rectangle\"\nmin = [0, 0]\nmax = [0.01, 0.01]\n");
  expect_input_error(run_hexdem(dir, "mesh " + quote(outline) + " -o " + quote(dir / "o.vtu")), {"o.toml:4: body[0].name"});
  EXPECT_FALSE(fs::exists(dir / "o.vtu"));
}

TEST(InputChecksCli, ThreadCountsAreBoundedForDashJAndTheEnvironment) {
  // Was: OMP_NUM_THREADS=100000 crashed (SIGSEGV), 1025 and -j 1024 under a 4 GB limit ended
  // in libgomp with exit 1; nothing named -j or OMP_NUM_THREADS.
  const fs::path dir = work_dir();
  const std::string c = quote(write(dir, "c.toml", plate_case(kFixedBottom)));
  for (const std::string cmd : {"check " + c, "run -q " + c + " -o " + quote(dir / "out")})
    expect_input_error(run_with(dir, "OMP_NUM_THREADS=100000", cmd), {"OMP_NUM_THREADS=100000: more threads than"});
  expect_input_error(run_with(dir, "OMP_NUM_THREADS=99999999999", "check " + c), {"OMP_NUM_THREADS=99999999999"});
  const unsigned hw = std::max(1U, std::thread::hardware_concurrency());
  if (4 * hw < 1024) {
    expect_input_error(run_hexdem(dir, "run -q -j 1024 " + c + " -o " + quote(dir / "out")),
                       {"-j 1024: more threads than " + std::to_string(4 * hw)});
    expect_input_error(run_with(dir, "OMP_NUM_THREADS=" + std::to_string(4 * hw + 1), "check " + c),
                       {"OMP_NUM_THREADS=" + std::to_string(4 * hw + 1)});
  }
  EXPECT_FALSE(fs::exists(dir / "out" / "c.status"));
  // Within the bound, and -j overriding the environment: accepted.
  EXPECT_EQ(run_with(dir, "OMP_NUM_THREADS=1", "check " + c).code, 0);
  EXPECT_EQ(run_with(dir, "OMP_NUM_THREADS=100000", "run -q -j 1 " + c + " -o " + quote(dir / "out")).code, 0);
}

TEST(InputChecksCli, FifosAreRefusedBeforeTheyAreOpened) {
  // Was: a FIFO as the case, outline, DXF or checkpoint blocked in open() for ever.
  const fs::path dir = work_dir();
  for (const std::string name : {"f.toml", "f.dxf", "f.chk"}) ASSERT_EQ(mkfifo((dir / name).c_str(), 0600), 0);
  const std::string t = "timeout 30";
  expect_input_error(run_with(dir, t, "check " + quote(dir / "f.toml")), {"f.toml: not a regular file"});
  expect_input_error(run_with(dir, t, "run -q " + quote(dir / "f.toml")), {"f.toml: not a regular file"});
  expect_input_error(run_with(dir, t, "mesh " + quote(dir / "f.dxf") + " -r 1e-3 -o " + quote(dir / "o.vtu")),
                     {"f.dxf: not a regular file"});
  expect_input_error(run_with(dir, t, "mesh " + quote(dir / "f.toml") + " -o " + quote(dir / "o.vtu")),
                     {"f.toml: not a regular file"});
  std::string fifo_outline = plate_case(kFixedBottom);
  const std::size_t from = fifo_outline.find("[lattice]"), to = fifo_outline.find("[[material]]");
  fifo_outline.replace(from, to - from, "[mesh]\noutline = \"f.toml\"\n");
  const std::string case_file = quote(write(dir, "c.toml", fifo_outline));
  expect_input_error(run_with(dir, t, "check " + case_file), {"c.toml:4: mesh.outline:", "is not a regular file"});
  const std::string c = quote(write(dir, "plate.toml", plate_case(kFixedBottom)));
  expect_input_error(run_with(dir, t, "run -q " + c + " --restart " + quote(dir / "f.chk") + " -o " + quote(dir / "out")),
                     {"f.chk: the checkpoint (--restart) is not a regular file"});
  EXPECT_FALSE(fs::exists(dir / "o.vtu"));
}

TEST(InputChecksCli, MeshRefusesToWriteOverItsOutline) {
  // Was: `hexdem mesh outline.toml -o outline.toml` replaced the outline by the .vtu.
  const fs::path dir = work_dir();
  const std::string text = "[lattice]\nradius = 1e-3\n[[body]]\nname = \"a\"\n[[body.shape]]\n"
                           "type = \"rectangle\"\nmin = [0, 0]\nmax = [0.01, 0.01]\n";
  const fs::path outline = write(dir, "o.toml", text);
  expect_input_error(run_hexdem(dir, "mesh " + quote(outline) + " -o " + quote(outline)),
                     {"the output is the outline itself"});
  // Another spelling of the same path, and a link to it.
  expect_input_error(run_hexdem(dir, "mesh " + quote(outline) + " -o " + quote(dir / "." / "o.toml")),
                     {"the output is the outline itself"});
  fs::create_symlink(outline, dir / "link.toml");
  expect_input_error(run_hexdem(dir, "mesh " + quote(dir / "link.toml") + " -o " + quote(outline)),
                     {"the output is the outline itself"});
  EXPECT_EQ(slurp(outline), text);
}

TEST(InputChecksCli, LatticesWithLooseDisksOrNoAreaAreRefused) {
  // Was: a spike narrower than the lattice meshed to 8 disks without any bond (exit 0), and
  // --scale 1e-300 meshed to cells of 0 m^2 (exit 0).
  const fs::path dir = work_dir();
  const fs::path spike =
      write(dir, "spike.toml",
            "units = \"mm\"\n[lattice]\nradius = 1.0\n[[body]]\nname = \"plate\"\n[[body.shape]]\n"
            "type = \"polygon\"\npoints = [[0, -20], [10, -20], [10, 0], [5.0001, 0], [5.0, 30.0], [4.9999, 0], [0, 0]]\n");
  expect_input_error(run_hexdem(dir, "mesh " + quote(spike) + " -o " + quote(dir / "s.vtu")),
                     {"spike.toml:4: body 'plate': 8 of the body's 75 disks have no bond", "the first at ("});
  EXPECT_FALSE(fs::exists(dir / "s.vtu"));
  const fs::path outline = write(dir, "o.toml",
                                 "[lattice]\nradius = 1e-3\n[[body]]\nname = \"a\"\n[[body.shape]]\n"
                                 "type = \"rectangle\"\nmin = [0, 0]\nmax = [0.01, 0.01]\n");
  expect_input_error(run_hexdem(dir, "mesh " + quote(outline) + " --scale 1e-300 -o " + quote(dir / "t.vtu")),
                     {"the cells' total area is 0 m^2 (--scale 1e-300)"});
  EXPECT_FALSE(fs::exists(dir / "t.vtu"));
  // The same outline at a sane scale meshes.
  const Result r = run_hexdem(dir, "mesh -q " + quote(outline) + " -o " + quote(dir / "t.vtu"));
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(InputChecksCli, DuplicateBodiesOfABodyForceAreRefused) {
  // Was: accepted, while duplicates in reactions and body_history are refused.
  const fs::path dir = work_dir();
  const std::string load = kFixedBottom +
                           "[[load]]\ntype = \"body-force\"\nacceleration = [0.0, -9.81]\nbodies = [\"plate\", \"plate\"]\n";
  expect_check_and_run_refuse(dir, quote(write(dir, "c.toml", plate_case(load))),
                              {"load[0].bodies[1]: duplicate body 'plate'"});
}

}  // namespace
