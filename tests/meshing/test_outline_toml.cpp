// Tests of the TOML outline reader: every shape type and key, units, the resolution order
// of lattice options, and one test per kind of bad input checking the whole message.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <string>
#include <string_view>

#include "hexdem/error.hpp"
#include "hexdem/meshing/outline_toml.hpp"

namespace {

using hexdem::meshing::Loop;
using hexdem::meshing::Outline;
using hexdem::meshing::parse_outline_toml;
using hexdem::meshing::read_outline_toml;
using hexdem::meshing::ReadOptions;
using hexdem::meshing::signed_area;
using hexdem::meshing::Vec2;

constexpr double kPi = std::numbers::pi;

/// Drops the newline that opens a raw string, so that line 1 is the first line written.
std::string text_of(std::string_view text) {
  if (!text.empty() && text.front() == '\n') text.remove_prefix(1);
  return std::string(text);
}

ReadOptions with_radius(double radius = 0.5e-3) {
  ReadOptions options;
  options.radius = radius;
  return options;
}

Outline parse(std::string_view text, const ReadOptions& options = with_radius()) {
  return parse_outline_toml(text_of(text), "case.toml", options);
}

/// The message of the InputError that parsing throws, or "" if none.
std::string error_of(std::string_view text, const ReadOptions& options = with_radius()) {
  try {
    parse(text, options);
  } catch (const hexdem::InputError& error) {
    return error.what();
  }
  return "";
}

std::string write_work_file(const std::string& name, std::string_view contents) {
  const std::string path = std::string(HEXDEM_TEST_WORK_DIR) + "/" + name;
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

/// Name of the boundary set of edge k, "" if none.
std::string edge_name(const Outline& outline, const Loop& loop, std::size_t k) {
  return loop.edge_set[k] < 0 ? "" : outline.boundary_names[static_cast<std::size_t>(loop.edge_set[k])];
}

bool same_point(Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; }

/// Index of the edge that runs from p to q, or the number of edges if there is none.
std::size_t find_edge(const Loop& loop, Vec2 p, Vec2 q) {
  const std::size_t n = loop.points.size();
  for (std::size_t k = 0; k < n; ++k) {
    if (same_point(loop.points[k], p) && same_point(loop.points[(k + 1) % n], q)) return k;
  }
  return n;
}

bool starts_with(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

constexpr std::string_view kTwoBodies = R"(
[[body]]
name = "target"
  [[body.shape]]
  type = "rectangle"
  min = [0.0, -0.05]
  max = [0.2, 0.0]
[[body]]
name = "projectile"
  [[body.shape]]
  type = "circle"
  center = [0.1, CENTER_Y]
  radius = 0.01
)";

std::string two_bodies(const std::string& center_y) {
  std::string text(kTwoBodies);
  text.replace(text.find("CENTER_Y"), 8, center_y);
  return text;
}

TEST(OutlineToml, ReadsRectangleWithSideNames) {
  const Outline outline = parse(R"(
[[body]]
name = "target"
material = 3
  [[body.shape]]
  type = "rectangle"
  min = [0.0, -0.05]
  max = [0.2, 0.0]
  boundary = { bottom = "base", right = "far", left = "sym" }
)");
  EXPECT_EQ(outline.source, "case.toml");
  ASSERT_EQ(outline.bodies.size(), 1u);
  const auto& body = outline.bodies[0];
  EXPECT_EQ(body.name, "target");
  EXPECT_EQ(body.material, 3);
  EXPECT_EQ(body.where, "case.toml:1: body 'target'");
  ASSERT_EQ(body.outers.size(), 1u);
  EXPECT_TRUE(body.holes.empty());
  const Loop& loop = body.outers[0];
  EXPECT_EQ(loop.where, "case.toml:4: body 'target' shape[0] (rectangle)");
  ASSERT_EQ(loop.points.size(), 4u);
  const Vec2 corners[] = {{0.0, -0.05}, {0.2, -0.05}, {0.2, 0.0}, {0.0, 0.0}};
  const char* names[] = {"base", "far", "", "sym"};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_TRUE(same_point(loop.points[k], corners[k])) << k;
    EXPECT_EQ(edge_name(outline, loop, k), names[k]) << k;
    EXPECT_EQ(loop.edge_straight[k], 1) << k;
  }
}

TEST(OutlineToml, ReadsRectangleWithOneName) {
  const Outline outline = parse(R"(
[[body]]
name = "b"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [1, 2]
  boundary = "wall"
)");
  const Loop& loop = outline.bodies[0].outers[0];
  for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(edge_name(outline, loop, k), "wall");
  EXPECT_EQ(outline.bodies[0].material, 1);
  EXPECT_DOUBLE_EQ(signed_area(loop), 2.0);
}

TEST(OutlineToml, ReadsPolygonWithPerEdgeNames) {
  // Given clockwise: the reader returns it counter-clockwise with each name on its edge.
  const Outline outline = parse(R"(
[[body]]
name = "b"
  [[body.shape]]
  type = "polygon"
  points = [[0, 0], [0, 1], [1, 1], [1, 0]]
  boundary = ["left", "", "right", "bottom"]
)");
  const Loop& loop = outline.bodies[0].outers[0];
  EXPECT_GT(signed_area(loop), 0.0);
  const auto name_between = [&](Vec2 p, Vec2 q) {
    std::size_t k = find_edge(loop, p, q);
    if (k == loop.points.size()) k = find_edge(loop, q, p);
    return k == loop.points.size() ? std::string("(no edge)") : edge_name(outline, loop, k);
  };
  EXPECT_EQ(name_between({0, 0}, {0, 1}), "left");
  EXPECT_EQ(name_between({0, 1}, {1, 1}), "");
  EXPECT_EQ(name_between({1, 1}, {1, 0}), "right");
  EXPECT_EQ(name_between({1, 0}, {0, 0}), "bottom");
  EXPECT_TRUE(std::all_of(loop.edge_straight.begin(), loop.edge_straight.end(),
                          [](std::uint8_t s) { return s == 1; }));
}

TEST(OutlineToml, ReadsCircle) {
  ReadOptions options = with_radius(0.5e-3);
  options.chord_fraction = 1e-2;
  const Outline outline = parse(R"(
[[body]]
name = "disc"
  [[body.shape]]
  type = "circle"
  center = [0.1, 0.2]
  radius = 0.01
  boundary = "rim"
)",
                                options);
  const Loop& loop = outline.bodies[0].outers[0];
  const double r = 0.01;
  const double chord_error = 1e-2 * 0.5e-3;
  const std::size_t n = loop.points.size();
  ASSERT_GE(n, 8u);
  EXPECT_TRUE(same_point(loop.points[0], {0.11, 0.2}));
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 p = loop.points[k];
    const Vec2 q = loop.points[(k + 1) % n];
    EXPECT_NEAR(std::hypot(p.x - 0.1, p.y - 0.2), r, 1e-12);
    const double mid = std::hypot(0.5 * (p.x + q.x) - 0.1, 0.5 * (p.y + q.y) - 0.2);
    EXPECT_LE(r - mid, chord_error * (1.0 + 1e-6));
    EXPECT_EQ(edge_name(outline, loop, k), "rim");
    EXPECT_EQ(loop.edge_straight[k], 0);
  }
  const double area = signed_area(loop);
  EXPECT_LT(area, kPi * r * r);
  EXPECT_GT(area, kPi * r * r - 2.0 * kPi * r * chord_error);
}

TEST(OutlineToml, ReadsPathWithArcAboutCentre) {
  // A quarter disc: straight base, arc about the origin, straight edge back.
  const Outline outline = parse(R"(
[[body]]
name = "quarter"
  [[body.shape]]
  type = "path"
  start = [0.0, 0.0]
  boundary = "side"
  segments = [
    { to = [0.01, 0.0], boundary = "base" },
    { to = [0.0, 0.01], center = [0.0, 0.0], direction = "ccw" },
    { to = [0.0, 0.0], bulge = 0.0 },
  ]
)");
  const Loop& loop = outline.bodies[0].outers[0];
  const std::size_t n = loop.points.size();
  ASSERT_GT(n, 4u);
  EXPECT_TRUE(same_point(loop.points[0], {0.0, 0.0}));
  EXPECT_TRUE(same_point(loop.points[1], {0.01, 0.0}));
  EXPECT_TRUE(same_point(loop.points[n - 1], {0.0, 0.01}));
  EXPECT_EQ(edge_name(outline, loop, 0), "base");
  EXPECT_EQ(loop.edge_straight[0], 1);
  for (std::size_t k = 1; k + 1 < n; ++k) {
    EXPECT_EQ(edge_name(outline, loop, k), "side");
    EXPECT_EQ(loop.edge_straight[k], 0);
  }
  EXPECT_EQ(edge_name(outline, loop, n - 1), "side");
  EXPECT_EQ(loop.edge_straight[n - 1], 1);
  EXPECT_NEAR(signed_area(loop), 0.25 * kPi * 1e-4, 1e-8);
}

TEST(OutlineToml, ReadsClockwiseArcAndBulges) {
  // Half discs on the chord (0,0)-(0.02,0): below it by a clockwise arc, above it by a
  // bulge of +1 (half a turn counter-clockwise), and below again by a bulge of -1.
  const auto half_disc = [](const std::string& closing) {
    return parse(std::string(R"(
[[body]]
name = "half"
  [[body.shape]]
  type = "path"
  start = [0.0, 0.0]
  segments = [ { to = [0.02, 0.0] }, )") +
                 closing + " ]\n");
  };
  const auto y_range = [](const Loop& loop) {
    double lo = 0.0, hi = 0.0;
    for (const Vec2& p : loop.points) {
      lo = std::min(lo, p.y);
      hi = std::max(hi, p.y);
    }
    return std::pair{lo, hi};
  };
  const double half_area = 0.5 * kPi * 1e-4;
  for (const auto& [closing, below] :
       {std::pair{std::string("{ to = [0.0, 0.0], center = [0.01, 0.0], direction = \"cw\" }"), true},
        std::pair{std::string("{ to = [0.0, 0.0], bulge = 1.0 }"), false},
        std::pair{std::string("{ to = [0.0, 0.0], bulge = -1 }"), true}}) {
    const Outline outline = half_disc(closing);
    const Loop& loop = outline.bodies[0].outers[0];
    const auto [lo, hi] = y_range(loop);
    EXPECT_NEAR(below ? -lo : hi, 0.01, 1e-9) << closing;
    EXPECT_EQ(below ? hi : lo, 0.0) << closing;
    EXPECT_NEAR(signed_area(loop), half_area, 2e-8) << closing;
  }
}

TEST(OutlineToml, ReadsHoleAndOrientsIt) {
  const Outline outline = parse(R"(
[[body]]
name = "plate"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [1, 1]
  [[body.shape]]
  type = "circle"
  role = "hole"
  center = [0.5, 0.5]
  radius = 0.2
  boundary = "bore"
)");
  const auto& body = outline.bodies[0];
  ASSERT_EQ(body.outers.size(), 1u);
  ASSERT_EQ(body.holes.size(), 1u);
  EXPECT_GT(signed_area(body.outers[0]), 0.0);
  EXPECT_LT(signed_area(body.holes[0]), 0.0);
  EXPECT_EQ(body.holes[0].where, "case.toml:7: body 'plate' shape[1] (circle)");
  EXPECT_EQ(edge_name(outline, body.holes[0], 0), "bore");
}

TEST(OutlineToml, ScalesLengthsByUnits) {
  ReadOptions options;  // no command-line radius: [lattice] gives it, in file units
  const Outline outline = parse(R"(
units = "mm"
[lattice]
radius = 0.5
origin = [1, 2]
[[body]]
name = "b"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [10, 5]
[[body]]
name = "c"
radius = 0.25
  [[body.shape]]
  type = "circle"
  center = [20, 0]
  radius = 3
)",
                                options);
  const auto& b = outline.bodies[0];
  EXPECT_DOUBLE_EQ(*b.radius, 0.5e-3);
  EXPECT_DOUBLE_EQ(b.origin->x, 1e-3);
  EXPECT_DOUBLE_EQ(b.origin->y, 2e-3);
  EXPECT_DOUBLE_EQ(b.outers[0].points[2].x, 0.01);
  EXPECT_DOUBLE_EQ(b.outers[0].points[2].y, 0.005);
  const auto& c = outline.bodies[1];
  EXPECT_DOUBLE_EQ(*c.radius, 0.25e-3);
  EXPECT_DOUBLE_EQ(c.outers[0].points[0].x, 0.023);
  EXPECT_NEAR(signed_area(c.outers[0]), kPi * 9e-6, 1e-8);
}

TEST(OutlineToml, CommandLineLengthsAreNotScaled) {
  ReadOptions options = with_radius(3e-3);
  options.origin = Vec2{0.1, 0.2};
  const Outline outline = parse(R"(
units = "cm"
[[body]]
name = "b"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [10, 5]
)",
                                options);
  const auto& body = outline.bodies[0];
  EXPECT_DOUBLE_EQ(*body.radius, 3e-3);
  EXPECT_DOUBLE_EQ(body.origin->x, 0.1);
  EXPECT_DOUBLE_EQ(body.origin->y, 0.2);
  EXPECT_DOUBLE_EQ(body.outers[0].points[2].x, 0.1);
}

// radius_factor scales the radius the body would otherwise get ([lattice], or the command line
// over it), so that a body refined against the others stays refined at any --radius; a factor
// is a pure number, not a length in the file's units.
TEST(OutlineToml, RadiusFactorScalesTheLatticeRadius) {
  const std::string text = R"(
units = "mm"
[lattice]
radius = 0.5
[[body]]
name = "target"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [10, 5]
[[body]]
name = "warhead"
radius_factor = 0.5
  [[body.shape]]
  type = "circle"
  center = [20, 0]
  radius = 3
)";
  const Outline from_file = parse(text, ReadOptions{});
  EXPECT_DOUBLE_EQ(*from_file.bodies[0].radius, 0.5e-3);
  EXPECT_DOUBLE_EQ(*from_file.bodies[1].radius, 0.25e-3);
  const Outline from_command_line = parse(text, with_radius(1e-3));
  EXPECT_DOUBLE_EQ(*from_command_line.bodies[0].radius, 1e-3);
  EXPECT_DOUBLE_EQ(*from_command_line.bodies[1].radius, 0.5e-3);
}

TEST(OutlineToml, RejectsBadRadiusFactor) {
  const std::string body = R"(
[[body]]
name = "warhead"
)";
  EXPECT_EQ(error_of(body + "radius_factor = 0\n"),
            "case.toml:3: body[0].radius_factor: must be > 0 (got 0)");
  EXPECT_EQ(error_of(body + "radius_factor = 1000\n"),
            "case.toml:3: body[0].radius_factor: must be in [0.01, 100] (got 1000)");
  EXPECT_EQ(error_of(body + "radius_factor = \"half\"\n"),
            "case.toml:3: body[0].radius_factor: expected a number (got \"half\")");
  EXPECT_EQ(error_of(body + "radius = 0.25\nradius_factor = 0.5\n"),
            "case.toml:4: body[0].radius_factor: give the body's radius or its radius_factor, not "
            "both (got radius_factor = 0.5)");
}

TEST(OutlineToml, ScaleOptionOverridesUnits) {
  ReadOptions options = with_radius();
  options.scale = 0.0254;
  const Outline outline = parse(R"(
units = "mm"
[[body]]
name = "b"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [10, 5]
)",
                                options);
  EXPECT_DOUBLE_EQ(outline.bodies[0].outers[0].points[2].x, 0.254);
}

TEST(OutlineToml, AcceptsEveryUnit) {
  for (const auto& [unit, factor] : {std::pair{"m", 1.0}, std::pair{"cm", 0.01}, std::pair{"mm", 1e-3},
                                     std::pair{"um", 1e-6}, std::pair{"in", 0.0254}, std::pair{"ft", 0.3048}}) {
    const Outline outline = parse("units = \"" + std::string(unit) + R"("
[[body]]
name = "b"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [2, 1]
)");
    EXPECT_DOUBLE_EQ(outline.bodies[0].outers[0].points[1].x, 2.0 * factor) << unit;
  }
}

TEST(OutlineToml, ResolvesLatticeOptionsBodyThenCommandLineThenFile) {
  constexpr std::string_view text = R"(
[lattice]
radius = 1.0e-3
angle = 30.0
origin = [0.5, 0.5]
[[body]]
name = "own"
radius = 2.0e-3
angle = 10
origin = [0.1, 0.2]
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [1, 1]
[[body]]
name = "inherits"
  [[body.shape]]
  type = "rectangle"
  min = [2, 0]
  max = [3, 1]
)";
  const Outline from_file = parse(text, ReadOptions{});
  const auto& own = from_file.bodies[0];
  EXPECT_DOUBLE_EQ(*own.radius, 2e-3);
  EXPECT_DOUBLE_EQ(*own.angle_deg, 10.0);
  EXPECT_DOUBLE_EQ(own.origin->y, 0.2);
  const auto& inherits = from_file.bodies[1];
  EXPECT_DOUBLE_EQ(*inherits.radius, 1e-3);
  EXPECT_DOUBLE_EQ(*inherits.angle_deg, 30.0);
  EXPECT_DOUBLE_EQ(inherits.origin->x, 0.5);

  ReadOptions options = with_radius(3e-3);
  options.angle_deg = 45.0;
  options.origin = Vec2{7.0, 8.0};
  const Outline from_command_line = parse(text, options);
  EXPECT_DOUBLE_EQ(*from_command_line.bodies[0].radius, 2e-3);
  EXPECT_DOUBLE_EQ(*from_command_line.bodies[0].angle_deg, 10.0);
  EXPECT_DOUBLE_EQ(from_command_line.bodies[0].origin->x, 0.1);
  const auto& overridden = from_command_line.bodies[1];
  EXPECT_DOUBLE_EQ(*overridden.radius, 3e-3);
  EXPECT_DOUBLE_EQ(*overridden.angle_deg, 45.0);
  EXPECT_DOUBLE_EQ(overridden.origin->x, 7.0);
  EXPECT_DOUBLE_EQ(overridden.origin->y, 8.0);
}

TEST(OutlineToml, DefaultsAngleAndOrigin) {
  const Outline outline = parse(R"(
[[body]]
name = "b"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [1, 1]
)");
  EXPECT_EQ(*outline.bodies[0].angle_deg, 0.0);
  EXPECT_EQ(outline.bodies[0].origin->x, 0.0);
  EXPECT_EQ(outline.bodies[0].origin->y, 0.0);
}

TEST(OutlineToml, ReadsFileFromDisk) {
  const std::string path = write_work_file("outline_from_disk.toml", text_of(two_bodies("0.01")));
  const Outline outline = read_outline_toml(path, with_radius());
  EXPECT_EQ(outline.source, path);
  ASSERT_EQ(outline.bodies.size(), 2u);
  EXPECT_EQ(outline.bodies[1].outers[0].where, path + ":9: body 'projectile' shape[0] (circle)");
}

TEST(OutlineToml, RejectsParseError) {
  const std::string message = error_of(R"(
[[body]]
name = "unterminated
)");
  EXPECT_TRUE(starts_with(message, "case.toml:2:")) << message;
  EXPECT_NE(message.find(": TOML parse error: "), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(OutlineToml, RejectsUnknownKey) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "disc"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [1, 1]
  [[body.shape]]
  type = "circle"
  center = [3, 3]
  raduis = 0.5
)"),
            "case.toml:10: body[0].shape[1]: unknown key 'raduis' (allowed: type, role, boundary, "
            "center, radius)");
}

TEST(OutlineToml, RejectsMisspeltShapeType) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "b"
  [[body.shape]]
  tpye = "circle"
)"),
            "case.toml:4: body[0].shape[0]: unknown key 'tpye' (allowed: type, role, boundary, min, "
            "max, points, center, radius, start, segments)");
}

TEST(OutlineToml, RejectsUnknownTopLevelKey) {
  EXPECT_EQ(error_of("unit = \"mm\"\n"),
            "case.toml:1: unknown key 'unit' (allowed: units, lattice, body)");
}

TEST(OutlineToml, RejectsMissingFile) {
  const std::string path = std::string(HEXDEM_TEST_WORK_DIR) + "/no-such-outline.toml";
  try {
    read_outline_toml(path, with_radius());
    FAIL() << "no error";
  } catch (const hexdem::InputError& error) {
    EXPECT_EQ(std::string(error.what()), path + ": cannot open file");
  }
}

TEST(OutlineToml, RejectsEmptyFile) {
  const std::string path = write_work_file("empty_outline.toml", "");
  try {
    read_outline_toml(path, with_radius());
    FAIL() << "no error";
  } catch (const hexdem::InputError& error) {
    EXPECT_EQ(std::string(error.what()), path + ": no [[body]] in outline");
  }
  EXPECT_EQ(error_of("[lattice]\nradius = 1e-3\n"), "case.toml: no [[body]] in outline");
}

TEST(OutlineToml, RejectsOpenPath) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "open"
  [[body.shape]]
  type = "path"
  start = [0.0, 0.0]
  segments = [
    { to = [0.01, 0.0] },
    { to = [0.0, 0.01], center = [0.0, 0.0], direction = "ccw" },
  ]
)"),
            "case.toml:8: body[0].shape[0].segments[1].to: open outline (the path ends at (0, 0.01) "
            "but starts at (0, 0))");
}

TEST(OutlineToml, RejectsSelfIntersectingPolygon) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "bowtie"
  [[body.shape]]
  type = "polygon"
  points = [[0, 0], [1, 1], [1, 0], [0, 1]]
)"),
            "case.toml:3: body 'bowtie' shape[0] (polygon): self-intersecting outline (edges 0 and 2 "
            "meet at (0.5, 0.5))");
}

TEST(OutlineToml, RejectsHoleOutsideBoundary) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "plate"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [1, 1]
  [[body.shape]]
  type = "circle"
  role = "hole"
  center = [3, 3]
  radius = 0.5
)"),
            "case.toml:7: body 'plate' shape[1] (circle): hole is not inside an outer boundary of "
            "body 'plate' (its vertex (3.5, 3) is outside)");
}

TEST(OutlineToml, RejectsHoleCrossingBoundary) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "plate"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [1, 1]
  [[body.shape]]
  type = "polygon"
  role = "hole"
  points = [[0.8, 0.4], [0.8, 0.6], [1.2, 0.6], [1.2, 0.4]]
)"),
            "case.toml:7: body 'plate' shape[1] (polygon): hole touches or crosses outer boundary "
            "case.toml:3: body 'plate' shape[0] (rectangle) (its edge 1 meets edge 1 at (1, 0.6))");
}

TEST(OutlineToml, RejectsOverlappingBodies) {
  const std::string message = error_of(two_bodies("0.005"));
  EXPECT_TRUE(starts_with(message,
                          "case.toml:9: body 'projectile' shape[0] (circle): overlaps case.toml:3: "
                          "body 'target' shape[0] (rectangle) (overlap area "))
      << message;
}

TEST(OutlineToml, AllowsTouchingBodies) {
  // The disc rests on the target at one point; the block shares part of its top edge.
  std::string text = two_bodies("0.01");
  text += R"(
[[body]]
name = "block"
  [[body.shape]]
  type = "rectangle"
  min = [0.0, 0.0]
  max = [0.05, 0.02]
)";
  EXPECT_EQ(error_of(text), "");
}

TEST(OutlineToml, RejectsNonPositiveRadius) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "disc"
  [[body.shape]]
  type = "circle"
  center = [0.0, 0.0]
  radius = -0.01
)"),
            "case.toml:6: body[0].shape[0].radius: must be > 0 (got -0.01)");
  EXPECT_EQ(error_of(R"(
[[body]]
name = "disc"
radius = 0
)"),
            "case.toml:3: body[0].radius: must be > 0 (got 0)");
}

TEST(OutlineToml, RejectsInconsistentArcCentre) {
  const std::string message = error_of(R"(
[[body]]
name = "quarter"
  [[body.shape]]
  type = "path"
  start = [0.0, 0.0]
  segments = [
    { to = [0.01, 0.0] },
    { to = [0.0, 0.01], center = [0.0, 0.001], direction = "ccw" },
    { to = [0.0, 0.0] },
  ]
)");
  EXPECT_TRUE(starts_with(message,
                          "case.toml:8: body[0].shape[0].segments[1].center: arc centre is not "
                          "equidistant from the arc's ends (|start - center| = 0.0100498"))
      << message;
  EXPECT_NE(message.find("|to - center| = 0.009"), std::string::npos) << message;
}

TEST(OutlineToml, RejectsMissingRadius) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "x"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [1, 1]
)",
                     ReadOptions{}),
            "case.toml: body 'x': no disk radius (give --radius or [lattice] radius)");
}

TEST(OutlineToml, RejectsDuplicateBodyName) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "a"
  [[body.shape]]
  type = "rectangle"
  min = [0, 0]
  max = [1, 1]
[[body]]
name = "a"
)"),
            "case.toml:8: body[1].name: duplicate body name (got \"a\")");
}

TEST(OutlineToml, RejectsUnknownUnit) {
  EXPECT_EQ(error_of("units = \"yd\"\n"),
            "case.toml:1: units: unknown unit \"yd\" (expected \"m\", \"cm\", \"mm\", \"um\", \"in\" "
            "or \"ft\")");
}

TEST(OutlineToml, RejectsWrongNumberOfEdgeNames) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "b"
  [[body.shape]]
  type = "polygon"
  points = [[0, 0], [1, 0], [1, 1]]
  boundary = ["a", "b"]
)"),
            "case.toml:6: body[0].shape[0].boundary: expected one name per edge, 3 (got 2)");
}

TEST(OutlineToml, RejectsUnknownShapeType) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "b"
  [[body.shape]]
  type = "ellipse"
)"),
            "case.toml:4: body[0].shape[0].type: unknown shape type \"ellipse\" (expected "
            "\"rectangle\", \"polygon\", \"circle\" or \"path\")");
}

TEST(OutlineToml, RejectsWrongValueType) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "b"
material = 1.5
)"),
            "case.toml:3: body[0].material: expected an integer from 0 to 2147483647 (got 1.5)");
  // An integer beyond the range is named as such (was: "expected an integer >= 0").
  EXPECT_EQ(error_of(R"(
[[body]]
name = "b"
material = 9223372036854775807
)"),
            "case.toml:3: body[0].material: expected an integer from 0 to 2147483647 (got 9223372036854775807)");
  EXPECT_EQ(error_of(R"(
[[body]]
name = "b"
  [[body.shape]]
  type = "rectangle"
  min = [0, "zero"]
  max = [1, 1]
)"),
            "case.toml:5: body[0].shape[0].min[1]: expected a number (got \"zero\")");
}

TEST(OutlineToml, RejectsBodyWithoutShape) {
  EXPECT_EQ(error_of(R"(
[[body]]
name = "b"
)"),
            "case.toml:1: body[0]: no [[body.shape]] (a body needs at least one shape)");
}

}  // namespace
