// Tests of the lattice generator on outlines whose lattices are known by hand, and of the
// area, coordination and boundary-set invariants on general outlines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <utility>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_generator.hpp"

namespace {

using namespace hexdem::meshing;
constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrt3 = 1.7320508075688772935;

Loop make_loop(std::vector<Vec2> pts, std::vector<std::int32_t> sets = {}, bool straight = true) {
  Loop l;
  l.edge_set = sets.empty() ? std::vector<std::int32_t>(pts.size(), -1) : sets;
  l.edge_straight.assign(pts.size(), straight ? 1 : 0);
  l.points = std::move(pts);
  l.where = "test loop";
  return l;
}

Loop rectangle(double x0, double y0, double x1, double y1, std::vector<std::int32_t> sets = {}) {
  return make_loop({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, std::move(sets));
}

Loop reversed(Loop l) {
  // Edge k runs from point k to k+1; reversing maps edge k to edge n-2-k (mod n).
  const std::size_t n = l.points.size();
  Loop r = l;
  for (std::size_t k = 0; k < n; ++k) {
    r.points[k] = l.points[n - 1 - k];
    r.edge_set[k] = l.edge_set[(2 * n - 2 - k) % n];
    r.edge_straight[k] = l.edge_straight[(2 * n - 2 - k) % n];
  }
  return r;
}

Loop circle(Vec2 c, double R, int n, double phase = 0.0) {
  std::vector<Vec2> pts;
  for (int k = 0; k < n; ++k) {
    const double a = phase + 2 * kPi * k / n;
    pts.push_back({c.x + R * std::cos(a), c.y + R * std::sin(a)});
  }
  return make_loop(pts, {}, false);
}

Outline one_body(std::vector<Loop> outers, std::vector<Loop> holes = {},
                 std::vector<std::string> sets = {}) {
  Outline o;
  o.source = "test";
  o.boundary_names = std::move(sets);
  BodyOutline b;
  b.name = "body";
  b.where = "test body";
  b.outers = std::move(outers);
  for (auto& h : holes) b.holes.push_back(reversed(std::move(h)));
  o.bodies.push_back(std::move(b));
  return o;
}

Lattice generate(const Outline& o, double r, double angle = 0.0, Vec2 origin = {},
                 GeometryMode mode = GeometryMode::Plane, GeneratorReport* rep = nullptr) {
  GeneratorOptions opt;
  opt.lattice.radius = r;
  opt.lattice.angle_deg = angle;
  opt.lattice.origin = origin;
  opt.mode = mode;
  return generate_lattice(o, opt, rep);
}

std::vector<int> coordination(const Lattice& lat) {
  std::vector<int> c(lat.num_disks(), 0);
  for (std::size_t b = 0; b < lat.num_bonds(); ++b) {
    ++c[lat.bond_i[b]];
    ++c[lat.bond_j[b]];
  }
  return c;
}

double cell_sum(const Lattice& lat) {
  return std::accumulate(lat.cell_area.begin(), lat.cell_area.end(), 0.0);
}

long count_semi(const Lattice& lat) {
  return std::count(lat.kind.begin(), lat.kind.end(), static_cast<std::uint8_t>(DiskKind::SemiDisk));
}

/// Every bond joins two disks of one body at distance 2r, listed once with i < j.
void check_bonds(const Lattice& lat, double angle_deg = 0.0) {
  std::set<std::pair<int, int>> seen;
  for (std::size_t b = 0; b < lat.num_bonds(); ++b) {
    const int i = lat.bond_i[b], j = lat.bond_j[b];
    const double dist = std::hypot(lat.x[i] - lat.x[j], lat.y[i] - lat.y[j]);
    ASSERT_NEAR(dist, 2 * lat.radius[i], 1e-9 * lat.radius[i]) << "bond " << b;
    ASSERT_LT(i, j);
    ASSERT_EQ(lat.body[i], lat.body[j]);
    ASSERT_TRUE(seen.insert({i, j}).second) << "duplicate bond " << i << "-" << j;
    // Class 1 along the lattice axis, class 2 along the other two directions.
    const double axis = angle_deg * kPi / 180.0;
    const double along = std::abs((lat.x[j] - lat.x[i]) * std::sin(axis) - (lat.y[j] - lat.y[i]) * std::cos(axis));
    ASSERT_EQ(int(lat.bond_class[b]), along < 1e-9 * lat.radius[i] ? 1 : 2) << "bond " << b;
  }
}

TEST(LatticeGenerator, AlignedRectangleExactCounts) {
  // 10 spacings wide, 6 rows high: rows 0..6; even rows 11 disks, odd rows 10.
  const double r = 1e-3, d = 2 * r, h = kSqrt3 * r;
  const Outline o = one_body({rectangle(0, 0, 10 * d, 6 * h, {0, 1, 2, 3})}, {},
                             {"bottom", "right", "top", "left"});
  GeneratorReport rep;
  const Lattice lat = generate(o, r, 0.0, {}, GeometryMode::Plane, &rep);
  EXPECT_EQ(lat.num_disks(), 4u * 11 + 3u * 10);
  EXPECT_EQ(count_semi(lat), 22);          // the two neat rows, corners included
  EXPECT_EQ(lat.num_bonds(), 67u + 120u);  // 4*10 + 3*9 along rows, 6 row pairs * 20
  EXPECT_NEAR(cell_sum(lat), 10 * d * 6 * h, 1e-6 * 10 * d * 6 * h);
  EXPECT_EQ(rep.disks, 74);
  EXPECT_EQ(rep.bonds, 187);
  check_bonds(lat);

  const double hex = 2 * kSqrt3 * r * r;
  for (std::size_t k = 0; k < lat.num_disks(); ++k) {
    const bool on_x_edge = std::abs(lat.x[k]) < 1e-12 || std::abs(lat.x[k] - 10 * d) < 1e-12;
    const bool on_y_edge = std::abs(lat.y[k]) < 1e-12 || std::abs(lat.y[k] - 6 * h) < 1e-12;
    const double expected = hex * (on_x_edge ? 0.5 : 1.0) * (on_y_edge ? 0.5 : 1.0);
    EXPECT_NEAR(lat.cell_area[k], expected, 1e-6 * hex) << "disk at " << lat.x[k] << ", " << lat.y[k];
  }
  // Interior disks have six bonds.
  const auto c = coordination(lat);
  for (std::size_t k = 0; k < lat.num_disks(); ++k) {
    if (lat.x[k] > 1.5 * d && lat.x[k] < 8.5 * d && lat.y[k] > 0.5 * h && lat.y[k] < 5.5 * h) {
      EXPECT_EQ(c[k], 6);
    }
  }
  // Boundary sets: the named edges are shared out exactly.
  const double len[4] = {10 * d, 6 * h, 10 * d, 6 * h};
  for (std::size_t s = 0; s < 4; ++s) {
    double sum = 0;
    for (auto e = lat.set_offset[s]; e < lat.set_offset[s + 1]; ++e) sum += lat.set_length[e];
    EXPECT_NEAR(sum, len[s], 1e-9 * len[s]) << lat.set_names[s];
  }
  // Left edge x = 0 (across the rows): its set holds the even-row disks on it (distance 0)
  // and the odd-row disks whose full cells touch it (distance r).
  const int left = 3;
  int on_edge = 0, off_edge = 0;
  for (auto e = lat.set_offset[left]; e < lat.set_offset[left + 1]; ++e) {
    const double x = lat.x[lat.set_disk[e]];
    EXPECT_NEAR(lat.set_distance[e], x, 1e-9 * r);
    (x < 1e-12 ? on_edge : off_edge) += 1;
  }
  EXPECT_EQ(on_edge, 4);
  EXPECT_EQ(off_edge, 3);
  // The top set holds exactly the 11 semi-disks of the top row, normal +y.
  const int top = 2;
  EXPECT_EQ(lat.set_offset[top + 1] - lat.set_offset[top], 11);
  for (auto e = lat.set_offset[top]; e < lat.set_offset[top + 1]; ++e) {
    EXPECT_NEAR(lat.y[lat.set_disk[e]], 6 * h, 1e-12);
    EXPECT_NEAR(lat.set_ny[e], 1.0, 1e-9);
  }
}

TEST(LatticeGenerator, DiskExactCounts) {
  // A circle about a lattice point holds the hexagonal patches of 1 and 2 rings.
  const double r = 0.5;
  for (const auto& [R, disks, bonds] : {std::tuple{1.5 * 2 * r, 7u, 12u}, std::tuple{2.2 * 2 * r, 19u, 42u}}) {
    const Outline o = one_body({circle({0, 0}, R, 720)});
    const Lattice lat = generate(o, r);
    EXPECT_EQ(lat.num_disks(), disks);
    EXPECT_EQ(lat.num_bonds(), bonds);
    EXPECT_EQ(count_semi(lat), 0);
    const double polygon_area = 0.5 * 720 * R * R * std::sin(2 * kPi / 720);
    EXPECT_NEAR(cell_sum(lat), polygon_area, 1e-9 * polygon_area);
  }
}

TEST(LatticeGenerator, SquareWithSquareHoleExactCounts) {
  const double r = 1.0, d = 2 * r, h = kSqrt3 * r;
  const Outline o = one_body({rectangle(0, 0, 10 * d, 8 * h)}, {rectangle(3 * d, 2 * h, 7 * d, 6 * h)});
  const Lattice lat = generate(o, r);
  EXPECT_EQ(lat.num_disks(), 95u - 11u);
  EXPECT_EQ(count_semi(lat), 22 + 10);
  const double area = 10 * d * 8 * h - 4 * d * 4 * h;
  EXPECT_NEAR(cell_sum(lat), area, 1e-6 * area);

  // Independent bond count: all disk pairs at distance d whose midpoint is not inside the hole.
  std::size_t expected = 0;
  for (std::size_t a = 0; a < lat.num_disks(); ++a)
    for (std::size_t b = a + 1; b < lat.num_disks(); ++b) {
      if (std::abs(std::hypot(lat.x[a] - lat.x[b], lat.y[a] - lat.y[b]) - d) > 1e-9) continue;
      const double mx = 0.5 * (lat.x[a] + lat.x[b]), my = 0.5 * (lat.y[a] + lat.y[b]);
      const bool in_hole = mx > 3 * d + 1e-9 && mx < 7 * d - 1e-9 && my > 2 * h + 1e-9 && my < 6 * h - 1e-9;
      expected += !in_hole;
    }
  EXPECT_EQ(lat.num_bonds(), expected);
  check_bonds(lat);
}

TEST(LatticeGenerator, RhombusAlongLatticeLinesIsAllSemiDisksOnItsRim) {
  // Sides along 0 and 60 degrees: every edge is neat.
  const double r = 1.0, d = 2 * r;
  const Vec2 a1{6 * d, 0}, a2{6 * r, 6 * kSqrt3 * r};
  const Outline o = one_body({make_loop({{0, 0}, a1, {a1.x + a2.x, a2.y}, a2})});
  const Lattice lat = generate(o, r);
  EXPECT_EQ(lat.num_disks(), 49u);
  EXPECT_EQ(count_semi(lat), 24);
  EXPECT_EQ(lat.num_bonds(), 42u + 42u + 36u);
  const double area = 6 * d * 6 * kSqrt3 * r;
  EXPECT_NEAR(cell_sum(lat), area, 1e-6 * area);
}

TEST(LatticeGenerator, CircleOfRadius50rAreaWithinTolerance) {
  const double r = 1e-3, R = 50 * r;
  for (double angle : {0.0, 17.0, 60.0}) {
    const Outline o = one_body({circle({0.0123, -0.0071}, R, 2000)});
    GeneratorReport rep;
    const Lattice lat = generate(o, r, angle, {0.0003, 0.0002}, GeometryMode::Plane, &rep);
    const double exact = kPi * R * R;
    EXPECT_NEAR(cell_sum(lat), exact, 1e-3 * exact);
    EXPECT_NEAR(rep.cell_area_sum, rep.region_area, 1e-7 * exact);
    EXPECT_EQ(rep.lost_area, 0.0);
    EXPECT_NEAR(static_cast<double>(lat.num_disks()), exact / (2 * kSqrt3 * r * r), 0.02 * exact / (2 * kSqrt3 * r * r));
    check_bonds(lat, angle);
    const auto c = coordination(lat);
    for (std::size_t k = 0; k < lat.num_disks(); ++k) {
      if (std::hypot(lat.x[k] - 0.0123, lat.y[k] + 0.0071) < R - 2 * r) {
        EXPECT_EQ(c[k], 6);
      }
    }
  }
}

TEST(LatticeGenerator, PolygonWithHolesArea) {
  // A star-shaped 12-gon with three holes (a triangle, a circle, a skewed quad), rotated lattice.
  const double r = 0.5e-3;
  std::vector<Vec2> star;
  for (int k = 0; k < 12; ++k) {
    const double a = 2 * kPi * k / 12, R = (k % 2 ? 0.03 : 0.05);
    star.push_back({R * std::cos(a), R * std::sin(a)});
  }
  const Outline o = one_body({make_loop(star)},
                             {make_loop({{-0.01, -0.01}, {0.0, -0.012}, {-0.004, 0.0}}),
                              circle({0.012, 0.01}, 0.006, 400),
                              make_loop({{-0.02, 0.01}, {-0.012, 0.008}, {-0.01, 0.016}, {-0.021, 0.02}})});
  GeneratorReport rep;
  const Lattice lat = generate(o, r, 23.0, {}, GeometryMode::Plane, &rep);
  EXPECT_NEAR(cell_sum(lat), rep.region_area, 1e-6 * rep.region_area);
  EXPECT_LT(std::abs(rep.area_error()), 1e-3);
  check_bonds(lat, 23.0);
  // No bond crosses a hole: no bond midpoint lies inside the circular hole.
  for (std::size_t b = 0; b < lat.num_bonds(); ++b) {
    const double mx = 0.5 * (lat.x[lat.bond_i[b]] + lat.x[lat.bond_j[b]]);
    const double my = 0.5 * (lat.y[lat.bond_i[b]] + lat.y[lat.bond_j[b]]);
    EXPECT_GT(std::hypot(mx - 0.012, my - 0.01), 0.006 - 1e-9);
  }
}

TEST(LatticeGenerator, ArcBoundedShapeArea) {
  // A "D": a half-disc of radius 20r on a straight diameter, which is a neat edge.
  const double r = 1e-3, R = 20 * r;
  std::vector<Vec2> pts;
  const int n = 600;
  for (int k = 0; k <= n; ++k) {
    const double a = kPi * k / n;
    pts.push_back({R * std::cos(a), R * std::sin(a)});
  }
  Loop l = make_loop(pts, {}, false);
  l.edge_straight.back() = 1;  // the diameter from (-R, 0) back to (R, 0)
  const Outline o = one_body({l});
  const Lattice lat = generate(o, r);
  const double exact = 0.5 * kPi * R * R;
  EXPECT_NEAR(cell_sum(lat), exact, 1e-3 * exact);
  EXPECT_EQ(count_semi(lat), 21);  // the diameter row: x = -20r .. 20r in steps of 2r
}

TEST(LatticeGenerator, NarrowSlotIsNotBridged) {
  // A slot of width r cut into a rectangle: no bond may cross it.
  const double r = 1.0, d = 2 * r;
  const Outline o = one_body({make_loop({{0, 0}, {20 * d, 0}, {20 * d, 10 * d}, {10.25 * d, 10 * d},
                                         {10.25 * d, 2 * d}, {9.75 * d, 2 * d}, {9.75 * d, 10 * d},
                                         {0, 10 * d}})});
  const Lattice lat = generate(o, r, 0.0, {0.1, 0.0});
  for (std::size_t b = 0; b < lat.num_bonds(); ++b) {
    const double xa = lat.x[lat.bond_i[b]], xb = lat.x[lat.bond_j[b]];
    const double ya = lat.y[lat.bond_i[b]], yb = lat.y[lat.bond_j[b]];
    const bool crosses = std::min(xa, xb) < 9.75 * d && std::max(xa, xb) > 10.25 * d && std::min(ya, yb) > 2 * d;
    EXPECT_FALSE(crosses) << "bond across the slot at y " << ya;
  }
  GeneratorReport rep;
  generate(o, r, 0.0, {0.1, 0.0}, GeometryMode::Plane, &rep);
  EXPECT_NEAR(rep.cell_area_sum, rep.region_area, 1e-7 * rep.region_area);
}

TEST(LatticeGenerator, TwoBodiesAreFilledIndependently) {
  const double r = 1.0, d = 2 * r, h = kSqrt3 * r;
  Outline o = one_body({rectangle(0, 0, 10 * d, 6 * h)});
  BodyOutline b2;
  b2.name = "second";
  b2.where = "test body 2";
  b2.material = 7;
  b2.outers.push_back(rectangle(0, 10 * h, 10 * d, 16 * h));
  o.bodies.push_back(b2);
  const Lattice lat = generate(o, r);
  EXPECT_EQ(lat.num_disks(), 2u * 74u);
  EXPECT_EQ(lat.num_bonds(), 2u * 187u);
  for (std::size_t b = 0; b < lat.num_bonds(); ++b) EXPECT_EQ(lat.body[lat.bond_i[b]], lat.body[lat.bond_j[b]]);
  EXPECT_EQ(std::count(lat.material.begin(), lat.material.end(), 7), 74);
  ASSERT_EQ(lat.body_names.size(), 2u);
  EXPECT_EQ(lat.body_names[1], "second");
}

TEST(LatticeGenerator, BodiesWithTheirOwnRadius) {
  const double r = 1.0, d = 2 * r, h = kSqrt3 * r;
  Outline o = one_body({rectangle(0, 0, 10 * d, 6 * h)});
  o.bodies[0].radius = r;
  BodyOutline b2;
  b2.name = "fine";
  b2.where = "test body 2";
  b2.radius = r / 2;
  b2.outers.push_back(rectangle(0, 10 * h, 10 * d, 16 * h));
  o.bodies.push_back(b2);
  const Lattice lat = generate(o, 99.0);
  EXPECT_EQ(std::count(lat.radius.begin(), lat.radius.end(), r), 74);
  EXPECT_EQ(std::count(lat.radius.begin(), lat.radius.end(), r / 2), static_cast<long>(lat.num_disks()) - 74);
  check_bonds(lat);
}

TEST(LatticeGenerator, AxisymmetricWeightsAndBondRadius) {
  const double r = 1e-3;
  const Outline o = one_body({rectangle(0, 0, 20 * r, 30 * r)});
  const Lattice lat = generate(o, r, 0.0, {}, GeometryMode::Axisymmetric);
  ASSERT_EQ(lat.bond_b.size(), lat.num_bonds());
  for (std::size_t k = 0; k < lat.num_disks(); ++k) EXPECT_GT(lat.cell_cx[k], 0.0);
  for (std::size_t b = 0; b < lat.num_bonds(); ++b) {
    EXPECT_DOUBLE_EQ(lat.bond_b[b], 0.5 * (lat.x[lat.bond_i[b]] + lat.x[lat.bond_j[b]]));
  }
  // Disks centred on the axis have half cells whose centroid is off the axis.
  for (std::size_t k = 0; k < lat.num_disks(); ++k) {
    if (std::abs(lat.x[k]) < 1e-12 && lat.y[k] > r && lat.y[k] < 29 * r) {
      EXPECT_NEAR(lat.cell_area[k], kSqrt3 * r * r, 1e-6 * r * r);
      EXPECT_NEAR(lat.cell_cx[k], 4.0 * r / 9.0, 1e-6 * r);  // centroid of a half hexagon
    }
  }
}

TEST(LatticeGenerator, AxisymmetricRegionLeftOfAxisIsAnError) {
  const Outline o = one_body({rectangle(-0.01, 0, 0.02, 0.03)});
  EXPECT_THROW(generate(o, 1e-3, 0.0, {}, GeometryMode::Axisymmetric), hexdem::InputError);
}

TEST(LatticeGenerator, BadRadius) {
  const Outline o = one_body({rectangle(0, 0, 1, 1)});
  for (double r : {0.0, -1.0}) {
    try {
      generate(o, r);
      FAIL() << "no error for radius " << r;
    } catch (const hexdem::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("radius"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("test body"), std::string::npos) << e.what();
    }
  }
  try {
    generate(o, 2.0);
    FAIL() << "no error for a radius larger than the region";
  } catch (const hexdem::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too large"), std::string::npos) << e.what();
  }
}

}  // namespace
