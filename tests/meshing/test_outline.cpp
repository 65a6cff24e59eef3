// Tests of the outline geometry helpers (signed_area, flatten_arc, boundary_index) and of
// validate_and_orient called directly on hand-built outlines.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/outline.hpp"

namespace {

using hexdem::meshing::BodyOutline;
using hexdem::meshing::flatten_arc;
using hexdem::meshing::Loop;
using hexdem::meshing::Outline;
using hexdem::meshing::signed_area;
using hexdem::meshing::validate_and_orient;
using hexdem::meshing::Vec2;

constexpr double kPi = std::numbers::pi;

/// A loop with edge k carrying edge set k (so edges can be traced through reordering).
Loop make_loop(std::vector<Vec2> points, const std::string& where) {
  Loop loop;
  loop.points = std::move(points);
  for (std::size_t k = 0; k < loop.points.size(); ++k) {
    loop.edge_set.push_back(static_cast<std::int32_t>(k));
    loop.edge_straight.push_back(static_cast<std::uint8_t>(k % 2));
  }
  loop.where = where;
  return loop;
}

/// A regular n-gon of radius r about c, counter-clockwise.
std::vector<Vec2> regular_polygon(Vec2 c, double r, std::size_t n) {
  std::vector<Vec2> points;
  for (std::size_t k = 0; k < n; ++k) {
    const double angle = 2.0 * kPi * static_cast<double>(k) / static_cast<double>(n);
    points.push_back({c.x + r * std::cos(angle), c.y + r * std::sin(angle)});
  }
  return points;
}

BodyOutline make_body(const std::string& name, std::vector<Loop> outers, std::vector<Loop> holes = {}) {
  BodyOutline body;
  body.name = name;
  body.where = "test: body '" + name + "'";
  body.outers = std::move(outers);
  body.holes = std::move(holes);
  return body;
}

/// The message of the InputError that validate_and_orient throws, or "" if none.
std::string validation_error(Outline outline) {
  try {
    validate_and_orient(outline);
  } catch (const hexdem::InputError& error) {
    return error.what();
  }
  return "";
}

/// Largest distance of the chord p-q from the circle of radius r about c (its sagitta).
double sagitta(Vec2 p, Vec2 q, Vec2 c, double r) {
  const Vec2 mid{0.5 * (p.x + q.x), 0.5 * (p.y + q.y)};
  return r - std::hypot(mid.x - c.x, mid.y - c.y);
}

TEST(Outline, SignedAreaIsPositiveCounterClockwise) {
  const Loop square = make_loop({{0, 0}, {2, 0}, {2, 3}, {0, 3}}, "square");
  EXPECT_DOUBLE_EQ(signed_area(square), 6.0);
}

TEST(Outline, SignedAreaIsNegativeClockwise) {
  const Loop triangle = make_loop({{0, 0}, {0, 1}, {1, 0}}, "triangle");
  EXPECT_DOUBLE_EQ(signed_area(triangle), -0.5);
}

TEST(Outline, SignedAreaIsAccurateFarFromOrigin) {
  const double x0 = 1.0e4;
  const Loop square = make_loop({{x0, x0}, {x0 + 1e-3, x0}, {x0 + 1e-3, x0 + 1e-3}, {x0, x0 + 1e-3}},
                                "square");
  EXPECT_NEAR(signed_area(square), 1e-6, 1e-15);
}

TEST(Outline, BoundaryIndexAddsEachNameOnce) {
  Outline outline;
  EXPECT_EQ(outline.boundary_index("base"), 0);
  EXPECT_EQ(outline.boundary_index("load"), 1);
  EXPECT_EQ(outline.boundary_index("base"), 0);
  EXPECT_EQ(outline.boundary_names.size(), 2u);
}

TEST(Outline, FlattenArcEndsExactlyAtEndPoint) {
  const Vec2 c{0.3, -0.2};
  const double r = 0.7;
  const Vec2 a{c.x + r * std::cos(0.1), c.y + r * std::sin(0.1)};
  const Vec2 b{c.x + r * std::cos(2.9), c.y + r * std::sin(2.9)};
  for (const bool ccw : {true, false}) {
    const auto points = flatten_arc(a, b, c, ccw, 1e-4);
    ASSERT_FALSE(points.empty());
    EXPECT_EQ(points.back().x, b.x);
    EXPECT_EQ(points.back().y, b.y);
    for (const Vec2& p : points) EXPECT_NEAR(std::hypot(p.x - c.x, p.y - c.y), r, 1e-12);
  }
}

TEST(Outline, FlattenArcRespectsSagittaBound) {
  const Vec2 c{1.0, 2.0};
  const double r = 0.05;
  const Vec2 a{c.x + r, c.y};
  const Vec2 b{c.x, c.y - r};
  for (const double chord_error : {1e-3, 1e-5, 1e-7}) {
    for (const bool ccw : {true, false}) {
      const auto points = flatten_arc(a, b, c, ccw, chord_error);
      Vec2 previous = a;
      double swept = 0.0;
      for (const Vec2& p : points) {
        EXPECT_LE(sagitta(previous, p, c, r), chord_error * (1.0 + 1e-9));
        const double turn = std::atan2((previous.x - c.x) * (p.y - c.y) - (previous.y - c.y) * (p.x - c.x),
                                       (previous.x - c.x) * (p.x - c.x) + (previous.y - c.y) * (p.y - c.y));
        EXPECT_EQ(turn > 0.0, ccw) << "chord turns against the direction of travel";
        swept += turn;
        previous = p;
      }
      // Counter-clockwise from 0 to -90 degrees sweeps 270 degrees; clockwise sweeps 90.
      EXPECT_NEAR(swept, ccw ? 1.5 * kPi : -0.5 * kPi, 1e-9);
    }
  }
}

TEST(Outline, FlattenArcUsesFewestChords) {
  const double r = 1.0;
  const double chord_error = 1e-3;
  const auto points = flatten_arc({r, 0.0}, {0.0, r}, {0.0, 0.0}, true, chord_error);
  const double max_angle = 2.0 * std::acos(1.0 - chord_error / r);
  EXPECT_EQ(points.size(), static_cast<std::size_t>(std::ceil(0.5 * kPi / max_angle)));
}

TEST(Outline, FlattenArcGivesAtLeastOneSegment) {
  const auto points = flatten_arc({1.0, 0.0}, {0.0, 1.0}, {0.0, 0.0}, true, 10.0);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0].x, 0.0);
  EXPECT_EQ(points[0].y, 1.0);
}

TEST(Outline, FlattenedCircleAreaIsWithinChordErrorBound) {
  const Vec2 c{-0.4, 0.25};
  const double r = 0.02;
  for (const double chord_error : {1e-4, 1e-6}) {
    Loop circle;
    const Vec2 east{c.x + r, c.y};
    const Vec2 west{c.x - r, c.y};
    circle.points.push_back(east);
    for (const Vec2& p : flatten_arc(east, west, c, true, chord_error)) circle.points.push_back(p);
    for (const Vec2& p : flatten_arc(west, east, c, true, chord_error)) circle.points.push_back(p);
    circle.points.pop_back();
    const double exact = kPi * r * r;
    const double area = signed_area(circle);
    // Inscribed chords lose area, at most the perimeter times the sagitta bound.
    EXPECT_LT(area, exact);
    EXPECT_GT(area, exact - 2.0 * kPi * r * chord_error);
  }
}

TEST(Outline, ValidateOrientsOuterCounterClockwiseAndHoleClockwise) {
  // Outer given clockwise, hole counter-clockwise: both are reversed.
  const std::vector<Vec2> outer_cw{{0, 0}, {0, 4}, {4, 4}, {4, 0}};
  const std::vector<Vec2> hole_ccw{{1, 1}, {2, 1}, {2, 2}, {1, 2}};
  Outline outline;
  outline.bodies.push_back(make_body("plate", {make_loop(outer_cw, "outer")}, {make_loop(hole_ccw, "hole")}));
  validate_and_orient(outline);
  const BodyOutline& body = outline.bodies[0];
  EXPECT_GT(signed_area(body.outers[0]), 0.0);
  EXPECT_LT(signed_area(body.holes[0]), 0.0);

  // Every edge still carries its own set and straightness: edge k of the input ran
  // input[k] -> input[k+1]; find that segment (either way round) in the output.
  const auto check_edges = [](const Loop& out, const std::vector<Vec2>& input) {
    const std::size_t n = input.size();
    ASSERT_EQ(out.points.size(), n);
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2 p = out.points[k];
      const Vec2 q = out.points[(k + 1) % n];
      const auto original = static_cast<std::size_t>(out.edge_set[k]);
      const Vec2 u = input[original];
      const Vec2 v = input[(original + 1) % n];
      const bool same = (p.x == v.x && p.y == v.y && q.x == u.x && q.y == u.y) ||
                        (p.x == u.x && p.y == u.y && q.x == v.x && q.y == v.y);
      EXPECT_TRUE(same) << "edge " << k << " lost its set";
      EXPECT_EQ(out.edge_straight[k], original % 2);
    }
  };
  check_edges(body.outers[0], outer_cw);
  check_edges(body.holes[0], hole_ccw);
}

TEST(Outline, ValidateDropsRepeatedVertices) {
  // (1,0) twice, and the closing vertex repeated: 4 distinct vertices remain.
  Outline outline;
  outline.bodies.push_back(
      make_body("b", {make_loop({{0, 0}, {1, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}}, "square")}));
  validate_and_orient(outline);
  const Loop& loop = outline.bodies[0].outers[0];
  ASSERT_EQ(loop.points.size(), 4u);
  EXPECT_EQ(loop.edge_set.size(), 4u);
  EXPECT_EQ(loop.edge_straight.size(), 4u);
  // Edge (1,0) -> (1,1) was input edge 2 (from the repeated vertex); edge (0,1) -> (0,0) was 4.
  EXPECT_EQ(loop.edge_set[1], 2);
  EXPECT_EQ(loop.edge_set[3], 4);
}

TEST(Outline, ValidateRejectsTooFewVertices) {
  Outline outline;
  outline.bodies.push_back(make_body("b", {make_loop({{0, 0}, {1, 0}, {1, 0}, {0, 0}}, "w")}));
  EXPECT_EQ(validation_error(outline), "w: fewer than 3 distinct vertices (got 2)");
}

TEST(Outline, ValidateRejectsZeroArea) {
  Outline outline;
  outline.bodies.push_back(make_body("b", {make_loop({{0, 0}, {1, 1}, {3, 3}}, "w")}));
  EXPECT_EQ(validation_error(outline), "w: zero area (all 3 vertices lie on one line)");
}

TEST(Outline, ValidateRejectsSpike) {
  // Edge 1 runs out to (3, 1) and edge 2 folds back over it.
  Outline outline;
  outline.bodies.push_back(make_body("b", {make_loop({{0, 0}, {2, 0}, {2, 1}, {3, 1}, {1, 1}, {0, 1}}, "w")}));
  const std::string message = validation_error(outline);
  EXPECT_NE(message.find("w: self-intersecting outline (edges"), std::string::npos) << message;
}

TEST(Outline, ValidateRejectsVertexTouchingAnEdge) {
  Outline outline;
  outline.bodies.push_back(make_body("b", {make_loop({{0, 0}, {4, 0}, {4, 4}, {2, 0}, {0, 4}}, "w")}));
  EXPECT_EQ(validation_error(outline), "w: self-intersecting outline (edges 0 and 2 meet at (2, 0))");
}

TEST(Outline, ValidateAcceptsIslandInsideHole) {
  Outline outline;
  outline.bodies.push_back(make_body("b",
                                     {make_loop({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, "outer"),
                                      make_loop({{3, 3}, {7, 3}, {7, 7}, {3, 7}}, "island")},
                                     {make_loop({{1, 1}, {9, 1}, {9, 9}, {1, 9}}, "hole"),
                                      make_loop({{4, 4}, {6, 4}, {6, 6}, {4, 6}}, "island hole")}));
  EXPECT_EQ(validation_error(outline), "");
}

TEST(Outline, ValidateRejectsHoleInsideHole) {
  Outline outline;
  outline.bodies.push_back(make_body("b", {make_loop({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, "outer")},
                                     {make_loop({{1, 1}, {9, 1}, {9, 9}, {1, 9}}, "hole"),
                                      make_loop({{4, 4}, {6, 4}, {6, 6}, {4, 6}}, "inner")}));
  EXPECT_EQ(validation_error(outline), "inner: hole lies inside another hole (its vertex (4, 4))");
}

TEST(Outline, ValidateRejectsNestedOuters) {
  Outline outline;
  outline.bodies.push_back(make_body("b", {make_loop({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, "big"),
                                           make_loop({{4, 4}, {6, 4}, {6, 6}, {4, 6}}, "small")}));
  EXPECT_EQ(validation_error(outline),
            "small: outer boundary overlaps another outer boundary of body 'b' (its vertex (4, 4) is "
            "inside it)");
}

TEST(Outline, ValidateRejectsTouchingOutersOfOneBody) {
  Outline outline;
  outline.bodies.push_back(make_body("b", {make_loop({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, "left"),
                                           make_loop({{1, 0}, {2, 0}, {2, 1}, {1, 1}}, "right")}));
  const std::string message = validation_error(outline);
  EXPECT_NE(message.find("right: outer boundary touches or crosses outer boundary left"), std::string::npos)
      << message;
}

TEST(Outline, ValidateTellsTouchingFromOverlappingBodies) {
  Outline touching;
  touching.bodies.push_back(make_body("a", {make_loop({{0, 0}, {2, 0}, {2, 1}, {0, 1}}, "a")}));
  // Shares part of a's top edge, and one vertex with it.
  touching.bodies.push_back(make_body("b", {make_loop({{1, 1}, {2, 1}, {2, 2}, {1, 2}}, "b")}));
  EXPECT_EQ(validation_error(touching), "");

  Outline corner = touching;
  corner.bodies[1] = make_body("b", {make_loop({{2, 1}, {3, 1}, {3, 2}, {2, 2}}, "b")});
  EXPECT_EQ(validation_error(corner), "");

  Outline overlapping = touching;
  overlapping.bodies[1] = make_body("b", {make_loop({{1, 0.5}, {2, 0.5}, {2, 2}, {1, 2}}, "b")});
  const std::string message = validation_error(overlapping);
  EXPECT_NE(message.find("b: overlaps a (overlap area 0.5 m^2"), std::string::npos) << message;
}

TEST(Outline, ValidateAllowsBodyInsideAnotherBodysHole) {
  Outline outline;
  outline.bodies.push_back(make_body("ring", {make_loop({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, "outer")},
                                     {make_loop({{2, 2}, {8, 2}, {8, 8}, {2, 8}}, "hole")}));
  // Fills the hole exactly: touches along the whole hole boundary but does not overlap.
  outline.bodies.push_back(make_body("plug", {make_loop({{2, 2}, {8, 2}, {8, 8}, {2, 8}}, "plug")}));
  EXPECT_EQ(validation_error(outline), "");
}

TEST(Outline, ValidateNestsThousandsOfLoopsByTheirRays) {
  // Which loops contain which is found by rays through edge bands (was: a point-in-polygon
  // test per pair of loops, minutes for 2,000 holes or 500 nested rings). A grid of square
  // holes puts every ray exactly through the vertices of the holes in its row (the half-open
  // rule must count them twice or not at all), and rings alternating outer and hole nest
  // 300 deep.
  std::vector<Loop> holes;
  for (int a = 0; a < 45; ++a)
    for (int b = 0; b < 45; ++b)
      holes.push_back(make_loop({{2.0 * a + 1, 2.0 * b + 1}, {2.0 * a + 2, 2.0 * b + 1}, {2.0 * a + 2, 2.0 * b + 2},
                                 {2.0 * a + 1, 2.0 * b + 2}},
                                "hole " + std::to_string(a) + "," + std::to_string(b)));
  Outline grid;
  grid.bodies.push_back(make_body("grid", {make_loop({{0, 0}, {91, 0}, {91, 91}, {0, 91}}, "outer")}, holes));
  EXPECT_EQ(validation_error(grid), "");
  // One more hole around a whole row of them: those holes now lie in a hole.
  Outline row = grid;
  row.bodies[0].holes.push_back(make_loop({{0.5, 4.5}, {90.5, 4.5}, {90.5, 6.5}, {0.5, 6.5}}, "band"));
  EXPECT_EQ(validation_error(row), "hole 0,2: hole lies inside another hole (its vertex (1, 5))");

  std::vector<Loop> outers, rings;
  for (int k = 0; k < 300; ++k) {
    Loop ring = make_loop(regular_polygon({0, 0}, 100.0 - 0.3 * k, 64), "ring " + std::to_string(k));
    (k % 2 == 0 ? outers : rings).push_back(std::move(ring));
  }
  Outline nested;
  nested.bodies.push_back(make_body("rings", outers, rings));
  EXPECT_EQ(validation_error(nested), "");
  // Ring 151 an outer instead of a hole: it lies in outer ring 150 with nothing between.
  Outline wrong = nested;
  wrong.bodies[0].outers.insert(wrong.bodies[0].outers.begin(), wrong.bodies[0].holes[75]);
  wrong.bodies[0].holes.erase(wrong.bodies[0].holes.begin() + 75);
  EXPECT_EQ(validation_error(wrong).rfind("ring 151: outer boundary overlaps another outer boundary of body 'rings'", 0), 0U)
      << validation_error(wrong);
}

TEST(Outline, ValidateFindsBodiesInsideBodiesThatDoNotTouch) {
  // The exact overlap test runs only on pairs of bodies whose edges meet or of which one lies
  // in the other's region (was: every pair with overlapping boxes, minutes for nested islands).
  Outline inside;
  inside.bodies.push_back(make_body("a", {make_loop({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, "a")}));
  inside.bodies.push_back(make_body("b", {make_loop({{4, 4}, {6, 4}, {6, 6}, {4, 6}}, "b")}));
  EXPECT_EQ(validation_error(inside).rfind("b: overlaps a (overlap area 4 m^2", 0), 0U) << validation_error(inside);
  Outline around = inside;  // the larger one second
  std::swap(around.bodies[0], around.bodies[1]);
  EXPECT_EQ(validation_error(around).rfind("a: overlaps b (overlap area 4 m^2", 0), 0U) << validation_error(around);

  // 60 rings, each a body of its own in the previous one's hole: no overlap.
  Outline islands;
  for (int k = 0; k < 60; ++k) {
    const double r = 100.0 - 1.5 * k;
    islands.bodies.push_back(make_body("ring " + std::to_string(k), {make_loop(regular_polygon({0, 0}, r, 48), "outer " + std::to_string(k))},
                                       {make_loop(regular_polygon({0, 0}, r - 0.75, 48), "hole " + std::to_string(k))}));
  }
  EXPECT_EQ(validation_error(islands), "");
  // A square in the material of ring 30 (between radii 54.25 and 55): it overlaps that ring only.
  islands.bodies.push_back(make_body("chip", {make_loop({{54.4, -0.1}, {54.9, -0.1}, {54.9, 0.1}, {54.4, 0.1}}, "chip")}));
  EXPECT_EQ(validation_error(islands).rfind("chip: overlaps outer 30 (overlap area 0.1 m^2", 0), 0U)
      << validation_error(islands);
}

TEST(Outline, ValidatesLargePolygonWithHoles) {
  // A 1,000-vertex star-shaped outer with 10 holes of 100 vertices.
  std::vector<Vec2> outer;
  for (std::size_t k = 0; k < 1000; ++k) {
    const double angle = 2.0 * kPi * static_cast<double>(k) / 1000.0;
    const double r = 1.0 + 0.05 * std::sin(37.0 * angle);
    outer.push_back({r * std::cos(angle), r * std::sin(angle)});
  }
  std::vector<Loop> holes;
  for (std::size_t h = 0; h < 10; ++h) {
    const double angle = 2.0 * kPi * static_cast<double>(h) / 10.0;
    holes.push_back(make_loop(regular_polygon({0.6 * std::cos(angle), 0.6 * std::sin(angle)}, 0.1, 100),
                              "hole " + std::to_string(h)));
  }
  Outline outline;
  outline.bodies.push_back(make_body("big", {make_loop(outer, "outer")}, std::move(holes)));
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(validation_error(outline), "");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("seconds", std::to_string(seconds));
}

}  // namespace
