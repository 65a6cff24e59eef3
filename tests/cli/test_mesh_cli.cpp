// End-to-end tests of `hexdem mesh`: exit codes, one-line errors naming the file, key or
// line and value, warnings, and no output file left behind on failure.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hexdem::testing;

fs::path work_dir() { return test_dir("cli", false); }

Result run(const std::string& args) { return run_hexdem(work_dir(), args); }

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = work_dir() / name;
  std::ofstream(p) << text;
  return p;
}

const char* kGood = R"(
[lattice]
radius = 0.001
[[body]]
name = "plate"
  [[body.shape]]
  type = "rectangle"
  min = [0.0, 0.0]
  max = [0.05, 0.03]
  boundary = { bottom = "base", right = "right", top = "top", left = "left" }
)";

/// Runs `hexdem mesh` on a bad input and checks the error contract.
void expect_input_error(const std::string& input_args, const fs::path& output,
                        std::initializer_list<std::string> must_contain) {
  fs::remove(output);
  const Result r = run("mesh " + input_args + " -o " + output.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("hexdem: error: ", 0), 0u) << r.err;
  for (const std::string& s : must_contain) EXPECT_NE(r.err.find(s), std::string::npos) << "missing '" << s << "' in: " << r.err;
  EXPECT_FALSE(fs::exists(output)) << "output left behind";
  for (const auto& e : fs::directory_iterator(output.parent_path())) {
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << "temporary left: " << e.path();
  }
}

TEST(MeshCli, VersionAndHelp) {
  Result r = run("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("hexdem 0."), std::string::npos) << r.out;
  r = run("mesh --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--radius"), std::string::npos);
  EXPECT_NE(r.out.find("--axisymmetric"), std::string::npos);
}

TEST(MeshCli, GoodOutlinePrintsSummaryAndWritesVtu) {
  const fs::path in = write("good.toml", kGood), out = work_dir() / "good.vtu";
  fs::remove(out);
  const Result r = run("mesh " + in.string() + " -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out));
  for (const char* key : {"disks", "semi-disks", "bonds", "area", "error", "time", "generation"}) {
    EXPECT_NE(r.out.find(key), std::string::npos) << key << " not in summary:\n" << r.out;
  }
  EXPECT_TRUE(r.err.empty()) << r.err;
}

// --jitter: the summary says how many disks moved, the file differs from the regular lattice's
// and is the same for the same seed; out of range exits 2 with one line and no file.
TEST(MeshCli, JitterMovesTheInteriorDisks) {
  const fs::path in = write("jitter.toml", kGood);
  const fs::path regular = work_dir() / "regular.vtu", a = work_dir() / "jitter_a.vtu", b = work_dir() / "jitter_b.vtu";
  ASSERT_EQ(run("mesh " + in.string() + " -o " + regular.string()).code, 0);
  const Result r = run("mesh " + in.string() + " --jitter 0.2 --jitter-seed 3 -o " + a.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("interior disks moved by up to 0.2 r (seed 3)"), std::string::npos) << r.out;
  ASSERT_EQ(run("mesh " + in.string() + " --jitter 0.2 --jitter-seed 3 -o " + b.string()).code, 0);
  const auto bytes = [](const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  EXPECT_EQ(bytes(a), bytes(b));
  EXPECT_NE(bytes(a), bytes(regular));
  const fs::path bad = work_dir() / "jitter_bad.vtu";
  fs::remove(bad);
  const Result e = run("mesh " + in.string() + " --jitter 0.5 -o " + bad.string());
  EXPECT_EQ(e.code, 2);
  EXPECT_EQ(count_lines(e.err), 1) << e.err;
  EXPECT_NE(e.err.find("--jitter"), std::string::npos) << e.err;
  EXPECT_FALSE(fs::exists(bad));
}

TEST(MeshCli, MissingFile) {
  expect_input_error((work_dir() / "nope.toml").string(), work_dir() / "o1.vtu", {"nope.toml", "cannot open"});
}

TEST(MeshCli, EmptyFile) {
  const fs::path in = write("empty.toml", "");
  expect_input_error(in.string(), work_dir() / "o2.vtu", {"empty.toml"});
}

TEST(MeshCli, SelfIntersectingOutline) {
  const fs::path in = write("bowtie.toml", R"([lattice]
radius = 0.001
[[body]]
name = "bowtie"
  [[body.shape]]
  type = "polygon"
  points = [[0.0, 0.0], [0.05, 0.05], [0.05, 0.0], [0.0, 0.05]]
)");
  expect_input_error(in.string(), work_dir() / "o3.vtu", {"bowtie.toml", "self-intersect"});
}

TEST(MeshCli, OpenOutline) {
  const fs::path in = write("open.toml", R"([lattice]
radius = 0.001
[[body]]
name = "open"
  [[body.shape]]
  type = "path"
  start = [0.0, 0.0]
  segments = [ { to = [0.05, 0.0] }, { to = [0.05, 0.05] }, { to = [0.0, 0.05] } ]
)");
  expect_input_error(in.string(), work_dir() / "o4.vtu", {"open.toml", "open"});
}

TEST(MeshCli, HoleOutsideBoundary) {
  const fs::path in = write("hole.toml", R"([lattice]
radius = 0.001
[[body]]
name = "holed"
  [[body.shape]]
  type = "rectangle"
  min = [0.0, 0.0]
  max = [0.05, 0.05]
  [[body.shape]]
  type = "circle"
  role = "hole"
  center = [0.2, 0.2]
  radius = 0.01
)");
  expect_input_error(in.string(), work_dir() / "o5.vtu", {"hole.toml", "hole"});
}

TEST(MeshCli, OverlappingBodies) {
  const fs::path in = write("overlap.toml", R"([lattice]
radius = 0.001
[[body]]
name = "a"
  [[body.shape]]
  type = "rectangle"
  min = [0.0, 0.0]
  max = [0.05, 0.05]
[[body]]
name = "b"
  [[body.shape]]
  type = "rectangle"
  min = [0.04, 0.04]
  max = [0.09, 0.09]
)");
  expect_input_error(in.string(), work_dir() / "o6.vtu", {"overlap.toml", "overlap"});
}

TEST(MeshCli, NonPositiveRadius) {
  const fs::path in = write("good2.toml", kGood);
  expect_input_error(in.string() + " --radius -0.001", work_dir() / "o7.vtu", {"--radius", "-0.001"});
  expect_input_error(in.string() + " --radius 0", work_dir() / "o7.vtu", {"--radius", "0"});
}

TEST(MeshCli, RadiusLargerThanRegion) {
  const fs::path in = write("good3.toml", kGood);
  expect_input_error(in.string() + " --radius 0.5", work_dir() / "o8.vtu", {"plate", "0.5", "too large"});
}

TEST(MeshCli, UnknownOutlineFormat) {
  const fs::path in = write("shape.stl", "solid x\n");
  expect_input_error(in.string(), work_dir() / "o9.vtu", {"shape.stl", ".stl"});
}

TEST(MeshCli, BadCommandLine) {
  const Result r = run("mesh");
  EXPECT_EQ(r.code, 2);
  const Result r2 = run("mesh x.toml --compression-level 12");
  EXPECT_EQ(r2.code, 2);
}

TEST(MeshCli, DxfWithUnsupportedEntitiesWarnsAndMeshes) {
  const fs::path dxf = work_dir() / "with_text.dxf";
  const std::string py = std::string(HEXDEM_SYSTEM_PYTHON) + " -c \"import ezdxf; d = ezdxf.new(); m = d.modelspace(); "
                         "m.add_lwpolyline([(0,0),(50,0),(50,30),(0,30)], close=True); "
                         "m.add_text('label'); m.add_point((1,1)); d.saveas('" + dxf.string() + "')\"";
  ASSERT_EQ(std::system(py.c_str()), 0);
  const fs::path out = work_dir() / "with_text.vtu";
  fs::remove(out);
  const Result r = run("mesh " + dxf.string() + " --radius 0.001 --scale 0.001 -o " + out.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out));
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("TEXT"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("POINT"), std::string::npos) << r.err;
}

}  // namespace
