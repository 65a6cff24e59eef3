#include "hexdem/meshing/lattice_order.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <type_traits>
#include <utility>

#include "hexdem/error.hpp"

namespace hexdem::meshing {

namespace {

constexpr std::uint32_t kGrid = 1u << 16;  // cells per side of the Hilbert grid

/// `out[new] = v[old]` for every old index.
template <typename T>
void permute(std::vector<T>& v, const std::vector<std::int32_t>& new_of_old) {
  if (v.empty()) return;
  std::vector<T> out(v.size());
  for (std::size_t old = 0; old < v.size(); ++old) out[static_cast<std::size_t>(new_of_old[old])] = std::move(v[old]);
  v = std::move(out);
}

}  // namespace

std::uint64_t hilbert_index(std::uint32_t ix, std::uint32_t iy) {
  HEXDEM_VERIFY(ix < kGrid && iy < kGrid, "hilbert_index: cell outside the 2^16 grid");
  std::uint64_t d = 0;
  for (std::uint32_t s = kGrid / 2; s > 0; s /= 2) {
    const std::uint32_t rx = (ix & s) != 0 ? 1 : 0, ry = (iy & s) != 0 ? 1 : 0;
    d += static_cast<std::uint64_t>(s) * s * ((3 * rx) ^ ry);
    // Rotate the quadrant so that the curve inside it starts and ends where its neighbours meet.
    if (ry == 0) {
      if (rx == 1) {
        ix = kGrid - 1 - ix;
        iy = kGrid - 1 - iy;
      }
      std::swap(ix, iy);
    }
  }
  return d;
}

std::vector<std::int32_t> hilbert_permutation(const Lattice& lat) {
  const std::size_t n = lat.num_disks();
  std::vector<std::int32_t> new_of_old(n);
  if (n == 0) return new_of_old;
  const auto [xmin, xmax] = std::minmax_element(lat.x.begin(), lat.x.end());
  const auto [ymin, ymax] = std::minmax_element(lat.y.begin(), lat.y.end());
  // One square grid over the bounding box; its cells are much smaller than a disk for up to
  // about 4e9 disks in a square, so that no two disks share a cell.
  const double span = std::max({*xmax - *xmin, *ymax - *ymin, 1e-300});
  const double cell = span / (kGrid - 1);
  struct Key { std::int32_t body; std::uint64_t h; std::int32_t old; };
  std::vector<Key> keys(n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto ix = static_cast<std::uint32_t>(std::lround((lat.x[k] - *xmin) / cell));
    const auto iy = static_cast<std::uint32_t>(std::lround((lat.y[k] - *ymin) / cell));
    keys[k] = {lat.body[k], hilbert_index(ix, iy), static_cast<std::int32_t>(k)};
  }
  // Ties (two disks in one cell) keep the generator's order, so the result is deterministic.
  std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
    if (a.body != b.body) return a.body < b.body;
    if (a.h != b.h) return a.h < b.h;
    return a.old < b.old;
  });
  for (std::size_t k = 0; k < n; ++k) new_of_old[static_cast<std::size_t>(keys[k].old)] = static_cast<std::int32_t>(k);
  return new_of_old;
}

void renumber_disks(Lattice& lat, const std::vector<std::int32_t>& new_of_old) {
  const std::size_t n = lat.num_disks();
  HEXDEM_VERIFY(new_of_old.size() == n, "renumber_disks: one new index per disk");
  {
    std::vector<std::uint8_t> seen(n, 0);
    for (const std::int32_t k : new_of_old) {
      HEXDEM_VERIFY(k >= 0 && static_cast<std::size_t>(k) < n && seen[static_cast<std::size_t>(k)] == 0,
                    "renumber_disks: new_of_old is not a permutation");
      seen[static_cast<std::size_t>(k)] = 1;
    }
  }
  permute(lat.x, new_of_old);
  permute(lat.y, new_of_old);
  permute(lat.radius, new_of_old);
  permute(lat.cell_area, new_of_old);
  permute(lat.cell_cx, new_of_old);
  permute(lat.cell_cy, new_of_old);
  permute(lat.kind, new_of_old);
  permute(lat.body, new_of_old);
  permute(lat.material, new_of_old);

  // Bonds: renumbered ends with i < j, sorted by (i, j) so the bond loop walks the disks in order.
  const std::size_t nb = lat.num_bonds();
  std::vector<std::int32_t> bond_of_rank(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    std::int32_t i = new_of_old[static_cast<std::size_t>(lat.bond_i[b])];
    std::int32_t j = new_of_old[static_cast<std::size_t>(lat.bond_j[b])];
    if (j < i) std::swap(i, j);
    lat.bond_i[b] = i;
    lat.bond_j[b] = j;
  }
  std::iota(bond_of_rank.begin(), bond_of_rank.end(), 0);
  std::sort(bond_of_rank.begin(), bond_of_rank.end(), [&](std::int32_t a, std::int32_t b) {
    const auto ua = static_cast<std::size_t>(a), ub = static_cast<std::size_t>(b);
    return lat.bond_i[ua] != lat.bond_i[ub] ? lat.bond_i[ua] < lat.bond_i[ub] : lat.bond_j[ua] < lat.bond_j[ub];
  });
  std::vector<std::int32_t> rank_of_bond(nb);
  for (std::size_t r = 0; r < nb; ++r) rank_of_bond[static_cast<std::size_t>(bond_of_rank[r])] = static_cast<std::int32_t>(r);
  permute(lat.bond_i, rank_of_bond);
  permute(lat.bond_j, rank_of_bond);
  permute(lat.bond_class, rank_of_bond);
  permute(lat.bond_on_edge, rank_of_bond);
  permute(lat.bond_b, rank_of_bond);

  // Boundary sets: each set's entries renumbered and put back in ascending disk order.
  for (std::size_t s = 0; s < lat.num_sets(); ++s) {
    const auto begin = static_cast<std::size_t>(lat.set_offset[s]), end = static_cast<std::size_t>(lat.set_offset[s + 1]);
    std::vector<std::size_t> order(end - begin);
    std::iota(order.begin(), order.end(), begin);
    for (std::size_t k = begin; k < end; ++k) lat.set_disk[k] = new_of_old[static_cast<std::size_t>(lat.set_disk[k])];
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return lat.set_disk[a] < lat.set_disk[b]; });
    const auto reorder = [&](auto& v) {
      using T = typename std::decay_t<decltype(v)>::value_type;
      const std::vector<T> copy(v.begin() + static_cast<std::ptrdiff_t>(begin), v.begin() + static_cast<std::ptrdiff_t>(end));
      for (std::size_t k = 0; k < order.size(); ++k) v[begin + k] = copy[order[k] - begin];
    };
    reorder(lat.set_disk);
    reorder(lat.set_length);
    reorder(lat.set_nx);
    reorder(lat.set_ny);
    reorder(lat.set_cx);
    reorder(lat.set_cy);
    reorder(lat.set_distance);
  }
}

void apply_disk_order(Lattice& lat, DiskOrder order) {
  if (order == DiskOrder::Rows) return;
  renumber_disks(lat, hilbert_permutation(lat));
}

}  // namespace hexdem::meshing
