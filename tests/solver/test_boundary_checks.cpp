// A body that crosses (or lies beyond) the mirror plane of a symmetry condition is refused
// (check_symmetry_planes, docs/case-format.md "Where a condition acts"): by the function, by
// the Solver, and by `hexdem run` with exit code 2, one line and no output.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "../cli/cli_runner.hpp"
#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/solver/boundary_checks.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;
namespace fs = std::filesystem;

/// A 20 x 5 mm plate (sets: `sym` on its left edge x = 0, `base` at its bottom y = -5 mm) and
/// a projectile of radius 2 mm centred at (cx, cy) mm, with a symmetry condition on `set`.
std::string impact_case(double cx, double cy, const std::string& set, const std::string& component) {
  return R"(units = "mm"
[case]
name = "sym"
geometry = "plane-strain"
thickness = 0.01
[mesh]
radius = 0.5e-3
[[body]]
name = "target"
material = 1
  [[body.shape]]
  type = "rectangle"
  min = [0.0, -5.0]
  max = [20.0, 0.0]
  boundary = { bottom = "base", left = "sym" }
[[body]]
name = "projectile"
material = 1
  [[body.shape]]
  type = "circle"
  center = [)" + std::to_string(cx) + ", " + std::to_string(cy) + R"(]
  radius = 2.0
[[material]]
id = 1
name = "steel"
density = 7850.0
E = 210e9
nu = 0.3
[[boundary]]
set = ")" + set + R"("
type = "symmetry"
component = ")" + component + R"("
[time]
end = 1e-7
[output]
interval = 1e-7
)";
}

fs::path write_case(const std::string& name, const std::string& text) {
  const fs::path dir = hexdem::testing::test_dir("boundary_checks", true);
  const fs::path path = dir / name;
  std::ofstream(path) << text;
  return path;
}

std::string refusal(const std::string& text) {
  const Case c = read_case(write_case("case.toml", text).string());
  const meshing::Lattice lattice = mesh_case(c);
  try {
    check_symmetry_planes(c, lattice);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(BoundaryChecks, BodiesOnTheModelSideAreAccepted) {
  EXPECT_EQ(refusal(impact_case(10.0, 3.0, "sym", "x")), "");
  // The plane y = -5 mm under the plate: both bodies above it.
  EXPECT_EQ(refusal(impact_case(10.0, 3.0, "base", "y")), "");
  // A projectile touching the plane from the model side.
  EXPECT_EQ(refusal(impact_case(2.0, 3.0, "sym", "x")), "");
}

// The generator puts a lattice point within 1e-3 d of an edge on the edge, on either side of
// it; the check must agree. The shipped warhead case at lattice angles 5 and 35 degrees has
// warhead disks 1.6e-7 m (6.5e-4 r) beyond its axis, which the check refused while it took
// 1e-6 r for the plane.
TEST(BoundaryChecks, DisksWithinTheGeneratorsToleranceOfThePlaneAreOnIt) {
  const std::string warhead = std::string(HEXDEM_SOURCE_DIR) + "/cases/warhead/case.toml";
  for (const char* angle : {"5", "35"}) {
    const Case c = read_case(warhead, {std::string("mesh.angle=") + angle});
    const meshing::Lattice lattice = mesh_case(c);
    double most = 0.0;  // the farthest disk centre beyond the axis, in units of its radius
    for (std::size_t i = 0; i < lattice.num_disks(); ++i) most = std::max(most, -lattice.x[i] / lattice.radius[i]);
    EXPECT_GT(most, 1e-6) << "angle " << angle << ": no disk beyond the axis; the test no longer tests";
    EXPECT_LT(most, meshing::kBoundaryTolerance * 2.0) << "angle " << angle;
    EXPECT_NO_THROW(check_symmetry_planes(c, lattice)) << "angle " << angle;
  }
}

TEST(BoundaryChecks, ABodyCrossingTheSymmetryPlaneIsRefused) {
  const std::string message = refusal(impact_case(0.0, 3.0, "sym", "x"));
  EXPECT_NE(message.find("boundary[0]: body 'projectile' crosses the symmetry plane x = 0 m of set 'sym'"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("(its disk at (-0.0015, "), std::string::npos) << message;
  EXPECT_NE(message.find("0.0015 m on the mirror side"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(BoundaryChecks, ABodyBeyondTheSymmetryPlaneIsRefused) {
  const std::string message = refusal(impact_case(-10.0, 3.0, "sym", "x"));
  EXPECT_NE(message.find("body 'projectile' lies beyond the symmetry plane x = 0 m"), std::string::npos)
      << message;
  // The plane y = -5 mm with the projectile below it.
  const std::string below = refusal(impact_case(10.0, -9.0, "base", "y"));
  EXPECT_NE(below.find("body 'projectile' lies beyond the symmetry plane y = -0.005 m of set 'base'"),
            std::string::npos)
      << below;
}

TEST(BoundaryChecks, TheSolverRefusesACrossingBody) {
  const Case c = read_case(write_case("case.toml", impact_case(0.0, 3.0, "sym", "x")).string());
  const meshing::Lattice lattice = mesh_case(c);
  EXPECT_THROW(Solver(c, lattice), InputError);
}

TEST(BoundaryChecks, HexdemRunExitsWithCodeTwoAndOneLine) {
  const fs::path path = write_case("crossing.toml", impact_case(0.0, 3.0, "sym", "x"));
  const fs::path out = path.parent_path() / "out";
  const auto r = hexdem::testing::run_hexdem(path.parent_path(), "run " + path.string() + " -q -o " + out.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(hexdem::testing::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("crossing.toml"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("crosses the symmetry plane x = 0 m"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_FALSE(fs::exists(out / "sym.pvd"));
}

}  // namespace
