// Tests of the irregular lattice ([mesh] jitter, meshing::jitter_lattice): which disks move
// and how far, the distribution of the moves against its closed form, the bonds' directions
// it spreads, and that the result depends on the seed and the sites only.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/meshing/lattice_jitter.hpp"
#include "hexdem/meshing/lattice_order.hpp"

namespace {

using namespace hexdem::meshing;

/// A 60 x 40 mm plate on a lattice turned by 17 degrees with a set on its bottom edge and a
/// round hole (every cell near it cut), r = 0.5 mm: about 3,000 disks.
Lattice plate(GeometryMode mode = GeometryMode::Plane) {
  Outline o;
  o.source = "test";
  o.boundary_names = {"bottom"};
  BodyOutline b;
  b.name = "plate";
  b.where = "test plate";
  b.radius = 0.5e-3;
  b.angle_deg = 17.0;
  Loop outer;
  outer.points = {{0.001, 0}, {0.061, 0}, {0.061, 0.04}, {0.001, 0.04}};
  outer.edge_set = {0, -1, -1, -1};
  outer.edge_straight.assign(4, 1);
  outer.where = "test loop";
  b.outers.push_back(outer);
  Loop hole;
  for (int k = 0; k < 48; ++k) {
    const double phi = -2 * std::numbers::pi * k / 48;  // clockwise
    hole.points.push_back({0.03 + 0.008 * std::cos(phi), 0.02 + 0.008 * std::sin(phi)});
  }
  hole.edge_set.assign(48, -1);
  hole.edge_straight.assign(48, 1);
  hole.where = "test hole";
  b.holes.push_back(hole);
  o.bodies.push_back(b);
  GeneratorOptions go;
  go.mode = mode;
  return generate_lattice(o, go);
}

std::vector<int> bond_counts(const Lattice& l) {
  std::vector<int> c(l.num_disks(), 0);
  for (std::size_t b = 0; b < l.num_bonds(); ++b) ++c[l.bond_i[b]], ++c[l.bond_j[b]];
  return c;
}

// Only interior disks move (full cell, six bonds, no set), each by at most fraction r; the
// cells move with them, and nothing else changes.
TEST(LatticeJitter, MovesOnlyInteriorDisksByAtMostTheFraction) {
  const Lattice regular = plate();
  Lattice l = plate();
  const double f = 0.25, r = 0.5e-3;
  const std::int64_t moved = jitter_lattice(l, f, 7);
  const std::vector<int> bonds = bond_counts(regular);
  std::vector<std::uint8_t> in_set(regular.num_disks(), 0);
  for (const std::int32_t d : regular.set_disk) in_set[d] = 1;
  std::int64_t interior = 0, moved_seen = 0;
  const double hexagon = 2 * std::sqrt(3.0) * r * r;
  for (std::size_t i = 0; i < l.num_disks(); ++i) {
    const double dx = l.x[i] - regular.x[i], dy = l.y[i] - regular.y[i];
    const bool is_interior = regular.kind[i] == 0 && bonds[i] == 6 && !in_set[i] &&
                             std::abs(regular.cell_area[i] - hexagon) <= 1e-9 * hexagon;
    interior += is_interior;
    if (!is_interior) {
      EXPECT_EQ(dx, 0.0) << i;
      EXPECT_EQ(dy, 0.0) << i;
    } else {
      moved_seen += dx != 0 || dy != 0;
      EXPECT_LE(std::hypot(dx, dy), f * r * (1 + 1e-12)) << i;
    }
    EXPECT_EQ(l.cell_cx[i] - regular.cell_cx[i], dx);
    EXPECT_EQ(l.cell_cy[i] - regular.cell_cy[i], dy);
    EXPECT_EQ(l.cell_area[i], regular.cell_area[i]);
    EXPECT_EQ(l.radius[i], regular.radius[i]);
  }
  EXPECT_EQ(moved, interior);
  EXPECT_EQ(moved_seen, interior);
  EXPECT_GT(interior, 2000);
  EXPECT_LT(interior, static_cast<std::int64_t>(l.num_disks()));  // the rim and the hole's cells stay
  EXPECT_EQ(l.bond_i, regular.bond_i);
  EXPECT_EQ(l.bond_j, regular.bond_j);
  EXPECT_EQ(l.set_disk, regular.set_disk);
}

// The moves are uniform over the disk of radius f r: |d|^2 / (f r)^2 is uniform on [0, 1)
// (mean 1/2, variance 1/12) and the direction uniform on the circle (the means of cos and sin
// of its angle, and of cos 2 and sin 2, are 0, each with standard deviation 1 / sqrt(2 N));
// the test allows 4.5 standard deviations of the mean of N moves.
TEST(LatticeJitter, MovesAreUniformOverTheDisk) {
  const Lattice regular = plate();
  Lattice l = plate();
  const double f = 0.3, r = 0.5e-3;
  jitter_lattice(l, f, 11);
  double s_q = 0, s_q2 = 0, s_c = 0, s_s = 0, s_c2 = 0, s_s2 = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < l.num_disks(); ++i) {
    const double dx = l.x[i] - regular.x[i], dy = l.y[i] - regular.y[i];
    if (dx == 0 && dy == 0) continue;
    const double q = (dx * dx + dy * dy) / (f * r * f * r), phi = std::atan2(dy, dx);
    s_q += q, s_q2 += q * q;
    s_c += std::cos(phi), s_s += std::sin(phi), s_c2 += std::cos(2 * phi), s_s2 += std::sin(2 * phi);
    ++n;
  }
  ASSERT_GT(n, 2000u);
  const double N = static_cast<double>(n);
  EXPECT_NEAR(s_q / N, 0.5, 4.5 * std::sqrt(1.0 / 12.0 / N));
  EXPECT_NEAR(s_q2 / N, 1.0 / 3.0, 4.5 * std::sqrt((1.0 / 5.0 - 1.0 / 9.0) / N));  // E q^2 = 1/3
  for (const double s : {s_c, s_s, s_c2, s_s2}) EXPECT_NEAR(s / N, 0.0, 4.5 / std::sqrt(2 * N));
}

// The bonds' directions spread around the lattice's three; no two disks come closer than the
// bound of kMaxJitter: bonded 2 r (1 - f), unbonded 2 r (checked against every pair).
TEST(LatticeJitter, BondDirectionsSpreadAndNoDisksOverlap) {
  const double f = kMaxJitter, r = 0.5e-3;
  Lattice l = plate();
  jitter_lattice(l, f, 3);
  std::set<std::pair<std::int32_t, std::int32_t>> bonded;
  double min_bonded = 1e9, max_turn = 0;
  const double axis = 17.0 * std::numbers::pi / 180;
  for (std::size_t b = 0; b < l.num_bonds(); ++b) {
    const auto i = l.bond_i[b], j = l.bond_j[b];
    bonded.insert({std::min(i, j), std::max(i, j)});
    const double dx = l.x[j] - l.x[i], dy = l.y[j] - l.y[i];
    min_bonded = std::min(min_bonded, std::hypot(dx, dy));
    // The angle from the nearest lattice direction (modulo 60 degrees).
    double a = std::fmod(std::atan2(dy, dx) - axis + 4 * std::numbers::pi, std::numbers::pi / 3);
    a = std::min(a, std::numbers::pi / 3 - a);
    max_turn = std::max(max_turn, a);
  }
  EXPECT_GE(min_bonded, 2 * r * (1 - f) * (1 - 1e-12));
  // Two ends moved by up to 0.3 r each across a 2 r bond: up to about 17 degrees; a few
  // thousand bonds reach well past half of that.
  EXPECT_GT(max_turn * 180 / std::numbers::pi, 10.0);
  EXPECT_LT(max_turn * 180 / std::numbers::pi, 17.5);
  double min_free = 1e9;
  for (std::size_t i = 0; i < l.num_disks(); ++i)
    for (std::size_t j = i + 1; j < l.num_disks(); ++j) {
      if (bonded.count({static_cast<std::int32_t>(i), static_cast<std::int32_t>(j)})) continue;
      const double d = std::hypot(l.x[j] - l.x[i], l.y[j] - l.y[i]);
      if (d < min_free) min_free = d;
    }
  EXPECT_GT(min_free, 2 * r);
}

// The same seed gives the same lattice in any disk order; another seed another one; 0 leaves
// the lattice as generated; axisymmetric bonds get their ring radius from the moved disks.
TEST(LatticeJitter, DependsOnTheSeedAndTheSitesOnly) {
  const Lattice regular = plate();
  Lattice a = plate(), b = plate(), c = plate(), zero = plate();
  jitter_lattice(a, 0.2, 5);
  jitter_lattice(b, 0.2, 5);
  jitter_lattice(c, 0.2, 6);
  EXPECT_EQ(jitter_lattice(zero, 0.0, 5), 0);
  EXPECT_EQ(zero.x, regular.x);
  EXPECT_EQ(zero.y, regular.y);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_NE(a.x, c.x);
  // Hilbert order first, then the jitter: the same positions, renumbered.
  Lattice h = plate();
  apply_disk_order(h, DiskOrder::Hilbert);
  jitter_lattice(h, 0.2, 5);
  std::multiset<std::pair<double, double>> pa, ph;
  for (std::size_t i = 0; i < a.num_disks(); ++i) pa.insert({a.x[i], a.y[i]});
  for (std::size_t i = 0; i < h.num_disks(); ++i) ph.insert({h.x[i], h.y[i]});
  EXPECT_TRUE(pa == ph);

  Lattice ax = plate(GeometryMode::Axisymmetric);
  jitter_lattice(ax, 0.2, 5);
  ASSERT_EQ(ax.bond_b.size(), ax.num_bonds());
  for (std::size_t k = 0; k < ax.num_bonds(); ++k)
    EXPECT_DOUBLE_EQ(ax.bond_b[k], 0.5 * (ax.x[ax.bond_i[k]] + ax.x[ax.bond_j[k]])) << k;
}

// Contact radii ([contact] radius_spread): the interior disks' spread uniformly over
// r (1 +- s) (mean and variance of u = (rc / r - 1) / s against those of the uniform law on
// [-1, 1): 0 and 1/3, within 4.5 standard deviations of the mean of N), every other disk keeps
// r; the draw depends on the seed and the positions only, not on the jitter's own draw; and at
// the largest jitter and spread no two unbonded disks overlap (every pair).
TEST(ContactRadii, SpreadOnlyTheInteriorDisksUniformly) {
  const double f = kMaxJitter, s = kMaxRadiusSpread, r = 0.5e-3;
  Lattice l = plate();
  EXPECT_TRUE(contact_radii(l, 0.0, 3).empty());
  jitter_lattice(l, f, 3);
  const std::vector<std::uint8_t> interior = interior_disks(l);
  const std::vector<double> rc = contact_radii(l, s, 3);
  ASSERT_EQ(rc.size(), l.num_disks());
  double s_u = 0, s_u2 = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < l.num_disks(); ++i) {
    if (!interior[i]) {
      EXPECT_EQ(rc[i], l.radius[i]) << i;
      continue;
    }
    const double u = (rc[i] / r - 1) / s;
    EXPECT_GE(u, -1.0 - 1e-12) << i;
    EXPECT_LT(u, 1.0 + 1e-12) << i;
    s_u += u, s_u2 += u * u;
    ++n;
  }
  ASSERT_GT(n, 2000u);
  const double N = static_cast<double>(n);
  EXPECT_NEAR(s_u / N, 0.0, 4.5 * std::sqrt(1.0 / 3.0 / N));
  EXPECT_NEAR(s_u2 / N, 1.0 / 3.0, 4.5 * std::sqrt((1.0 / 5.0 - 1.0 / 9.0) / N));  // E u^4 = 1/5
  // Independent of the jitter's draw with the same seed: no correlation of u with |move|^2.
  const Lattice regular = plate();
  double s_uq = 0;
  for (std::size_t i = 0; i < l.num_disks(); ++i) {
    if (!interior[i]) continue;
    const double q = (std::pow(l.x[i] - regular.x[i], 2) + std::pow(l.y[i] - regular.y[i], 2)) / (f * r * f * r);
    s_uq += (rc[i] / r - 1) / s * (q - 0.5);
  }
  EXPECT_NEAR(s_uq / N, 0.0, 4.5 * std::sqrt(1.0 / 3.0 / 12.0 / N));
  // No overlap between unbonded disks at their contact radii.
  std::set<std::pair<std::int32_t, std::int32_t>> bonded;
  for (std::size_t b = 0; b < l.num_bonds(); ++b)
    bonded.insert({std::min(l.bond_i[b], l.bond_j[b]), std::max(l.bond_i[b], l.bond_j[b])});
  double min_gap = 1e9;
  for (std::size_t i = 0; i < l.num_disks(); ++i)
    for (std::size_t j = i + 1; j < l.num_disks(); ++j) {
      if (bonded.count({static_cast<std::int32_t>(i), static_cast<std::int32_t>(j)})) continue;
      min_gap = std::min(min_gap, std::hypot(l.x[j] - l.x[i], l.y[j] - l.y[i]) - rc[i] - rc[j]);
    }
  EXPECT_GE(min_gap, 0.0);
}

// The same seed gives the same radius to the same disk in any disk order; another seed others.
TEST(ContactRadii, DependOnTheSeedAndThePositionsOnly) {
  Lattice a = plate(), h = plate();
  apply_disk_order(h, DiskOrder::Hilbert);
  jitter_lattice(a, 0.2, 5);
  jitter_lattice(h, 0.2, 5);
  const std::vector<double> ra = contact_radii(a, 0.1, 5), rh = contact_radii(h, 0.1, 5), r6 = contact_radii(a, 0.1, 6);
  std::multiset<std::tuple<double, double, double>> pa, ph;
  for (std::size_t i = 0; i < a.num_disks(); ++i) pa.insert({a.x[i], a.y[i], ra[i]});
  for (std::size_t i = 0; i < h.num_disks(); ++i) ph.insert({h.x[i], h.y[i], rh[i]});
  EXPECT_TRUE(pa == ph);
  EXPECT_NE(ra, r6);
}

}  // namespace
