// Hostile input to the hexdem program, full disks and kill -9: every case here once crashed,
// ended as an internal error (exit 1), or succeeded silently with wrong or missing output.
// Bad input must exit 2 with one line on stderr naming the file or option and the value,
// and leave no output that looks valid.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_runner.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace hexdem::testing;

fs::path work_dir() { return test_dir("cli_hostile", true); }

fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name, std::ios::binary) << text;
  return dir / name;
}

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }

/// A one-body plate; `name_line` goes into [case], `time` and `output` replace the tables.
std::string plate_case(const std::string& name_line, const std::string& time,
                       const std::string& output = "", const std::string& extra = "") {
  return "[case]\n" + name_line + "\ngeometry = \"plane-stress\"\n" + R"([lattice]
radius = 0.5e-3
[[body]]
name = "plate"
[[body.shape]]
type = "rectangle"
min = [0, -0.02]
max = [0.01, 0]
boundary = { bottom = "bottom", top = "load" }
[[material]]
id = 1
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
)" + time + "\n[output]\n" + output + "\n" + extra;
}

/// Exit 2, one line on stderr containing `needle`, nothing on stdout.
void expect_input_error(const Result& r, const std::string& needle) {
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("hexdem: error: ", 0), 0U) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "") << r.out;
}

// ---- command line ----------------------------------------------------------------------

TEST(HostileCli, ThreadCountIsBounded) {
  // Was: -j 100000 crashed in libgomp.
  const fs::path dir = work_dir();
  const fs::path outline = write(dir, "o.toml", "[lattice]\nradius = 1e-3\n[[body]]\nname = \"a\"\n"
                                 "[[body.shape]]\ntype = \"rectangle\"\nmin = [0, 0]\nmax = [0.01, 0.01]\n");
  for (const std::string& cmd : {"mesh " + quote(outline), "run " + quote(write(dir, "c.toml", plate_case("", "end = 1e-6")))}) {
    const Result r = run_hexdem(dir, cmd + " -j 100000");
    EXPECT_EQ(r.code, 2) << cmd << r.err;
    EXPECT_NE(r.err.find("100000"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("1024"), std::string::npos) << r.err;
  }
  EXPECT_EQ(run_hexdem(dir, "mesh " + quote(outline) + " -j -3").code, 2);
}

TEST(HostileCli, CommandLineErrorsAreOneLine) {
  // Was: two lines (the parser's "Run with --help for more information." after the error), and
  // --max-disks 0 printed its range up to the largest double, all 309 digits of it.
  const fs::path dir = work_dir();
  const std::string c = quote(write(dir, "c.toml", plate_case("", "end = 1e-6")));
  expect_input_error(run_hexdem(dir, "run " + c + " -j -1"), "--threads: Value -1 not in range 0 to 1024");
  expect_input_error(run_hexdem(dir, "run " + c + " --max-disks 0"), "--max-disks: must be a whole number >= 1 (got 0)");
  expect_input_error(run_hexdem(dir, "mesh " + c + " --max-disks -5"), "--max-disks: must be a whole number >= 1 (got -5)");
  expect_input_error(run_hexdem(dir, "sweep " + c + " --jobs 0"), "--jobs: Value 0 not in range 1 to 65536");
  expect_input_error(run_hexdem(dir, "run"), "case is required");
  expect_input_error(run_hexdem(dir, "run " + c + " --no-such-option"), "--no-such-option");
  const Result help = run_hexdem(dir, "run --help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("Usage"), std::string::npos) << help.out;
}

TEST(HostileCli, LatticeAnglesBeyondATurnAreRefusedNamingTheKey) {
  // Was: `--set mesh.angle=1e308` overflowed the radians and blamed the disk radius ("too
  // large for the region (-inf x -inf m)"), and `hexdem mesh --angle 1e300` meshed at
  // whatever angle the rounding of 1e300 degrees left.
  const fs::path dir = work_dir();
  const std::string outline_text = "[lattice]\nradius = 1e-3\n[[body]]\nname = \"a\"\n"
                                   "[[body.shape]]\ntype = \"rectangle\"\nmin = [0, 0]\nmax = [0.01, 0.01]\n";
  const fs::path outline = write(dir, "angle.toml", outline_text);
  const fs::path plate = write(dir, "angle_case.toml", plate_case("", "end = 1e-6"));
  expect_input_error(run_hexdem(dir, "run " + quote(plate) + " --set mesh.angle=1e308"), "mesh.angle: must lie in [-360, 360] degrees (got 1e+308)");
  expect_input_error(run_hexdem(dir, "run " + quote(plate) + " --set mesh.angle=-361"), "mesh.angle");
  std::string lattice_case = plate_case("", "end = 1e-6");
  lattice_case.replace(lattice_case.find("radius = 0.5e-3"), 15, "radius = 0.5e-3\nangle = 400");
  expect_input_error(run_hexdem(dir, "run " + quote(write(dir, "angle_lattice.toml", lattice_case))),
                     "lattice.angle: must lie in [-360, 360] degrees (got 400)");
  const fs::path body = write(dir, "angle_body.toml",
                              "[lattice]\nradius = 1e-3\n[[body]]\nname = \"a\"\nangle = 1e300\n"
                              "[[body.shape]]\ntype = \"rectangle\"\nmin = [0, 0]\nmax = [0.01, 0.01]\n");
  expect_input_error(run_hexdem(dir, "mesh " + quote(body)), "body[0].angle: must lie in [-360, 360] degrees");
  const Result cli = run_hexdem(dir, "mesh " + quote(outline) + " --angle 1e300 -o " + quote(dir / "angle.vtu"));
  EXPECT_EQ(cli.code, 2) << cli.err;
  EXPECT_NE(cli.err.find("--angle"), std::string::npos) << cli.err;
  EXPECT_FALSE(fs::exists(dir / "angle.vtu"));
  // A turn and its negative are angles still (the lattice repeats every 60 degrees).
  EXPECT_EQ(run_hexdem(dir, "mesh " + quote(outline) + " --angle -360 -q -o " + quote(dir / "angle.vtu")).code, 0);
  EXPECT_EQ(run_hexdem(dir, "run " + quote(plate) + " -q --set mesh.angle=360 -o " + quote(dir / "angle_out")).code, 0);
}

TEST(HostileCli, DeeplyNestedTomlIsAnErrorNotACrash) {
  // Was: SIGSEGV with nothing printed.
  const fs::path dir = work_dir();
  std::string deep = "[[body]]\nname = \"a\"\n";
  for (int k = 0; k < 50000; ++k) deep += "x.";
  deep += "y = 1\n";
  const fs::path outline = write(dir, "deep.toml", deep);
  expect_input_error(run_hexdem(dir, "mesh " + quote(outline) + " -r 1e-3"),
                     outline.string() + ":3:");
  const fs::path c = write(dir, "deep_case.toml", "[case]\ngeometry = \"plane-stress\"\n[" + deep.substr(20, 60000) + "]\n");
  expect_input_error(run_hexdem(dir, "run " + quote(c)), "levels deep (limit 256)");
}

TEST(HostileCli, DevZeroAsOutlineIsCapped) {
  const fs::path dir = work_dir();
  fs::create_symlink("/dev/zero", dir / "zero.toml");
  expect_input_error(run_hexdem(dir, "mesh " + quote(dir / "zero.toml") + " -r 1e-3"),
                     "zero.toml: not a regular file");  // refused before it is read
}

// ---- DXF fixtures of the project ---------------------------------------------------------

fs::path dxf_fixture(const std::string& name) {
  const fs::path dir = fs::path(HEXDEM_TEST_WORK_DIR) / "dxf_cli_hostile";
  if (!fs::exists(dir / "fixtures.stamp")) {
    const std::string command = std::string("\"") + HEXDEM_SYSTEM_PYTHON + "\" \"" +
                                HEXDEM_TEST_DATA_DIR + "/make_dxf_fixtures.py\" \"" +
                                dir.string() + "\" > /dev/null";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
  }
  return dir / name;
}

TEST(HostileCli, UnitlessDxfFixtureAtSmallRadiusIsRefusedWithTheCount) {
  // Was: std::bad_alloc (an internal error) or hours of meshing: the drawing has no units,
  // reads as metres, and r = 0.5 mm asks for 6.8e8 disks.
  const fs::path dir = work_dir();
  for (const std::string name : {"h_arc_lines.dxf", "l_arc_mirrored.dxf"}) {
    const Result r = run_hexdem(dir, "mesh " + quote(dxf_fixture(name)) + " -r 0.5e-3 -o " +
                                         quote(dir / "out.vtu"));
    expect_input_error(r, name + ": about 6.7");
    EXPECT_NE(r.err.find("e+08 disks"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("limit of 100000000"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--max-disks N"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out.vtu"));
  }
  // --scale 1e-3 (millimetres) makes it a small mesh; --max-disks below its count refuses it.
  const std::string args = "mesh " + quote(dxf_fixture("h_arc_lines.dxf")) +
                           " -r 0.5e-3 --scale 1e-3 -q -o " + quote(dir / "out.vtu");
  EXPECT_EQ(run_hexdem(dir, args).code, 0);
  expect_input_error(run_hexdem(dir, args + " --max-disks 100"), "limit of 100 ");
  EXPECT_EQ(run_hexdem(dir, args + " --max-disks 0").code, 2);
}

TEST(HostileCli, LayerNamedLikeAPointArrayIsExitTwo) {
  // Was: "internal error: point array 'body' appears twice" (exit 1) for the fixture.
  const fs::path dir = work_dir();
  const Result r = run_hexdem(dir, "mesh " + quote(dxf_fixture("g_skipped_types.dxf")) +
                                       " -r 0.5e-3 -o " + quote(dir / "g.vtu"));
  EXPECT_EQ(r.code, 2) << r.err;
  // The warnings about skipped entities, then the error.
  const std::string last = r.err.substr(r.err.rfind('\n', r.err.size() - 2) + 1);
  EXPECT_EQ(last.rfind("hexdem: error: ", 0), 0U) << r.err;
  EXPECT_NE(last.find("g_skipped_types.dxf: boundary set (layer) name 'body' is reserved"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "g.vtu"));
}

// ---- case name ---------------------------------------------------------------------------

TEST(HostileCli, CaseNameMustBeAFileStem) {
  // Was: "../x" and absolute names wrote outside --out; a NUL wrote every file to one file;
  // "a/b" failed late and left header-only CSVs.
  const fs::path dir = work_dir();
  for (const std::string name : {"../x", "/tmp/hexdem_abs", "a/b", "a\\u0000b", ".", "..", "a\\nb"}) {
    fs::remove_all(dir / "out");
    const fs::path c = write(dir, "c.toml", plate_case("name = \"" + name + "\"", "end = 1e-6"));
    const Result r = run_hexdem(dir, "run " + quote(c) + " -o " + quote(dir / "out"));
    expect_input_error(r, "c.toml:2: case.name: ");
    EXPECT_FALSE(fs::exists(dir / "out")) << name;
  }
  EXPECT_FALSE(fs::exists("/tmp/hexdem_abs.pvd"));
  EXPECT_FALSE(fs::exists(dir / "x.pvd"));
}

TEST(HostileCli, CaseFileStemThatIsNoNameIsRefused) {
  const fs::path dir = work_dir();
  const fs::path c = write(dir, "..toml", plate_case("", "end = 1e-6"));
  expect_input_error(run_hexdem(dir, "run " + quote(c) + " -o " + quote(dir / "out")),
                     "the file name does not make a case name");
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(HostileCli, DiskLimitOfACase) {
  const fs::path dir = work_dir();
  const fs::path c = write(dir, "c.toml", plate_case("name = \"p\"", "end = 1e-6", "",
                                                     "[mesh]\nmax_disks = 100\n"));
  // The plate has 252 disks.
  const Result r = run_hexdem(dir, "run " + quote(c) + " -o " + quote(dir / "out"));
  expect_input_error(r, "limit of 100 ");
  EXPECT_NE(r.err.find("[mesh] max_disks = N or --max-disks N"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  EXPECT_EQ(run_hexdem(dir, "run " + quote(c) + " -q --max-disks 300 -o " + quote(dir / "out")).code, 0);
  expect_input_error(run_hexdem(dir, "run " + quote(c) + " --max-disks 5 -o " + quote(dir / "out2")),
                     "limit of 5 ");
  const fs::path bad = write(dir, "bad.toml", plate_case("name = \"p\"", "end = 1e-6", "",
                                                         "[mesh]\nmax_disks = 0\n"));
  expect_input_error(run_hexdem(dir, "run " + quote(bad)), "mesh.max_disks: must lie in [1, ");
}

TEST(HostileCli, DiskLimitComesBeforeTheLoopsAreValidated) {
  // Was: the limit of `hexdem mesh` (and of a case) was checked by the generator, after the
  // loops' validation: 3,000 nested circles at r = 0.5 m (1.6e10 disks) took 70 s and 4.3 GB
  // before being refused. The readers now check the caller's limit first. Two overlapping
  // 10 m squares at r = 0.5 mm (about 2.3e8 disks estimated) show the order: the size message, not the
  // validation's, unless the limit is raised.
  const fs::path dir = work_dir();
  const fs::path o = write(dir, "squares.toml", R"([lattice]
radius = 0.5e-3
[[body]]
name = "a"
[[body.shape]]
type = "rectangle"
min = [0, 0]
max = [10, 10]
[[body]]
name = "b"
[[body.shape]]
type = "rectangle"
min = [5, 5]
max = [15, 15]
)");
  expect_input_error(run_hexdem(dir, "mesh " + quote(o) + " -o " + quote(dir / "squares.vtu")), "limit of 100000000 ");
  expect_input_error(run_hexdem(dir, "mesh " + quote(o) + " --max-disks 1000000 -o " + quote(dir / "squares.vtu")),
                     "limit of 1000000 (the mesh alone would need about");
  expect_input_error(run_hexdem(dir, "mesh " + quote(o) + " --max-disks 1000000000 -o " + quote(dir / "squares.vtu")),
                     "overlaps");
  EXPECT_FALSE(fs::exists(dir / "squares.vtu"));
  // A case reading that outline: its [mesh] max_disks, or `hexdem run --max-disks`, first.
  const fs::path c = write(dir, "squares_case.toml", "[case]\nname = \"squares\"\ngeometry = \"plane-stress\"\n"
                                                 "[mesh]\noutline = \"squares.toml\"\n"
                                                 "[[material]]\nid = 1\ndensity = 2400.0\nE = 30e9\nnu = 0.2\n"
                                                 "[time]\nend = 1e-6\n");
  const Result r = run_hexdem(dir, "run " + quote(c) + " -o " + quote(dir / "out_squares"));
  expect_input_error(r, "limit of 100000000 ");
  EXPECT_NE(r.err.find("[mesh] max_disks = N or --max-disks N"), std::string::npos) << r.err;
  expect_input_error(run_hexdem(dir, "run " + quote(c) + " --max-disks 1000000000 -o " + quote(dir / "out_squares")),
                     "overlaps");
  EXPECT_FALSE(fs::exists(dir / "out_squares"));
}

// ---- time control --------------------------------------------------------------------------

TEST(HostileCli, StepCountOverflowIsRefused) {
  // Was: "-9223372036854775808 steps", "done: 0 frames", exit 0 and no .pvd.
  const fs::path dir = work_dir();
  const fs::path end = write(dir, "end.toml", plate_case("name = \"p\"", "end = 1e13"));
  expect_input_error(run_hexdem(dir, "run " + quote(end) + " -o " + quote(dir / "out")),
                     "end.toml: [time] end = 1e+13 s at dt = ");
  EXPECT_FALSE(fs::exists(dir / "out" / "p.pvd"));
  EXPECT_FALSE(fs::exists(dir / "out" / "p.energy.csv"));
  const fs::path dt = write(dir, "dt.toml", plate_case("name = \"p\"", "end = 1e-6\ndt = 1e-300"));
  expect_input_error(run_hexdem(dir, "run " + quote(dt) + " -o " + quote(dir / "out")),
                     "dt.toml:31: time.dt: end / dt = 9.99");
}

TEST(HostileCli, TinyOutputIntervalEndsWithAFramePerStep) {
  // Was: an endless loop after the first frame.
  const fs::path dir = work_dir();
  const fs::path c = write(dir, "c.toml", plate_case("name = \"p\"", "end = 1e-6", "interval = 1e-300"));
  const Result q = run_hexdem(dir, "run " + quote(c) + " -o " + quote(dir / "out"));
  ASSERT_EQ(q.code, 0) << q.err;
  const std::smatch m = [&] {
    std::smatch s;
    std::regex_search(q.out, s, std::regex("(\\d+) steps to t"));
    return s;
  }();
  ASSERT_FALSE(m.empty()) << q.out;
  const int steps = std::stoi(m[1]);
  EXPECT_NE(q.out.find("done: " + std::to_string(steps + 1) + " frames"), std::string::npos) << q.out;
}

// ---- output folder -------------------------------------------------------------------------

TEST(HostileCli, OutputFolderProblemsAreExitTwoWithThePath) {
  // Was: "internal error" (exit 1) for each of these.
  const fs::path dir = work_dir();
  const fs::path c = write(dir, "c.toml", plate_case("name = \"p\"", "end = 1e-6"));
  write(dir, "afile", "x");
  expect_input_error(run_hexdem(dir, "run " + quote(c) + " -o " + quote(dir / "afile")),
                     (dir / "afile").string() + ": cannot create the output folder (a file of that name exists)");
  expect_input_error(run_hexdem(dir, "run " + quote(c) + " -o /proc/hexdem-out"),
                     "/proc/hexdem-out: cannot create the output folder (");
  // A frame name that is a folder.
  fs::create_directories(dir / "out" / "p" / "p_000000000.vtu" / "keep");
  const Result frame = run_hexdem(dir, "run " + quote(c) + " -q -o " + quote(dir / "out"));
  expect_input_error(frame, "cannot write '" + (dir / "out" / "p" / "p_000000000.vtu").string() +
                                "': rename failed: Is a directory");
  EXPECT_FALSE(fs::exists(dir / "out" / "p.pvd"));
  // The mesh command: an output path in a folder that does not exist.
  const fs::path outline = write(dir, "o.toml", "[lattice]\nradius = 1e-3\n[[body]]\nname = \"a\"\n"
                                 "[[body.shape]]\ntype = \"rectangle\"\nmin = [0, 0]\nmax = [0.01, 0.01]\n");
  expect_input_error(run_hexdem(dir, "mesh " + quote(outline) + " -o " + quote(dir / "nope" / "x.vtu")),
                     "cannot write '" + (dir / "nope" / "x.vtu").string() + "'");
}

TEST(HostileCli, RefusedRunsLeaveAFinishedFolderAsItWas) {
  // Was: a restart refused for a CSV that another run had changed (exit 2, the right line)
  // had already deleted the frames after the checkpoint, left them in the .pvd and set the
  // status to "running"; a probe outside every body left a folder with a "running" status,
  // empty CSVs and an empty frame folder; an empty outline name was an internal error.
  const fs::path dir = work_dir();
  const fs::path c = write(dir, "r.toml", plate_case("name = \"r\"", "end = 1e-6",
                                                     "interval = 2e-7\ncheckpoint_interval = 3e-7"));
  const fs::path out = dir / "r_out";
  ASSERT_EQ(run_hexdem(dir, "run " + quote(c) + " -q -j 1 -o " + quote(out)).code, 0);
  const auto listing = [&] {
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(out)) names.push_back(e.path().string());
    std::sort(names.begin(), names.end());
    return names;
  };
  const std::vector<std::string> before = listing();
  const std::string pvd = slurp(out / "r.pvd"), status = slurp(out / "r.status");
  ASSERT_NE(status.find("completed"), std::string::npos) << status;
  std::string energy = slurp(out / "r.energy.csv");
  energy[energy.find('\n') + 1] = '9';  // another run has written the CSV since
  write(out, "r.energy.csv", energy);
  expect_input_error(run_hexdem(dir, "run " + quote(c) + " -j 1 --restart " + quote(out / "r.chk")),
                     "r.energy.csv: its first");
  EXPECT_EQ(listing(), before);
  EXPECT_EQ(slurp(out / "r.pvd"), pvd);
  EXPECT_EQ(slurp(out / "r.status"), status);
  EXPECT_EQ(slurp(out / "r.energy.csv"), energy);

  std::string far = plate_case("name = \"f\"", "end = 1e-6");
  far.replace(far.find("point = [0.005, 0.0]"), 20, "point = [5.0, 0.0]");
  expect_input_error(run_hexdem(dir, "run " + quote(write(dir, "f.toml", far)) + " -o " + quote(dir / "f_out")),
                     "probe 'top' selects no disk");
  EXPECT_FALSE(fs::exists(dir / "f_out"));

  expect_input_error(run_hexdem(dir, "check " + quote(c) + " --set 'mesh.outline=\"\"'"), "mesh.outline");
}

// ---- full disks ----------------------------------------------------------------------------

/// Mounts a small tmpfs at `dir` (root only); false if that is not possible here.
bool mount_tmpfs(const fs::path& dir, const std::string& options) {
  fs::create_directories(dir);
  const std::string cmd = "mount -t tmpfs -o " + options + " tmpfs " + quote(dir) + " 2> /dev/null";
  return std::system(cmd.c_str()) == 0;
}

void unmount(const fs::path& dir) {
  const std::string cmd = "umount " + quote(dir) + " 2> /dev/null";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
}

TEST(HostileCli, FullDiskFailsTheRunNamingTheFile) {
  // Was: with frames = false the CSVs filled the disk and the run exited 0 with truncated
  // probes.csv and bodies.csv.
  const fs::path dir = work_dir();
  const fs::path disk = dir / "disk";
  if (!mount_tmpfs(disk, "size=64k")) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  const fs::path c = write(dir, "c.toml", plate_case("name = \"p\"", "end = 2e-4",
                                                     "frames = false\nbody_history = [\"plate\"]"));
  const Result r = run_hexdem(dir, "run " + quote(c) + " -q -o " + quote(disk / "out"));
  unmount(disk);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(".csv: write failed (No space left on device)"), std::string::npos) << r.err;
}

TEST(HostileCli, FullDiskWhileWritingFramesFailsNamingTheFrame) {
  const fs::path dir = work_dir();
  const fs::path disk = dir / "disk";
  if (!mount_tmpfs(disk, "size=64k")) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  const fs::path c = write(dir, "c.toml", plate_case("name = \"p\"", "end = 2e-5", "interval = 1e-7"));
  const Result r = run_hexdem(dir, "run " + quote(c) + " -q -o " + quote(disk / "out"));
  std::vector<std::string> leftovers;
  for (const auto& e : fs::recursive_directory_iterator(disk))
    if (e.path().extension() == ".tmp" || e.path().string().find(".tmp") != std::string::npos)
      leftovers.push_back(e.path().string());
  unmount(disk);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_TRUE(leftovers.empty()) << leftovers.front();
}

TEST(HostileCli, ReadOnlyOutputFolderIsExitTwo) {
  const fs::path dir = work_dir();
  const fs::path disk = dir / "ro";
  if (!mount_tmpfs(disk, "ro,size=64k")) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  const fs::path c = write(dir, "c.toml", plate_case("name = \"p\"", "end = 1e-6"));
  const Result r = run_hexdem(dir, "run " + quote(c) + " -q -o " + quote(disk / "out"));
  unmount(disk);
  expect_input_error(r, (disk / "out").string() + ": cannot create the output folder (Read-only file system)");
}

// ---- kill -9 -------------------------------------------------------------------------------

std::vector<std::string> read_lines(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

long long last_listed_step(const fs::path& pvd) {
  const std::string text = slurp(pvd);
  long long step = -1;
  const std::regex re("_(\\d{9})\\.vtu");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
    step = std::max(step, std::stoll((*it)[1]));
  return step;
}

TEST(HostileCli, KillNineLeavesWholeCsvRowsAtOrAfterTheLastFrame) {
  // Was: a truncated last line in 17 of 20 (probes) and 32 of 35 (bodies) trials, and CSVs
  // far behind the frames.
  const fs::path dir = work_dir();
  const fs::path c = write(dir, "c.toml", plate_case("name = \"p\"", "end = 1.0", "interval = 2e-5\nbody_history = [\"plate\"]"));
  int trials_with_frames = 0;
  for (const int delay_ms : {700, 1300, 1900}) {
    fs::remove_all(dir / "out");
    std::string bin = HEXDEM_BINARY;
    const std::string out = (dir / "out").string(), cs = c.string();
    std::vector<char*> argv = {bin.data(), const_cast<char*>("run"), const_cast<char*>(cs.c_str()),
                               const_cast<char*>("-q"), const_cast<char*>("-j"), const_cast<char*>("1"),
                               const_cast<char*>("-o"), const_cast<char*>(out.c_str()), nullptr};
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    pid_t pid = 0;
    ASSERT_EQ(posix_spawn(&pid, bin.c_str(), &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
    // The delays count from the start of the output (the status file, written just before the
    // CSVs are opened), not from the spawn: a slow build (sanitizers) on a loaded machine can
    // spend longer than the shortest delay in its set-up, and a run killed there has written
    // nothing, which is not what this test is about.
    const fs::path status_file = dir / "out" / "p.status";
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!fs::exists(status_file) && std::chrono::steady_clock::now() < give_up)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ASSERT_TRUE(fs::exists(status_file)) << "the run wrote no status within 120 s";
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed";

    const long long frame_step = last_listed_step(dir / "out" / "p.pvd");
    if (frame_step >= 0) ++trials_with_frames;
    for (const std::string name : {"p.probes.csv", "p.bodies.csv", "p.energy.csv"}) {
      const fs::path csv = dir / "out" / name;
      ASSERT_TRUE(fs::exists(csv)) << name;
      const std::string text = slurp(csv);
      ASSERT_FALSE(text.empty()) << name;
      EXPECT_EQ(text.back(), '\n') << name << ": truncated last row";
      const std::vector<std::string> rows = read_lines(csv);
      const auto commas = [](const std::string& s) { return std::count(s.begin(), s.end(), ','); };
      for (const std::string& row : rows) EXPECT_EQ(commas(row), commas(rows.front())) << name << ": " << row;
      if (frame_step >= 0) {
        ASSERT_GE(rows.size(), 2U) << name;
        const std::string& last = rows.back();
        const long long step = std::stoll(last.substr(last.find(',') + 1));
        EXPECT_GE(step, frame_step) << name << " lags the frames";
      }
    }
  }
  EXPECT_GT(trials_with_frames, 0);
}

}  // namespace
