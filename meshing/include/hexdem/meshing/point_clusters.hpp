// Clusters of nearby points: union-find over the pairs that a hash grid brings together.
//
// Used where nearby things must be grouped in O(n): the ends of a DXF drawing's pieces that
// meet within the tolerance (outline_dxf.cpp), and the separate parts of a boundary set, such as
// a beam's two supports (solver/src/boundaries.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <unordered_map>
#include <vector>

namespace hexdem::meshing {

/// Union-find with path halving; the smaller index becomes the root.
struct DisjointSets {
  std::vector<std::size_t> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t{0}); }
  std::size_t find(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

/// Groups the points 0..n-1 (point(k) has members .x and .y [any length unit]): k and j are in
/// one cluster when linked(k, j) holds, or through a chain of such pairs. Only pairs whose cells
/// of side `cell` touch are tried, so linked(k, j) must imply that the two points lie within
/// `cell` of each other. Returns each point's cluster, numbered from 0 in order of first
/// appearance; `clusters` receives their number.
template <class Point, class Linked>
std::vector<std::size_t> cluster_points(std::size_t n, Point point, double cell, Linked linked,
                                        std::size_t& clusters) {
  DisjointSets sets(n);
  if (n > 0) {
    double xmin = HUGE_VAL, ymin = HUGE_VAL;
    for (std::size_t k = 0; k < n; ++k) {
      xmin = std::min(xmin, static_cast<double>(point(k).x));
      ymin = std::min(ymin, static_cast<double>(point(k).y));
    }
    const auto cell_index = [&](double v, double v0) {
      return static_cast<std::int64_t>(std::floor(std::min((v - v0) / cell, 1e15)));
    };
    const auto key = [](std::int64_t i, std::int64_t j) {
      return static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ULL ^ static_cast<std::uint64_t>(j);
    };
    std::unordered_map<std::uint64_t, std::vector<std::size_t>> grid;
    grid.reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::int64_t i = cell_index(point(k).x, xmin), j = cell_index(point(k).y, ymin);
      for (std::int64_t di = -1; di <= 1; ++di)
        for (std::int64_t dj = -1; dj <= 1; ++dj) {
          const auto it = grid.find(key(i + di, j + dj));
          if (it == grid.end()) continue;
          for (const std::size_t other : it->second)
            if (linked(k, other)) sets.unite(k, other);
        }
      grid[key(i, j)].push_back(k);
    }
  }
  std::vector<std::size_t> cluster(n);
  std::unordered_map<std::size_t, std::size_t> of_root;
  for (std::size_t k = 0; k < n; ++k) cluster[k] = of_root.try_emplace(sets.find(k), of_root.size()).first->second;
  clusters = of_root.size();
  return cluster;
}

}  // namespace hexdem::meshing
