// Tests of the DXF outline reader (read_outline_dxf) on drawings written by an independent
// writer (tests/data/make_dxf_fixtures.py, ezdxf). The geometry of each drawing is documented
// in that script.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/outline.hpp"
#include "hexdem/meshing/outline_dxf.hpp"
#include "hexdem/meshing/outline_toml.hpp"

#if __has_include("hexdem/meshing/lattice_generator.hpp")
#include "hexdem/meshing/lattice_generator.hpp"
#define HEXDEM_HAVE_LATTICE_GENERATOR 1
#endif

namespace fs = std::filesystem;
using hexdem::InputError;
using hexdem::meshing::BodyOutline;
using hexdem::meshing::Loop;
using hexdem::meshing::Outline;
using hexdem::meshing::read_outline_dxf;
using hexdem::meshing::ReadOptions;
using hexdem::meshing::Vec2;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRadius = 0.5e-3;  // disk radius for all reads [m]

fs::path fixture_dir() {
  return fs::path(HEXDEM_TEST_WORK_DIR) / "dxf";
}

std::string fixture(const std::string& name) {
  return (fixture_dir() / name).string();
}

/// Runs make_dxf_fixtures.py into <work>/dxf before the tests of a process, unless the drawings
/// are newer than the script (its stamp file). The script writes each file atomically, so test
/// processes running side by side never read a partial drawing.
class DxfFixtures : public ::testing::Environment {
 public:
  void SetUp() override {
    const fs::path script = fs::path(HEXDEM_TEST_DATA_DIR) / "make_dxf_fixtures.py";
    const fs::path stamp = fixture_dir() / "fixtures.stamp";
    std::error_code ec;
    if (fs::exists(stamp, ec) && fs::last_write_time(stamp, ec) >= fs::last_write_time(script, ec))
      return;
    const std::string command = std::string("\"") + HEXDEM_SYSTEM_PYTHON + "\" \"" +
                                script.string() + "\" \"" + fixture_dir().string() + "\"";
    ASSERT_EQ(std::system(command.c_str()), 0) << "failed: " << command;
  }
};

[[maybe_unused]] auto* const dxf_fixtures = ::testing::AddGlobalTestEnvironment(new DxfFixtures);

ReadOptions options() {
  ReadOptions o;
  o.radius = kRadius;
  return o;
}

/// Max sagitta of the chords [m].
double chord_error(const ReadOptions& o = options()) {
  return o.chord_fraction * *o.radius;
}

double area(const Loop& loop) {
  return std::abs(hexdem::meshing::signed_area(loop));
}

std::string edge_name(const Outline& outline, const Loop& loop, std::size_t k) {
  const std::int32_t s = loop.edge_set.at(k);
  return s < 0 ? std::string() : outline.boundary_names.at(static_cast<std::size_t>(s));
}

/// Checks a loop's invariants: per-edge arrays as long as the points.
void expect_well_formed(const Loop& loop) {
  EXPECT_GE(loop.points.size(), 3U) << loop.where;
  EXPECT_EQ(loop.edge_set.size(), loop.points.size()) << loop.where;
  EXPECT_EQ(loop.edge_straight.size(), loop.points.size()) << loop.where;
}

/// Checks the chords of an arc about `c` with radius `r`: every chord edge that starts on the
/// circle ends on it, with a sagitta of at most the chord error. Returns the chords checked.
std::size_t expect_arc_chords(const Loop& loop, Vec2 c, double r, double error) {
  std::size_t checked = 0;
  const std::size_t n = loop.points.size();
  for (std::size_t k = 0; k < n; ++k) {
    if (loop.edge_straight[k] != 0) continue;
    const Vec2 a = loop.points[k], b = loop.points[(k + 1) % n];
    EXPECT_NEAR(std::hypot(a.x - c.x, a.y - c.y), r, 1e-12) << loop.where << " edge " << k;
    EXPECT_NEAR(std::hypot(b.x - c.x, b.y - c.y), r, 1e-12) << loop.where << " edge " << k;
    const double sagitta = r - std::hypot(0.5 * (a.x + b.x) - c.x, 0.5 * (a.y + b.y) - c.y);
    EXPECT_LE(sagitta, error * (1.0 + 1e-9) + 1e-15) << loop.where << " edge " << k;
    ++checked;
  }
  return checked;
}

/// The fewest chords of sagitta <= error that can flatten an arc of `sweep` radians.
std::size_t min_chords(double sweep, double r, double error) {
  return static_cast<std::size_t>(std::ceil(sweep / (2.0 * std::acos(1.0 - error / r)) - 1e-9));
}

/// A polygon inscribed in arcs of total length `arc_length` loses at most arc_length * error
/// of area (each chord cuts off a circular segment thinner than the chord error).
void expect_area_within_chord_bound(double actual, double exact, double arc_length, double error) {
  EXPECT_LE(actual, exact * (1.0 + 1e-12));
  EXPECT_GE(actual, exact - arc_length * error - 1e-12 * exact);
}

bool has_point(const Loop& loop, Vec2 p, double tol = 1e-12) {
  return std::any_of(loop.points.begin(), loop.points.end(), [&](Vec2 q) {
    return std::abs(q.x - p.x) <= tol && std::abs(q.y - p.y) <= tol;
  });
}

std::string read_error(const std::string& path, const ReadOptions& o = options()) {
  try {
    read_outline_dxf(path, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

/// Writes a small hand-made DXF into the work folder and returns its path.
std::string write_dxf(const std::string& name, const std::string& text) {
  const fs::path path = fs::path(HEXDEM_TEST_WORK_DIR) / name;
  std::ofstream(path) << text;
  return path.string();
}

/// A unit square (0,0)..(1,1) as a closed LWPOLYLINE, in DXF group-code form.
const char* const kUnitSquareLwpolyline =
    "0\nLWPOLYLINE\n8\n0\n90\n4\n70\n1\n"
    "10\n0\n20\n0\n10\n1\n20\n0\n10\n1\n20\n1\n10\n0\n20\n1\n";

}  // namespace

TEST(DxfUnits, InsunitsTable) {
  using hexdem::meshing::dxf_insunits_to_metres;
  EXPECT_EQ(dxf_insunits_to_metres(0), 1.0);
  EXPECT_EQ(dxf_insunits_to_metres(1), 0.0254);
  EXPECT_EQ(dxf_insunits_to_metres(2), 0.3048);
  EXPECT_EQ(dxf_insunits_to_metres(3), 1609.344);
  EXPECT_EQ(dxf_insunits_to_metres(4), 1e-3);
  EXPECT_EQ(dxf_insunits_to_metres(5), 1e-2);
  EXPECT_EQ(dxf_insunits_to_metres(6), 1.0);
  EXPECT_EQ(dxf_insunits_to_metres(7), 1e3);
  EXPECT_DOUBLE_EQ(dxf_insunits_to_metres(8), 0.0254e-6);
  EXPECT_DOUBLE_EQ(dxf_insunits_to_metres(9), 0.0254e-3);
  EXPECT_EQ(dxf_insunits_to_metres(10), 0.9144);
  EXPECT_EQ(dxf_insunits_to_metres(11), 1e-10);
  EXPECT_EQ(dxf_insunits_to_metres(12), 1e-9);
  EXPECT_EQ(dxf_insunits_to_metres(13), 1e-6);
  EXPECT_EQ(dxf_insunits_to_metres(14), 0.1);
  EXPECT_EQ(dxf_insunits_to_metres(15), 10.0);
  EXPECT_EQ(dxf_insunits_to_metres(16), 100.0);
  EXPECT_EQ(dxf_insunits_to_metres(17), 1e9);
  EXPECT_DOUBLE_EQ(dxf_insunits_to_metres(21), 1200.0 / 3937.0);
  EXPECT_DOUBLE_EQ(dxf_insunits_to_metres(24), 6336000.0 / 3937.0);
  EXPECT_EQ(dxf_insunits_to_metres(25), 1.0);
  EXPECT_EQ(dxf_insunits_to_metres(-1), 1.0);
}

TEST(OutlineDxf, RectanglePolylineInMillimetres) {
  const std::string path = fixture("a_rect_lwpolyline.dxf");
  std::vector<std::string> warnings;
  ReadOptions o = options();
  o.angle_deg = 30.0;
  o.origin = Vec2{0.001, 0.002};
  const Outline outline = read_outline_dxf(path, o, &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(outline.source, path);
  ASSERT_EQ(outline.bodies.size(), 1U);
  const BodyOutline& body = outline.bodies[0];
  EXPECT_EQ(body.name, "body1");
  EXPECT_EQ(body.material, 1);
  EXPECT_EQ(body.where, path + ": body1");
  EXPECT_EQ(body.radius, kRadius);
  EXPECT_EQ(body.angle_deg, 30.0);
  ASSERT_TRUE(body.origin.has_value());
  EXPECT_EQ(body.origin->x, 0.001);
  EXPECT_EQ(body.origin->y, 0.002);
  ASSERT_EQ(body.outers.size(), 1U);
  EXPECT_TRUE(body.holes.empty());
  const Loop& loop = body.outers[0];
  expect_well_formed(loop);
  ASSERT_EQ(loop.points.size(), 4U);
  EXPECT_EQ(loop.where, path + ": layer 'rim' loop 1");
  EXPECT_NEAR(hexdem::meshing::signed_area(loop), 40e-3 * 20e-3, 1e-15);  // counter-clockwise
  for (const Vec2 p :
       {Vec2{0.010, 0.005}, Vec2{0.050, 0.005}, Vec2{0.050, 0.025}, Vec2{0.010, 0.025}})
    EXPECT_TRUE(has_point(loop, p)) << p.x << " " << p.y;
  ASSERT_EQ(outline.boundary_names, std::vector<std::string>{"rim"});
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(loop.edge_set[k], 0);
    EXPECT_EQ(loop.edge_straight[k], 1);
  }
}

TEST(OutlineDxf, DefaultLatticeAngleAndOrigin) {
  const Outline outline = read_outline_dxf(fixture("a_rect_lwpolyline.dxf"), options());
  ASSERT_EQ(outline.bodies.size(), 1U);
  EXPECT_EQ(outline.bodies[0].angle_deg, 0.0);
  ASSERT_TRUE(outline.bodies[0].origin.has_value());
  EXPECT_EQ(outline.bodies[0].origin->x, 0.0);
  EXPECT_EQ(outline.bodies[0].origin->y, 0.0);
}

TEST(OutlineDxf, ScaleOverridesInsunits) {
  ReadOptions o = options();
  o.scale = 0.01;  // take the drawing as centimetres
  const Outline outline = read_outline_dxf(fixture("a_rect_lwpolyline.dxf"), o);
  ASSERT_EQ(outline.bodies.size(), 1U);
  const Loop& loop = outline.bodies[0].outers.at(0);
  EXPECT_NEAR(area(loop), 0.4 * 0.2, 1e-14);
  EXPECT_TRUE(has_point(loop, Vec2{0.5, 0.25}));
}

TEST(OutlineDxf, LooseLinesEqualPolyline) {
  const Outline lines = read_outline_dxf(fixture("b_rect_lines.dxf"), options());
  const Outline poly = read_outline_dxf(fixture("a_rect_lwpolyline.dxf"), options());
  ASSERT_EQ(lines.bodies.size(), 1U);
  ASSERT_EQ(lines.bodies[0].outers.size(), 1U);
  const Loop& a = lines.bodies[0].outers[0];
  const Loop& b = poly.bodies[0].outers.at(0);
  expect_well_formed(a);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (const Vec2 p : b.points) EXPECT_TRUE(has_point(a, p, 0.0)) << p.x << " " << p.y;
  EXPECT_EQ(hexdem::meshing::signed_area(a), hexdem::meshing::signed_area(b));

  // Each side carries the name of its layer.
  std::set<std::string> names(lines.boundary_names.begin(), lines.boundary_names.end());
  EXPECT_EQ(names, (std::set<std::string>{"bottom", "right", "top", "left"}));
  const std::size_t n = a.points.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 p = a.points[k], q = a.points[(k + 1) % n];
    const Vec2 mid{0.5 * (p.x + q.x), 0.5 * (p.y + q.y)};
    std::string side;
    if (std::abs(mid.y - 0.005) < 1e-12) side = "bottom";
    if (std::abs(mid.x - 0.050) < 1e-12) side = "right";
    if (std::abs(mid.y - 0.025) < 1e-12) side = "top";
    if (std::abs(mid.x - 0.010) < 1e-12) side = "left";
    EXPECT_EQ(edge_name(lines, a, k), side) << "edge " << k;
    EXPECT_EQ(a.edge_straight[k], 1);
  }
  EXPECT_EQ(a.where.rfind(fixture("b_rect_lines.dxf") + ": layers ", 0), 0U) << a.where;
}

TEST(OutlineDxf, BulgeSemicircle) {
  const Outline outline = read_outline_dxf(fixture("c_bulge.dxf"), options());
  ASSERT_EQ(outline.bodies.size(), 1U);
  const Loop& loop = outline.bodies[0].outers.at(0);
  expect_well_formed(loop);
  const double r = 0.010, e = chord_error();
  const std::size_t chords = expect_arc_chords(loop, Vec2{0.040, 0.010}, r, e);
  EXPECT_GE(chords, min_chords(kPi, r, e));
  EXPECT_LE(chords, min_chords(kPi, r, e) + 2);
  EXPECT_EQ(loop.points.size() - chords, 3U);  // the three straight sides
  // End points of the arc, and its far point within the chord error.
  EXPECT_TRUE(has_point(loop, Vec2{0.040, 0.0}));
  EXPECT_TRUE(has_point(loop, Vec2{0.040, 0.020}));
  double xmax = 0.0;
  for (const Vec2 p : loop.points) xmax = std::max(xmax, p.x);
  EXPECT_LE(xmax, 0.050 + 1e-15);
  EXPECT_GE(xmax, 0.050 - e);
  expect_area_within_chord_bound(area(loop), 800e-6 + 0.5 * kPi * r * r, kPi * r, e);
  EXPECT_EQ(outline.boundary_names, std::vector<std::string>{"outline"});
}

TEST(OutlineDxf, DiskWithSquareHole) {
  const std::string path = fixture("d_disk_hole.dxf");
  const Outline outline = read_outline_dxf(path, options());
  ASSERT_EQ(outline.bodies.size(), 1U);
  const BodyOutline& body = outline.bodies[0];
  ASSERT_EQ(body.outers.size(), 1U);
  ASSERT_EQ(body.holes.size(), 1U);
  const Loop& rim = body.outers[0];
  const Loop& hole = body.holes[0];
  expect_well_formed(rim);
  expect_well_formed(hole);
  const double r = 0.020, e = chord_error();
  EXPECT_EQ(expect_arc_chords(rim, Vec2{0.0, 0.0}, r, e), rim.points.size());  // all chords
  EXPECT_GE(rim.points.size(), min_chords(2 * kPi, r, e));
  EXPECT_LE(rim.points.size(), min_chords(2 * kPi, r, e) + 2);
  expect_area_within_chord_bound(area(rim), kPi * r * r, 2 * kPi * r, e);
  EXPECT_GT(hexdem::meshing::signed_area(rim), 0.0);
  EXPECT_LT(hexdem::meshing::signed_area(hole), 0.0);
  ASSERT_EQ(hole.points.size(), 4U);
  EXPECT_NEAR(area(hole), 1e-4, 1e-16);
  for (std::size_t k = 0; k < rim.points.size(); ++k) EXPECT_EQ(edge_name(outline, rim, k), "rim");
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(edge_name(outline, hole, k), "hole");
    EXPECT_EQ(hole.edge_straight[k], 1);
  }
  EXPECT_EQ(rim.where, path + ": layer 'rim' loop 1");
  EXPECT_EQ(hole.where, path + ": layer 'hole' loop 2");
}

TEST(OutlineDxf, TwoBodiesByDecreasingArea) {
  const std::string path = fixture("e_two_bodies.dxf");
  const Outline outline = read_outline_dxf(path, options());
  ASSERT_EQ(outline.bodies.size(), 2U);
  EXPECT_TRUE(outline.boundary_names.empty());
  const double areas[] = {300e-6, 100e-6};
  for (std::size_t i = 0; i < 2; ++i) {
    const BodyOutline& body = outline.bodies[i];
    EXPECT_EQ(body.name, "body" + std::to_string(i + 1));
    EXPECT_EQ(body.material, static_cast<int>(i + 1));
    EXPECT_EQ(body.where, path + ": " + body.name);
    ASSERT_EQ(body.outers.size(), 1U);
    EXPECT_TRUE(body.holes.empty());
    EXPECT_NEAR(area(body.outers[0]), areas[i], 1e-16);
    for (const std::int32_t s : body.outers[0].edge_set) EXPECT_EQ(s, -1);  // layer "0"
  }
  // The larger body is the second loop of the file.
  EXPECT_EQ(outline.bodies[0].outers[0].where, path + ": layer '0' loop 2");
}

TEST(OutlineDxf, IslandInsideHoleIsSeparateBody) {
  const Outline outline = read_outline_dxf(fixture("j_island.dxf"), options());
  ASSERT_EQ(outline.bodies.size(), 2U);
  const BodyOutline& frame = outline.bodies[0];
  const BodyOutline& island = outline.bodies[1];
  ASSERT_EQ(frame.outers.size(), 1U);
  ASSERT_EQ(frame.holes.size(), 1U);
  EXPECT_NEAR(area(frame.outers[0]), 0.1 * 0.1, 1e-15);
  EXPECT_NEAR(area(frame.holes[0]), 0.06 * 0.06, 1e-15);
  ASSERT_EQ(island.outers.size(), 1U);
  EXPECT_TRUE(island.holes.empty());
  EXPECT_NEAR(area(island.outers[0]), 0.02 * 0.02, 1e-15);
  EXPECT_EQ(island.material, 2);
}

TEST(OutlineDxf, SkippedTypesWarnOncePerType) {
  const std::string path = fixture("g_skipped_types.dxf");
  std::vector<std::string> warnings;
  const Outline outline = read_outline_dxf(path, options(), &warnings);
  // The block definition's entities and the paper-space LINE are not read.
  ASSERT_EQ(outline.bodies.size(), 1U);
  EXPECT_NEAR(area(outline.bodies[0].outers.at(0)), 0.020 * 0.010, 1e-15);
  EXPECT_EQ(outline.boundary_names, std::vector<std::string>{"body"});

  const std::vector<std::string> expected = {
      path + ": skipped 1 INSERT entity (unsupported: block references are not expanded)",
      path + ": skipped 3 POINT entities (unsupported)",
      path + ": skipped 1 SPLINE entity (unsupported)",
      path + ": skipped 2 TEXT entities (unsupported)",
      path + ": skipped 1 entity in paper space",
  };
  EXPECT_EQ(warnings, expected);
  for (const std::string& w : warnings) EXPECT_EQ(w.find('\n'), std::string::npos);
}

TEST(OutlineDxf, ArcAndLinesChainIntoOneLoop) {
  const Outline outline = read_outline_dxf(fixture("h_arc_lines.dxf"), options());  // unitless: m
  ASSERT_EQ(outline.bodies.size(), 1U);
  const Loop& loop = outline.bodies[0].outers.at(0);
  expect_well_formed(loop);
  const double r = 8.0, e = chord_error();
  const std::size_t chords = expect_arc_chords(loop, Vec2{22.0, 12.0}, r, e);
  EXPECT_GE(chords, min_chords(0.5 * kPi, r, e));
  EXPECT_LE(chords, min_chords(0.5 * kPi, r, e) + 2);
  EXPECT_EQ(loop.points.size() - chords, 4U);  // four straight sides
  EXPECT_TRUE(has_point(loop, Vec2{30.0, 12.0}));
  EXPECT_TRUE(has_point(loop, Vec2{22.0, 20.0}));
  expect_area_within_chord_bound(area(loop), 536.0 + 16.0 * kPi, 0.5 * kPi * r, e);
  for (std::size_t k = 0; k < loop.points.size(); ++k)
    EXPECT_EQ(edge_name(outline, loop, k), loop.edge_straight[k] ? "side" : "fillet") << k;
}

TEST(OutlineDxf, MirroredArcMatchesPlainArc) {
  const Outline plain = read_outline_dxf(fixture("h_arc_lines.dxf"), options());
  const Outline mirrored = read_outline_dxf(fixture("l_arc_mirrored.dxf"), options());
  ASSERT_EQ(mirrored.bodies.size(), 1U);
  const Loop& a = plain.bodies[0].outers.at(0);
  const Loop& b = mirrored.bodies[0].outers.at(0);
  ASSERT_EQ(a.points.size(), b.points.size());
  EXPECT_NEAR(area(a), area(b), 1e-9);
  expect_arc_chords(b, Vec2{22.0, 12.0}, 8.0, chord_error());
  for (const Vec2 p : b.points) {
    EXPECT_GE(p.x, -1e-12);
    EXPECT_LE(p.x, 30.0 + 1e-12);
  }
}

TEST(OutlineDxf, ClassicPolylineWithNegativeBulge) {
  const std::string path = fixture("i_polyline_r12.dxf");
  std::vector<std::string> warnings;
  const Outline outline = read_outline_dxf(path, options(), &warnings);  // no $INSUNITS: m
  EXPECT_TRUE(warnings.empty());
  ASSERT_EQ(outline.bodies.size(), 1U);
  const Loop& loop = outline.bodies[0].outers.at(0);
  expect_well_formed(loop);
  EXPECT_GT(hexdem::meshing::signed_area(loop), 0.0);  // drawn clockwise, oriented by the reader
  const double r = 0.005, e = chord_error();
  const std::size_t chords = expect_arc_chords(loop, Vec2{0.02, 0.005}, r, e);
  EXPECT_GE(chords, min_chords(kPi, r, e));
  EXPECT_LE(chords, min_chords(kPi, r, e) + 2);
  for (const Vec2 p : loop.points) EXPECT_LE(p.x, 0.025 + 1e-15);
  double xmax = 0.0;
  for (const Vec2 p : loop.points) xmax = std::max(xmax, p.x);
  EXPECT_GE(xmax, 0.025 - e);  // the arc bulges outwards (bulge -1 on a clockwise loop)
  expect_area_within_chord_bound(area(loop), 2e-4 + 0.5 * kPi * r * r, kPi * r, e);
  EXPECT_EQ(outline.boundary_names, std::vector<std::string>{"shell"});
  EXPECT_EQ(loop.where, path + ": layer 'shell' loop 1");
}

TEST(OutlineDxf, UnknownInsunitsWarnsAndUsesMetres) {
  const std::string path =
      write_dxf("dxf_unknown_units.dxf",
                std::string("0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\n99\n0\nENDSEC\n") +
                    "0\nSECTION\n2\nENTITIES\n" + kUnitSquareLwpolyline + "0\nENDSEC\n0\nEOF\n");
  std::vector<std::string> warnings;
  const Outline outline = read_outline_dxf(path, options(), &warnings);
  ASSERT_EQ(outline.bodies.size(), 1U);
  EXPECT_NEAR(area(outline.bodies[0].outers.at(0)), 1.0, 1e-15);
  ASSERT_EQ(warnings.size(), 1U);
  EXPECT_EQ(warnings[0], path + ": unknown $INSUNITS code 99; taking 1 drawing unit = 1 m");
}

TEST(OutlineDxf, HugeInsunitsCodeIsReportedAsWritten) {
  // Was: "unknown $INSUNITS code 1215752191" (dxflib wraps the value into an int).
  const std::string path =
      write_dxf("dxf_huge_units.dxf",
                std::string("0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\n99999999999\n0\nENDSEC\n") +
                    "0\nSECTION\n2\nENTITIES\n" + kUnitSquareLwpolyline + "0\nENDSEC\n0\nEOF\n");
  std::vector<std::string> warnings;
  const Outline outline = read_outline_dxf(path, options(), &warnings);
  EXPECT_NEAR(area(outline.bodies.at(0).outers.at(0)), 1.0, 1e-15);
  EXPECT_EQ(warnings,
            std::vector<std::string>{
                path + ": unknown $INSUNITS code 99999999999; taking 1 drawing unit = 1 m"});
}

TEST(OutlineDxf, TinyExtrusionAlongZIsThePlainPlane) {
  // (0, 0, 1e-300) is the direction +z; its length underflowed to 0 and the circle was dropped.
  const std::string path =
      write_dxf("dxf_tiny_extrusion.dxf",
                "0\nSECTION\n2\nENTITIES\n0\nCIRCLE\n8\nc\n10\n0\n20\n0\n40\n1\n210\n0\n220\n0\n"
                "230\n1e-300\n0\nENDSEC\n0\nEOF\n");
  const Outline outline = read_outline_dxf(path, options());
  ASSERT_EQ(outline.bodies.size(), 1U);
}

TEST(OutlineDxfErrors, OpenChain) {
  const std::string path = fixture("f_open_chain.dxf");
  const std::string message = read_error(path);
  EXPECT_EQ(message.rfind(path + ": open outline: chain on layer 'edge' ends at (0, 0) with no "
                                 "continuation",
                          0),
            0U)
      << message;
  // The nearest loose end, in drawing units (mm) as the CAD program shows them.
  EXPECT_NE(message.find("(nearest loose end (0, 5), 5 away)"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(OutlineDxfErrors, Branching) {
  const std::string path = fixture("k_branch.dxf");
  const std::string message = read_error(path);
  EXPECT_EQ(
      message.rfind(path + ": branching outline: 3 entity ends meet at (0, 0) on layer 'web'", 0),
      0U)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(OutlineDxfErrors, MissingFile) {
  const std::string path = fixture("no_such_drawing.dxf");
  EXPECT_EQ(read_error(path), path + ": cannot open file");
}

TEST(OutlineDxfErrors, EmptyFile) {
  const std::string path = fixture("empty.dxf");
  EXPECT_EQ(read_error(path), path + ": not a DXF file or no entities");
}

TEST(OutlineDxfErrors, TextFileIsNotDxf) {
  const std::string path = fixture("not_dxf.dxf");
  const std::string message = read_error(path);
  EXPECT_EQ(message.rfind(path + ": not a DXF file or no entities", 0), 0U) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(OutlineDxfErrors, NoEntitiesSection) {
  const std::string path = write_dxf(
      "dxf_header_only.dxf", "0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\n4\n0\nENDSEC\n0\nEOF\n");
  EXPECT_EQ(read_error(path), path + ": not a DXF file or no entities");
}

TEST(OutlineDxfErrors, NoClosedOutline) {
  const std::string path = write_dxf("dxf_text_only.dxf",
                                     "0\nSECTION\n2\nENTITIES\n0\nTEXT\n8\nnotes\n10\n0\n20\n0\n40"
                                     "\n1\n1\nhello\n0\nENDSEC\n0\nEOF\n");
  std::vector<std::string> warnings;
  try {
    read_outline_dxf(path, options(), &warnings);
    FAIL() << "no error";
  } catch (const InputError& e) {
    // The skipped entities are part of the error: warnings are not printed after an error.
    EXPECT_EQ(std::string(e.what()),
              path + ": no closed outline; skipped 1 TEXT entity (unsupported)");
  }
  EXPECT_EQ(warnings, std::vector<std::string>{path + ": skipped 1 TEXT entity (unsupported)"});
}

namespace {

/// A DXF of the given ENTITIES section text, with or without the closing ENDSEC and EOF.
std::string entities_dxf(const std::string& entities, bool complete = true) {
  return "0\nSECTION\n2\nENTITIES\n" + entities + (complete ? "0\nENDSEC\n0\nEOF\n" : "");
}

/// A closed LWPOLYLINE on `layer` with the vertex count `count` (group code 90) and the
/// vertices of the square (x0, 0)..(x0 + 10, 10), each with bulge `bulge` if not empty.
std::string square_lwpolyline(const std::string& layer, const std::string& count, double x0 = 0.0,
                              const std::string& bulge = "") {
  std::string t = "0\nLWPOLYLINE\n8\n" + layer + "\n90\n" + count + "\n70\n1\n";
  const double xs[] = {x0, x0 + 10, x0 + 10, x0};
  const double ys[] = {0, 0, 10, 10};
  for (int k = 0; k < 4; ++k) {
    t += "10\n" + std::to_string(xs[k]) + "\n20\n" + std::to_string(ys[k]) + "\n";
    if (!bulge.empty()) t += "42\n" + bulge + "\n";
  }
  return t;
}

/// One line of message, starting with `prefix`.
void expect_error_line(const std::string& message, const std::string& prefix) {
  EXPECT_EQ(message.rfind(prefix, 0), 0U) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

}  // namespace

TEST(OutlineDxfErrors, TruncatedFileIsRefused) {
  // Was: a file cut inside its second LWPOLYLINE meshed the first body only (dxflib reports an
  // entity when the next one starts), and one cut after its last entity said "no closed outline".
  const std::string two = square_lwpolyline("a", "4") + square_lwpolyline("b", "4", 20.0);
  // Cut after the x of the last vertex.
  std::string cut_inside = entities_dxf(two, false);
  for (int k = 0; k < 2; ++k) cut_inside.erase(cut_inside.rfind('\n', cut_inside.size() - 2) + 1);
  std::string path = write_dxf("dxf_cut_inside.dxf", cut_inside);
  const auto lines = [](const std::string& text) {
    return std::to_string(std::count(text.begin(), text.end(), '\n'));
  };
  EXPECT_EQ(read_error(path),
            path + ": truncated: no EOF marker (the file ends at line " + lines(cut_inside) + ")");
  // Cut after the last entity, after ENDSEC, and between a group code and its value.
  for (const std::string& text :
       {entities_dxf(two, false), entities_dxf(two, false) + "0\nENDSEC\n",
        entities_dxf(two, false) + "0\nENDSEC\n0\n"}) {
    path = write_dxf("dxf_cut.dxf", text);
    EXPECT_EQ(read_error(path),
              path + ": truncated: no EOF marker (the file ends at line " + lines(text) + ")");
  }
  // The complete file reads (also with a last line that has no newline).
  path = write_dxf("dxf_complete.dxf", entities_dxf(two) + "\n");
  EXPECT_EQ(read_outline_dxf(path, options()).bodies.size(), 2U);
  path = write_dxf("dxf_complete_no_newline.dxf", entities_dxf(two) + "0\nEOF");
  EXPECT_EQ(read_error(path), "(no error)");
}

TEST(OutlineDxfErrors, LwpolylineVertexCountMustMatchItsVertices) {
  // Was: a count of 3 with 4 vertices meshed a triangle, 0 dropped the square without a word,
  // 1 called it zero-length, 2e9 ran out of memory (exit 1, no file name) and 1e8 took 6 s and
  // GBs: dxflib allocates and reads as many vertices as the count says.
  const std::string ok = square_lwpolyline("ok", "4", 20.0);
  // Line of the count's value: SECTION header (4 lines), "0 LWPOLYLINE 8 rim 90".
  const std::string at = ":10: LWPOLYLINE on layer 'rim': vertex count (group code 90) is ";
  for (const auto& [count, shown] : std::vector<std::pair<std::string, std::string>>{
           {"3", "3"},
           {"0", "0"},
           {"1", "1"},
           {"5", "5"},
           {"-4", "-4"},
           {"+2000000000", "+2000000000"},
           {"100000000", "100000000"},
           {"99999999999999999999", "99999999999999999999"}}) {
    const std::string path =
        write_dxf("dxf_count.dxf", entities_dxf(square_lwpolyline("rim", count) + ok));
    const auto start = std::chrono::steady_clock::now();
    const std::string message = read_error(path);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(message, path + at + shown + ", but 4 vertices are listed");
    EXPECT_LT(seconds, 2.0) << count;
  }
  // A count that is not an integer, a missing count, and a vertex or bulge out of order.
  std::string path = write_dxf("dxf_count.dxf", entities_dxf(square_lwpolyline("rim", "4.0")));
  EXPECT_EQ(read_error(path),
            path + ":10: group code 90 of LWPOLYLINE: not an integer (got '4.0')");
  path = write_dxf("dxf_count.dxf",
                   entities_dxf("0\nLWPOLYLINE\n8\nrim\n70\n1\n10\n0\n20\n0\n10\n1\n20\n0\n"));
  expect_error_line(read_error(path), path +
                                          ":12: LWPOLYLINE on layer 'rim': vertex (group code "
                                          "10) before the vertex count (group code 90)");
  path = write_dxf("dxf_count.dxf", entities_dxf("0\nLWPOLYLINE\n8\nrim\n70\n1\n0\nLINE\n8\nx\n"));
  expect_error_line(read_error(path),
                    path + ":6: LWPOLYLINE on layer 'rim': no vertex count (group code 90)");
  path = write_dxf("dxf_count.dxf",
                   entities_dxf("0\nLWPOLYLINE\n8\nrim\n90\n1\n42\n1\n10\n0\n20\n0\n"));
  expect_error_line(read_error(path), path +
                                          ":12: LWPOLYLINE on layer 'rim': bulge (group code "
                                          "42) before the first vertex");
  // A closed polyline without vertices is degenerate (was: skipped silently).
  path = write_dxf("dxf_count.dxf", entities_dxf("0\nLWPOLYLINE\n8\nrim\n90\n0\n70\n1\n" + ok));
  EXPECT_EQ(read_error(path), path +
                                  ": degenerate outline: closed LWPOLYLINE on layer 'rim' has "
                                  "fewer than 3 distinct vertices (it has none)");
  // Also when its count says otherwise (was: skipped silently).
  path = write_dxf("dxf_count.dxf", entities_dxf("0\nLWPOLYLINE\n8\nrim\n90\n4\n70\n1\n" + ok));
  EXPECT_EQ(read_error(path), path +
                                  ":10: degenerate outline: closed LWPOLYLINE on layer 'rim' has "
                                  "fewer than 3 distinct vertices (it has none; its vertex count "
                                  "(group code 90) is 4)");
  // An open one without vertices has no length: skipped with the zero-length warning.
  path = write_dxf("dxf_count.dxf", entities_dxf("0\nLWPOLYLINE\n8\nrim\n90\n0\n70\n0\n" + ok));
  std::vector<std::string> warnings;
  EXPECT_EQ(read_outline_dxf(path, options(), &warnings).bodies.size(), 1U);
  EXPECT_EQ(warnings, std::vector<std::string>{path + ": skipped 1 zero-length entity"});
}

TEST(OutlineDxfErrors, LinesTooLongForTheParserAreRefused) {
  // Was: a layer name of 5000 characters split the line in dxflib, and the entity was lost.
  const std::string ok = square_lwpolyline("ok", "4", 20.0);
  std::string path = write_dxf("dxf_long_layer.dxf",
                               entities_dxf(square_lwpolyline(std::string(5000, 'L'), "4") + ok));
  EXPECT_EQ(read_error(path), path +
                                  ":8: group code 8 of LWPOLYLINE: line of 5000 characters "
                                  "(at most 1022 can be read)");
  // 1000 characters are read.
  path = write_dxf("dxf_long_layer.dxf",
                   entities_dxf(square_lwpolyline(std::string(1000, 'L'), "4") + ok));
  EXPECT_EQ(read_outline_dxf(path, options()).boundary_names.at(0), std::string(1000, 'L'));
}

TEST(OutlineDxfErrors, NulCharacterIsRefused) {
  // Was: the layer "r\0m" became the boundary set "r".
  const std::string path =
      write_dxf("dxf_nul.dxf", entities_dxf(square_lwpolyline(std::string("r\0m", 3), "4")));
  EXPECT_EQ(read_error(path),
            path + ":8: group code 8 of LWPOLYLINE: NUL character in the value ('r\\x00m')");
}

TEST(OutlineDxfErrors, InsunitsMustBeAnInteger) {
  // Was: "mm" was read as 0 (unitless) and the drawing taken as metres.
  const std::string path =
      write_dxf("dxf_text_units.dxf", "0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\nmm\n0\nENDSEC\n" +
                                          entities_dxf(kUnitSquareLwpolyline));
  EXPECT_EQ(read_error(path), path + ":8: header variable $INSUNITS: not an integer (got 'mm')");
  // A variable without a value is absent (metres), and leaves the next section alone.
  const std::string bare =
      write_dxf("dxf_bare_units.dxf", "0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n0\nENDSEC\n" +
                                          entities_dxf(kUnitSquareLwpolyline));
  std::vector<std::string> warnings;
  EXPECT_NEAR(area(read_outline_dxf(bare, options(), &warnings).bodies.at(0).outers.at(0)), 1.0,
              1e-15);
  EXPECT_TRUE(warnings.empty());
}

TEST(OutlineDxfErrors, HugeBulgeIsRefused) {
  // Was: "no closed outline" for two closed polylines (bulges 1e300 and 1e12).
  const std::string ok = square_lwpolyline("ok", "4", 20.0);
  for (const std::string bulge : {"1e300", "1e12", "-1000001"}) {
    const std::string path =
        write_dxf("dxf_bulge.dxf", entities_dxf(square_lwpolyline("rim", "4", 0.0, bulge) + ok));
    EXPECT_EQ(read_error(path), path +
                                    ":18: group code 42 of LWPOLYLINE: bulge out of range (got '" +
                                    bulge + "'; |bulge| must be at most 1e+06)");
  }
  // Also on the VERTEX of a classic POLYLINE.
  const std::string path = write_dxf(
      "dxf_bulge.dxf", entities_dxf("0\nPOLYLINE\n8\np\n66\n1\n70\n1\n0\nVERTEX\n8\np\n10\n0\n20\n0"
                                    "\n42\n1e9\n0\nVERTEX\n8\np\n10\n1\n20\n0\n0\nSEQEND\n"));
  EXPECT_EQ(read_error(path), path +
                                  ":22: group code 42 of VERTEX: bulge out of range (got "
                                  "'1e9'; |bulge| must be at most 1e+06)");
}

TEST(OutlineDxfErrors, NoClosedOutlineNamesTheSkippedEntities) {
  // Was: only "no closed outline": the program prints warnings after a successful read, so the
  // reason the only circle was dropped was lost.
  for (const std::string extrusion : {"1\n220\n0\n230\n0", "0\n220\n0\n230\n0"}) {
    const std::string path =
        write_dxf("dxf_extrusion.dxf",
                  entities_dxf("0\nCIRCLE\n8\nc\n10\n0\n20\n0\n40\n5\n210\n" + extrusion + "\n"));
    EXPECT_EQ(read_error(path), path +
                                    ": no closed outline; skipped 1 CIRCLE entity (not "
                                    "parallel to the XY plane)");
  }
}

TEST(OutlineDxfErrors, NoRadius) {
  const std::string path = fixture("a_rect_lwpolyline.dxf");
  EXPECT_EQ(read_error(path, ReadOptions{}), path + ": no disk radius (give --radius)");
  ReadOptions o = options();
  o.radius = -1.0;
  EXPECT_EQ(read_error(path, o), path + ": disk radius must be > 0 (-1)");
}

#ifdef HEXDEM_HAVE_LATTICE_GENERATOR
namespace {

/// A disk's place on the lattice, as a key that tolerates round-off in its coordinates.
std::pair<long long, long long> disk_key(const hexdem::meshing::Lattice& l, std::size_t i) {
  const double unit = 0.01 * kRadius;
  return {std::llround(l.y[i] / unit), std::llround(l.x[i] / unit)};
}

}  // namespace

TEST(OutlineDxfLattice, LooseLinesMatchTomlRectangle) {
  using namespace hexdem::meshing;
  const Outline from_dxf = read_outline_dxf(fixture("b_rect_lines.dxf"), options());
  const std::string toml_text = R"(units = "mm"
[[body]]
name = "body1"
material = 1
[[body.shape]]
type = "rectangle"
min = [10, 5]
max = [50, 25]
boundary = { bottom = "bottom", right = "right", top = "top", left = "left" }
)";
  Outline from_toml = parse_outline_toml(toml_text, "b_rect.toml", options());
  validate_and_orient(from_toml);

  GeneratorOptions g;
  g.lattice.radius = kRadius;
  const Lattice a = generate_lattice(from_dxf, g);
  const Lattice b = generate_lattice(from_toml, g);
  ASSERT_GT(a.num_disks(), 100U);
  ASSERT_EQ(a.num_disks(), b.num_disks());
  ASSERT_EQ(a.num_bonds(), b.num_bonds());

  // Match disks by position, then compare cells, kinds, bonds and boundary sets.
  std::map<std::pair<long long, long long>, std::size_t> index_b;
  for (std::size_t i = 0; i < b.num_disks(); ++i) index_b[disk_key(b, i)] = i;
  ASSERT_EQ(index_b.size(), b.num_disks());
  std::vector<std::size_t> to_b(a.num_disks());
  const double hex_area = 2.0 * std::sqrt(3.0) * kRadius * kRadius;
  for (std::size_t i = 0; i < a.num_disks(); ++i) {
    const auto it = index_b.find(disk_key(a, i));
    ASSERT_NE(it, index_b.end()) << "disk " << i << " at " << a.x[i] << ", " << a.y[i];
    const std::size_t j = to_b[i] = it->second;
    EXPECT_NEAR(a.x[i], b.x[j], 1e-12);
    EXPECT_NEAR(a.y[i], b.y[j], 1e-12);
    EXPECT_NEAR(a.cell_area[i], b.cell_area[j], 1e-10 * hex_area) << "disk " << i;
    EXPECT_EQ(a.kind[i], b.kind[j]) << "disk " << i;
    EXPECT_EQ(a.material[i], b.material[j]);
  }
  std::set<std::pair<std::size_t, std::size_t>> bonds_a, bonds_b;
  for (std::size_t k = 0; k < a.num_bonds(); ++k) {
    const std::size_t i = to_b[static_cast<std::size_t>(a.bond_i[k])];
    const std::size_t j = to_b[static_cast<std::size_t>(a.bond_j[k])];
    bonds_a.insert({std::min(i, j), std::max(i, j)});
  }
  for (std::size_t k = 0; k < b.num_bonds(); ++k) {
    const auto i = static_cast<std::size_t>(b.bond_i[k]);
    const auto j = static_cast<std::size_t>(b.bond_j[k]);
    bonds_b.insert({std::min(i, j), std::max(i, j)});
  }
  EXPECT_EQ(bonds_a, bonds_b);

  ASSERT_EQ(a.num_sets(), b.num_sets());
  for (std::size_t s = 0; s < a.num_sets(); ++s) {
    const int t = b.find_set(a.set_names[s]);
    ASSERT_GE(t, 0) << a.set_names[s];
    std::map<std::size_t, double> length_a, length_b;
    for (auto e = a.set_offset[s]; e < a.set_offset[s + 1]; ++e)
      length_a[to_b[static_cast<std::size_t>(a.set_disk[static_cast<std::size_t>(e)])]] =
          a.set_length[static_cast<std::size_t>(e)];
    const auto st = static_cast<std::size_t>(t);
    for (auto e = b.set_offset[st]; e < b.set_offset[st + 1]; ++e)
      length_b[static_cast<std::size_t>(b.set_disk[static_cast<std::size_t>(e)])] =
          b.set_length[static_cast<std::size_t>(e)];
    ASSERT_EQ(length_a.size(), length_b.size()) << a.set_names[s];
    for (const auto& [disk, length] : length_a) {
      ASSERT_TRUE(length_b.count(disk)) << a.set_names[s] << " disk " << disk;
      EXPECT_NEAR(length, length_b[disk], 1e-12) << a.set_names[s] << " disk " << disk;
    }
  }
}
#endif
