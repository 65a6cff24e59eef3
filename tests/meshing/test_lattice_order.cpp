// Tests of the disk order ([mesh] order): the Hilbert index against the curve's defining
// properties, and a renumbered lattice against the generator's (the same disks, bonds and
// boundary sets, only numbered differently).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/meshing/lattice_order.hpp"

namespace {

using namespace hexdem::meshing;

// The first 4^k indices fill the k-th lower-left square [0, 2^k)^2 (its quadrant code is 0 at
// every level), each cell once, and consecutive indices are edge neighbours: a Hilbert curve.
TEST(LatticeOrder, HilbertIndexIsAContinuousCurveThroughEveryCell) {
  constexpr std::uint32_t side = 64;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cell_of(side * side, {UINT32_MAX, UINT32_MAX});
  for (std::uint32_t ix = 0; ix < side; ++ix)
    for (std::uint32_t iy = 0; iy < side; ++iy) {
      const std::uint64_t d = hilbert_index(ix, iy);
      ASSERT_LT(d, side * side) << "(" << ix << ", " << iy << ")";
      ASSERT_EQ(cell_of[d].first, UINT32_MAX) << "index " << d << " taken twice";
      cell_of[d] = {ix, iy};
    }
  for (std::size_t d = 1; d < cell_of.size(); ++d) {
    const auto [x0, y0] = cell_of[d - 1];
    const auto [x1, y1] = cell_of[d];
    const std::uint32_t step = (x0 > x1 ? x0 - x1 : x1 - x0) + (y0 > y1 ? y0 - y1 : y1 - y0);
    ASSERT_EQ(step, 1u) << "indices " << d - 1 << " and " << d;
  }
  // The whole grid: its corners are the curve's ends and the last cell of the first quadrant.
  EXPECT_EQ(hilbert_index(0, 0), 0u);
  EXPECT_EQ(hilbert_index(65535, 0), (std::uint64_t{1} << 32) - 1);
  EXPECT_EQ(hilbert_index(0, 32767), (std::uint64_t{1} << 30) - 1);
}

Loop rectangle(double x0, double y0, double x1, double y1, std::vector<std::int32_t> sets) {
  Loop l;
  l.points = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  l.edge_set = std::move(sets);
  l.edge_straight.assign(4, 1);
  l.where = "test loop";
  return l;
}

/// Two bodies: a plate with a square hole (sets on its bottom, top and the hole) on a lattice
/// turned by 17 degrees, and a small block above it.
Lattice two_bodies() {
  Outline o;
  o.source = "test";
  o.boundary_names = {"bottom", "top", "hole"};
  BodyOutline plate;
  plate.name = "plate";
  plate.where = "test plate";
  plate.radius = 0.5e-3;
  plate.angle_deg = 17.0;
  plate.outers.push_back(rectangle(0, 0, 0.06, 0.03, {0, -1, 1, -1}));
  Loop hole = rectangle(0.02, 0.01, 0.03, 0.02, {2, 2, 2, 2});
  std::reverse(hole.points.begin(), hole.points.end());  // clockwise; all its edges are set 2
  plate.holes.push_back(hole);
  o.bodies.push_back(plate);
  BodyOutline block;
  block.name = "block";
  block.where = "test block";
  block.radius = 0.4e-3;
  block.outers.push_back(rectangle(0.01, 0.032, 0.02, 0.04, {-1, -1, -1, -1}));
  o.bodies.push_back(block);
  return generate_lattice(o, GeneratorOptions{});
}

using DiskKey = std::tuple<double, double, double, double, int, int, int>;
DiskKey disk_key(const Lattice& l, std::size_t k) {
  return {l.x[k], l.y[k], l.radius[k], l.cell_area[k], l.kind[k], l.body[k], l.material[k]};
}
using BondKey = std::tuple<double, double, double, double, int, int>;
BondKey bond_key(const Lattice& l, std::size_t b) {
  auto i = static_cast<std::size_t>(l.bond_i[b]), j = static_cast<std::size_t>(l.bond_j[b]);
  if (std::make_pair(l.x[j], l.y[j]) < std::make_pair(l.x[i], l.y[i])) std::swap(i, j);
  return {l.x[i], l.y[i], l.x[j], l.y[j], l.bond_class[b], l.bond_on_edge[b]};
}
using SetKey = std::tuple<std::size_t, double, double, double, double, double, double>;
std::multiset<SetKey> set_keys(const Lattice& l) {
  std::multiset<SetKey> out;
  for (std::size_t s = 0; s < l.num_sets(); ++s)
    for (auto k = l.set_offset[s]; k < l.set_offset[s + 1]; ++k) {
      const auto e = static_cast<std::size_t>(k);
      const auto d = static_cast<std::size_t>(l.set_disk[e]);
      out.insert({s, l.x[d], l.y[d], l.set_length[e], l.set_nx[e], l.set_distance[e], l.set_cx[e]});
    }
  return out;
}

TEST(LatticeOrder, HilbertRenumberingKeepsDisksBondsAndSets) {
  const Lattice rows = two_bodies();
  Lattice hilbert = two_bodies();
  apply_disk_order(hilbert, DiskOrder::Hilbert);
  ASSERT_EQ(hilbert.num_disks(), rows.num_disks());
  ASSERT_EQ(hilbert.num_bonds(), rows.num_bonds());
  ASSERT_GT(rows.num_disks(), 1000u);

  // The order did change, and the bodies stay contiguous and in order.
  std::size_t moved = 0;
  for (std::size_t k = 0; k < rows.num_disks(); ++k) moved += rows.x[k] != hilbert.x[k] || rows.y[k] != hilbert.y[k];
  EXPECT_GT(moved, rows.num_disks() / 2);
  EXPECT_TRUE(std::is_sorted(hilbert.body.begin(), hilbert.body.end()));

  // The same disks (position, radius, cell, kind, body, material).
  std::multiset<DiskKey> a, b;
  for (std::size_t k = 0; k < rows.num_disks(); ++k) a.insert(disk_key(rows, k));
  for (std::size_t k = 0; k < hilbert.num_disks(); ++k) b.insert(disk_key(hilbert, k));
  EXPECT_TRUE(a == b);

  // The same bonds between the same disks, with i < j, sorted by (i, j).
  std::multiset<BondKey> ba, bb;
  for (std::size_t k = 0; k < rows.num_bonds(); ++k) ba.insert(bond_key(rows, k));
  for (std::size_t k = 0; k < hilbert.num_bonds(); ++k) {
    bb.insert(bond_key(hilbert, k));
    ASSERT_LT(hilbert.bond_i[k], hilbert.bond_j[k]);
    if (k > 0) {
      ASSERT_TRUE(std::make_pair(hilbert.bond_i[k - 1], hilbert.bond_j[k - 1]) <
                  std::make_pair(hilbert.bond_i[k], hilbert.bond_j[k]));
    }
  }
  EXPECT_TRUE(ba == bb);

  // The same set entries, ascending by disk within each set.
  EXPECT_EQ(hilbert.set_offset, rows.set_offset);
  EXPECT_TRUE(set_keys(rows) == set_keys(hilbert));
  for (std::size_t s = 0; s < hilbert.num_sets(); ++s) {
    const auto first = hilbert.set_disk.begin() + hilbert.set_offset[s];
    const auto last = hilbert.set_disk.begin() + hilbert.set_offset[s + 1];
    EXPECT_GT(last - first, 10);
    EXPECT_TRUE(std::is_sorted(first, last)) << hilbert.set_names[s];
  }

  // Locality: consecutive disks of the curve are close (the mean gap is about one spacing,
  // a Hilbert curve jumps only at the region's edges), where the rows jump a row's width.
  const auto mean_gap = [](const Lattice& l) {
    double sum = 0;
    for (std::size_t k = 1; k < l.num_disks(); ++k) sum += std::hypot(l.x[k] - l.x[k - 1], l.y[k] - l.y[k - 1]);
    return sum / static_cast<double>(l.num_disks() - 1);
  };
  std::printf("mean distance of consecutive disks: rows %.3g m, Hilbert %.3g m\n", mean_gap(rows), mean_gap(hilbert));
  EXPECT_LT(mean_gap(hilbert), 2.0 * 1e-3);
}

TEST(LatticeOrder, RenumberRefusesWhatIsNotAPermutation) {
  Lattice l = two_bodies();
  std::vector<std::int32_t> p(l.num_disks(), 0);
  EXPECT_THROW(renumber_disks(l, p), std::exception);
  p.resize(3);
  EXPECT_THROW(renumber_disks(l, p), std::exception);
}

}  // namespace
