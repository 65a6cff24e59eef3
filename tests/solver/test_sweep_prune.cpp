// Contact broad phase (sweep and prune): the candidate list must equal a brute-force test of
// all pairs of stored boxes (closed intervals), the stored boxes must follow the margin rule
// of sweep_prune.hpp, and every pair of disks whose current boxes overlap must be listed.
// Checked on thousands of random configurations and move sequences, on both the incremental
// and the from-scratch paths.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "hexdem/solver/sweep_prune.hpp"

namespace hexdem::solver {
namespace {

using Pair = SweepPrune::Pair;
using PairList = std::vector<Pair>;

struct Disks {
  std::vector<double> x, y, r;
  [[nodiscard]] std::size_t size() const { return x.size(); }
  void push(double xi, double yi, double ri) {
    x.push_back(xi);
    y.push_back(yi);
    r.push_back(ri);
  }
};

/// Independent model of the stored boxes: the margin rule of sweep_prune.hpp, written out.
struct Model {
  double h = 0;
  std::vector<double> rx, ry, rr;
  std::vector<SweepBox> boxes;

  void set(std::size_t i, double x, double y, double r) {
    rx[i] = x;
    ry[i] = y;
    rr[i] = r;
    const double w = r + h;
    boxes[i] = {x - w, x + w, y - w, y + w};
  }
  void build(const Disks& d, double margin) {
    h = 0.5 * margin;
    const std::size_t n = d.size();
    rx.assign(n, 0);
    ry.assign(n, 0);
    rr.assign(n, 0);
    boxes.assign(n, {});
    for (std::size_t i = 0; i < n; ++i) set(i, d.x[i], d.y[i], d.r[i]);
  }
  void update(const Disks& d) {
    for (std::size_t i = 0; i < d.size(); ++i) {
      const double dx = d.x[i] - rx[i], dy = d.y[i] - ry[i];
      const bool moved = dx * dx + dy * dy > h * h || d.r[i] != rr[i];
      const bool finite = std::isfinite(d.x[i]) && std::isfinite(d.y[i]) && std::isfinite(d.r[i]);
      if (moved && finite) set(i, d.x[i], d.y[i], d.r[i]);
    }
  }
};

bool closed_overlap(const SweepBox& a, const SweepBox& b) {
  return a.lo_x <= b.hi_x && b.lo_x <= a.hi_x && a.lo_y <= b.hi_y && b.lo_y <= a.hi_y;
}

PairList brute_force(const std::vector<SweepBox>& boxes, const std::set<Pair>& excluded) {
  PairList out;
  const auto n = static_cast<std::int32_t>(boxes.size());
  for (std::int32_t i = 0; i < n; ++i) {
    for (std::int32_t j = i + 1; j < n; ++j) {
      if (closed_overlap(boxes[i], boxes[j]) && excluded.count({i, j}) == 0) out.push_back({i, j});
    }
  }
  return out;
}

/// Symmetric excluded set -> CSR with each pair in one row only (the class symmetrises).
struct Csr {
  std::vector<std::int32_t> offsets, neighbours;
};
Csr to_csr(const std::set<Pair>& excluded, std::size_t n, std::mt19937_64& rng) {
  std::vector<std::vector<std::int32_t>> rows(n);
  for (const auto& [i, j] : excluded) {
    if (rng() % 2) {
      rows[i].push_back(j);
    } else {
      rows[j].push_back(i);
    }
    if (rng() % 8 == 0) rows[i].push_back(j);  // duplicates are allowed
  }
  Csr c;
  c.offsets.push_back(0);
  for (auto& row : rows) {
    std::shuffle(row.begin(), row.end(), rng);  // rows need not be sorted
    c.neighbours.insert(c.neighbours.end(), row.begin(), row.end());
    c.offsets.push_back(static_cast<std::int32_t>(c.neighbours.size()));
  }
  return c;
}

/// Everything the class promises about its current state.
void expect_consistent(const SweepPrune& sp, const Model& model, const Disks& d,
                       const std::set<Pair>& excluded) {
  const std::size_t n = d.size();
  ASSERT_EQ(sp.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    const SweepBox b = sp.box(static_cast<std::int32_t>(i));
    const SweepBox& m = model.boxes[i];
    ASSERT_TRUE(b.lo_x == m.lo_x && b.hi_x == m.hi_x && b.lo_y == m.lo_y && b.hi_y == m.hi_y)
        << "box of disk " << i;
  }
  const PairList& got = sp.pairs();
  for (std::size_t k = 0; k < got.size(); ++k) {
    ASSERT_LT(got[k].first, got[k].second);
    if (k > 0) {
      ASSERT_LT(got[k - 1], got[k]) << "order at " << k;
    }
  }
  const PairList want = brute_force(model.boxes, excluded);
  ASSERT_EQ(got.size(), want.size());
  ASSERT_EQ(got, want);

  // Disks whose current boxes overlap (by more than rounding) are candidates.
  double scale = 1;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isfinite(d.x[i]) && std::isfinite(d.y[i]) && std::isfinite(d.r[i])) {
      scale = std::max({scale, std::abs(d.x[i]) + d.r[i], std::abs(d.y[i]) + d.r[i]});
    }
  }
  const double tol = 1e-12 * scale;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const double gx = std::abs(d.x[i] - d.x[j]) - (d.r[i] + d.r[j]);
      const double gy = std::abs(d.y[i] - d.y[j]) - (d.r[i] + d.r[j]);
      if (gx < -tol && gy < -tol) {
        const Pair p{static_cast<std::int32_t>(i), static_cast<std::int32_t>(j)};
        if (excluded.count(p) == 0) {
          ASSERT_TRUE(std::binary_search(got.begin(), got.end(), p))
              << "touching disks " << i << ", " << j << " not listed";
        }
      }
    }
  }
}

enum class Layout {
  Uniform,
  Clustered,
  SquareTouching,
  Hexagonal,
  Duplicated,
  MixedRadii,
  Integer
};
constexpr Layout kLayouts[] = {Layout::Uniform,   Layout::Clustered,  Layout::SquareTouching,
                               Layout::Hexagonal, Layout::Duplicated, Layout::MixedRadii,
                               Layout::Integer};

struct Scene {
  Disks disks;
  double margin = 0;
  double step = 0;    ///< typical small move [m]
  bool grid = false;  ///< moves stay on a dyadic grid (exact ties)
};

Scene make_scene(Layout layout, std::size_t n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  Scene s;
  Disks& d = s.disks;
  switch (layout) {
    case Layout::Uniform: {
      const double L = 2.5 * std::sqrt(static_cast<double>(n));
      for (std::size_t i = 0; i < n; ++i) d.push(L * u(rng), L * u(rng), 0.5 + 0.5 * u(rng));
      s.margin = 0.3 * u(rng);
      s.step = 0.15;
      break;
    }
    case Layout::Clustered: {
      std::normal_distribution<double> g(0, 1);
      const std::size_t clusters = 1 + rng() % 4;
      std::vector<std::pair<double, double>> c(clusters);
      for (auto& p : c) p = {50 * u(rng), 50 * u(rng)};
      const double spread = 0.5 + 4 * u(rng);
      for (std::size_t i = 0; i < n; ++i) {
        const auto& p = c[rng() % clusters];
        d.push(p.first + spread * g(rng), p.second + spread * g(rng), 0.1 + 0.2 * u(rng));
      }
      s.margin = 0.1 * u(rng);
      s.step = 0.05;
      break;
    }
    case Layout::SquareTouching: {
      // r = 0.5, margin 0.5: boxes of half-width 0.75 on a 1.5 grid touch exactly.
      const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
      for (std::size_t i = 0; i < n; ++i) d.push(1.5 * (i % side), 1.5 * (i / side), 0.5);
      s.margin = 0.5;
      s.step = 0.25;
      s.grid = true;
      break;
    }
    case Layout::Hexagonal: {
      const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
      const double r = 1e-3;
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t row = i / side, col = i % side;
        d.push(2 * r * col + (row % 2) * r, std::sqrt(3.0) * r * row, r);
      }
      s.margin = 0.2 * r * u(rng);
      s.step = 0.1 * r;
      break;
    }
    case Layout::Duplicated: {
      const std::size_t sites = 1 + rng() % (n / 4 + 1);
      std::vector<std::pair<double, double>> p(sites);
      for (auto& q : p) q = {static_cast<double>(rng() % 16), static_cast<double>(rng() % 16)};
      for (std::size_t i = 0; i < n; ++i) {
        const auto& q = p[rng() % sites];
        d.push(q.first, q.second, 0.75);
      }
      s.margin = 0.5 * static_cast<double>(rng() % 3);
      s.step = 0.5;
      s.grid = true;
      break;
    }
    case Layout::MixedRadii: {
      const double L = 3 * std::sqrt(static_cast<double>(n));
      for (std::size_t i = 0; i < n; ++i) {
        d.push(L * u(rng), L * u(rng), std::pow(10.0, -3 + 4 * u(rng)));
      }
      if (n > 0 && rng() % 3 == 0) d.r[0] = L;  // one disk covering everything
      s.margin = 0.2 * u(rng);
      s.step = 0.1;
      break;
    }
    case Layout::Integer: {
      for (std::size_t i = 0; i < n; ++i) {
        d.push(static_cast<double>(rng() % 12), static_cast<double>(rng() % 12),
               0.5 * static_cast<double>(rng() % 3));
      }
      s.margin = 0.5 * static_cast<double>(rng() % 3);
      s.step = 0.5;
      s.grid = true;
      break;
    }
  }
  return s;
}

/// One step of motion: small moves of a random fraction, sometimes large jumps, radius
/// changes or a still step.
void move(Scene& s, std::mt19937_64& rng) {
  Disks& d = s.disks;
  const std::size_t n = d.size();
  if (n == 0) return;
  std::uniform_real_distribution<double> u(-1, 1);
  const auto kind = rng() % 10;
  if (kind == 0) return;  // still
  const double fraction = std::array<double, 4>{0.01, 0.1, 0.5, 1.0}[rng() % 4];
  for (std::size_t i = 0; i < n; ++i) {
    if (std::uniform_real_distribution<double>(0, 1)(rng) >= fraction) continue;
    if (s.grid) {
      d.x[i] += s.step * static_cast<double>(static_cast<int>(rng() % 3) - 1);
      d.y[i] += s.step * static_cast<double>(static_cast<int>(rng() % 3) - 1);
    } else {
      d.x[i] += s.step * u(rng);
      d.y[i] += s.step * u(rng);
    }
  }
  if (kind == 1) {  // a few large jumps
    for (int k = 0; k < 3; ++k) {
      const std::size_t i = rng() % n, j = rng() % n;
      d.x[i] = d.x[j] + (s.grid ? 0.0 : s.step * u(rng));
      d.y[i] = d.y[j];
    }
  }
  if (kind == 2) {  // radius changes
    const std::size_t i = rng() % n;
    d.r[i] = s.grid ? 0.5 * static_cast<double>(rng() % 3) : d.r[i] * (1 + 0.5 * std::abs(u(rng)));
  }
}

TEST(SweepPrune, MatchesBruteForceOnRandomSequences) {
  std::mt19937_64 rng(20240611);
  const std::size_t sizes[] = {2, 3, 7, 20, 60, 150};
  int configurations = 0;
  for (int round = 0; round < 30; ++round) {
    for (const Layout layout : kLayouts) {
      for (const std::size_t n : sizes) {
        if (n >= 150 && round % 3 != 0) continue;
        Scene s = make_scene(layout, n, rng);
        Model model;
        model.build(s.disks, s.margin);
        // Incremental only, from scratch only, and the default switch between the two.
        SweepPrune sp[3];
        sp[0].set_rebuild_fraction(2.0);
        sp[1].set_rebuild_fraction(0.0);
        for (auto& p : sp)
          p.build(s.disks.x.data(), s.disks.y.data(), s.disks.r.data(), n, s.margin);
        ASSERT_NO_FATAL_FAILURE(expect_consistent(sp[0], model, s.disks, {}));
        ASSERT_EQ(sp[1].pairs(), sp[0].pairs());
        ++configurations;
        for (int step = 0; step < 8; ++step) {
          move(s, rng);
          model.update(s.disks);
          for (int k = 0; k < 3; ++k) {
            const PairList before = sp[k].pairs();
            const bool changed = sp[k].update(s.disks.x.data(), s.disks.y.data(), s.disks.r.data());
            ASSERT_EQ(changed, before != sp[k].pairs()) << "layout " << static_cast<int>(layout);
          }
          ASSERT_FALSE(sp[0].stats().rebuilt);
          ASSERT_NO_FATAL_FAILURE(expect_consistent(sp[0], model, s.disks, {}))
              << "layout " << static_cast<int>(layout) << " n " << n << " step " << step;
          ASSERT_EQ(sp[1].pairs(), sp[0].pairs());
          ASSERT_EQ(sp[2].pairs(), sp[0].pairs());
          ++configurations;
        }
      }
    }
  }
  EXPECT_GT(configurations, 5000);
}

TEST(SweepPrune, FullSearchWithManyLargeDisks) {
  // A third of the disks are 500 times larger than the median: the band search widens its
  // bands until the entries stay bounded, and must still find every pair exactly once.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  for (int round = 0; round < 20; ++round) {
    Disks d;
    for (int k = 0; k < 300; ++k) d.push(30 * u(rng), 30 * u(rng), k % 3 == 0 ? 5.0 : 0.01);
    const double margin = 0.01 * static_cast<double>(round % 3);
    Model model;
    model.build(d, margin);
    SweepPrune sp;
    sp.set_rebuild_fraction(0.0);
    sp.build(d.x.data(), d.y.data(), d.r.data(), d.size(), margin);
    ASSERT_NO_FATAL_FAILURE(expect_consistent(sp, model, d, {}));
    for (std::size_t i = 0; i < d.size(); i += 7) d.x[i] += 0.5;
    model.update(d);
    sp.update(d.x.data(), d.y.data(), d.r.data());
    ASSERT_TRUE(sp.stats().rebuilt);
    ASSERT_NO_FATAL_FAILURE(expect_consistent(sp, model, d, {}));
  }
}

TEST(SweepPrune, ExactTiesCountAsOverlap) {
  // Two disks whose boxes touch at one coordinate, with and without margin.
  Disks d;
  d.push(0, 0, 1);
  d.push(2, 0, 1);
  SweepPrune sp;
  sp.build(d.x.data(), d.y.data(), d.r.data(), 2, 0);
  EXPECT_EQ(sp.pairs(), (PairList{{0, 1}}));
  d.x[1] = 3;  // boxes [-0.5, 0.5] + ... touch at 1.5 with margin 1
  sp.build(d.x.data(), d.y.data(), d.r.data(), 2, 1);
  EXPECT_EQ(sp.pairs(), (PairList{{0, 1}}));
  // Corner contact only.
  d.y[1] = 3;
  sp.build(d.x.data(), d.y.data(), d.r.data(), 2, 1);
  EXPECT_EQ(sp.pairs(), (PairList{{0, 1}}));
  // One ulp apart: no overlap.
  d.y[1] = std::nextafter(3.0, 4.0);
  sp.build(d.x.data(), d.y.data(), d.r.data(), 2, 1);
  EXPECT_TRUE(sp.pairs().empty());
  // Zero-size boxes at one point overlap.
  Disks p;
  for (int k = 0; k < 4; ++k) p.push(1, 1, 0);
  sp.build(p.x.data(), p.y.data(), p.r.data(), 4, 0);
  EXPECT_EQ(sp.pairs(), (PairList{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}));
}

TEST(SweepPrune, SignedZerosNegativesAndManyTies) {
  // Hundreds of disks on a few coordinates, negative ones, -0.0 and 1e-300 among them:
  // point-sized boxes (r = 0, no margin) overlap exactly when their disks sit at one point
  // (-0.0 and +0.0 being one point), then boxes of radius 0.5 after a full rebuild.
  std::mt19937_64 rng(5);
  const double coords[] = {-2.5, -1.0, -0.0, 0.0, 1.0, 1e-300, -1e-300};
  for (const std::size_t n : {40U, 200U, 700U}) {
    Disks d;
    for (std::size_t i = 0; i < n; ++i) d.push(coords[rng() % 7], coords[rng() % 7], 0.0);
    Model model;
    model.build(d, 0.0);
    SweepPrune sp;
    sp.build(d.x.data(), d.y.data(), d.r.data(), n, 0.0);
    ASSERT_NO_FATAL_FAILURE(expect_consistent(sp, model, d, {})) << n << " disks";
    // Boxes of radius 0.5 on the same points, and the rebuild path after moves.
    for (double& r : d.r) r = 0.5;
    SweepPrune again;
    again.set_rebuild_fraction(0.0);
    again.build(d.x.data(), d.y.data(), d.r.data(), n, 0.0);
    for (std::size_t i = 0; i < n; i += 3) d.x[i] = -d.x[i];
    model.build(d, 0.0);
    again.update(d.x.data(), d.y.data(), d.r.data());
    ASSERT_TRUE(again.stats().rebuilt);
    ASSERT_NO_FATAL_FAILURE(expect_consistent(again, model, d, {})) << n << " disks, rebuilt";
  }
}

TEST(SweepPrune, MarginRuleAndReturnValue) {
  Disks d;
  d.push(0, 0, 1);
  d.push(3, 0, 1);  // gap 1: a pair with margin 1 (boxes touch), not with margin 0.5
  SweepPrune sp;
  sp.build(d.x.data(), d.y.data(), d.r.data(), 2, 1.0);
  EXPECT_EQ(sp.pairs(), (PairList{{0, 1}}));
  EXPECT_FALSE(sp.update(d.x.data(), d.y.data(), d.r.data()));
  EXPECT_EQ(sp.stats().refreshed, 0U);
  EXPECT_EQ(sp.stats().swaps, 0U);

  d.x[1] = 3.5;  // moved exactly h = 0.5: box kept
  EXPECT_FALSE(sp.update(d.x.data(), d.y.data(), d.r.data()));
  EXPECT_EQ(sp.stats().refreshed, 0U);
  EXPECT_EQ(sp.box(1).lo_x, 3 - 1.5);
  EXPECT_EQ(sp.pairs(), (PairList{{0, 1}}));

  d.x[1] = 3.625;  // now beyond h: new box, gap 1.625 > margin
  EXPECT_TRUE(sp.update(d.x.data(), d.y.data(), d.r.data()));
  EXPECT_EQ(sp.stats().refreshed, 1U);
  EXPECT_EQ(sp.stats().flips, 1U);
  EXPECT_EQ(sp.box(1).lo_x, 3.625 - 1.5);
  EXPECT_TRUE(sp.pairs().empty());

  d.r[0] = 1.625;  // radius change refreshes although the centre did not move
  EXPECT_TRUE(sp.update(d.x.data(), d.y.data(), d.r.data()));
  EXPECT_EQ(sp.stats().refreshed, 1U);
  EXPECT_EQ(sp.pairs(), (PairList{{0, 1}}));

  d.y[0] = 0.25;  // moved 0.25 < h = 0.5: box kept
  EXPECT_FALSE(sp.update(d.x.data(), d.y.data(), d.r.data()));
  EXPECT_EQ(sp.stats().refreshed, 0U);
}

TEST(SweepPrune, NonFiniteDiskKeepsItsBox) {
  Disks d;
  d.push(0, 0, 1);
  d.push(2, 0, 1);
  d.push(10, 0, 1);
  SweepPrune sp;
  sp.build(d.x.data(), d.y.data(), d.r.data(), 3, 0.5);
  const SweepBox before = sp.box(1);
  d.x[1] = std::numeric_limits<double>::quiet_NaN();
  d.x[2] = 2;
  EXPECT_TRUE(sp.update(d.x.data(), d.y.data(), d.r.data()));
  EXPECT_EQ(sp.stats().non_finite, 1U);
  EXPECT_EQ(sp.stats().refreshed, 1U);
  EXPECT_EQ(sp.box(1).lo_x, before.lo_x);
  EXPECT_EQ(sp.pairs(), (PairList{{0, 1}, {0, 2}, {1, 2}}));
  d.y[1] = std::numeric_limits<double>::infinity();
  d.x[1] = 0;
  sp.update(d.x.data(), d.y.data(), d.r.data());
  EXPECT_EQ(sp.stats().non_finite, 1U);
  EXPECT_EQ(sp.box(1).lo_x, before.lo_x);
}

TEST(SweepPrune, RejectsBadInput) {
  Disks d;
  d.push(0, 0, 1);
  d.push(1, 0, 1);
  SweepPrune sp;
  EXPECT_THROW(sp.build(d.x.data(), d.y.data(), d.r.data(), 2, -1), std::logic_error);
  EXPECT_THROW(sp.build(d.x.data(), d.y.data(), d.r.data(), 2, std::nan("")), std::logic_error);
  d.r[1] = -1;
  EXPECT_THROW(sp.build(d.x.data(), d.y.data(), d.r.data(), 2, 0.1), std::logic_error);
  d.r[1] = 1;
  d.y[0] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(sp.build(d.x.data(), d.y.data(), d.r.data(), 2, 0.1), std::logic_error);
  d.y[0] = 0;
  const std::int32_t off[] = {0, 1, 1};
  const std::int32_t bad[] = {2};
  EXPECT_THROW(sp.set_exclusions(off, bad, 2), std::logic_error);
  const std::int32_t bi[] = {0, 1}, bj[] = {1, 5};
  EXPECT_THROW(sp.set_exclusion_pairs(bi, bj, 2, 2), std::logic_error);
  const std::int32_t good[] = {1};
  sp.set_exclusions(off, good, 2);
  EXPECT_THROW(sp.build(d.x.data(), d.y.data(), d.r.data(), 3, 0.1), std::logic_error);
  sp.build(d.x.data(), d.y.data(), d.r.data(), 2, 0.1);
  EXPECT_TRUE(sp.pairs().empty());
}

TEST(SweepPrune, EmptyAndSingle) {
  SweepPrune sp;
  EXPECT_FALSE(sp.update(nullptr, nullptr, nullptr));  // not built
  sp.build(nullptr, nullptr, nullptr, 0, 1.0);
  EXPECT_TRUE(sp.pairs().empty());
  EXPECT_FALSE(sp.update(nullptr, nullptr, nullptr));
  const double x = 1, y = 2, r = 3;
  sp.build(&x, &y, &r, 1, 0.0);
  EXPECT_TRUE(sp.pairs().empty());
  const double x2 = 100;
  EXPECT_FALSE(sp.update(&x2, &y, &r));
  EXPECT_EQ(sp.stats().refreshed, 1U);
}

TEST(SweepPrune, ExclusionsOfBondedNeighbours) {
  std::mt19937_64 rng(7);
  for (int round = 0; round < 40; ++round) {
    // Hexagonal patch with every lattice neighbour bonded (excluded), plus loose disks.
    const std::size_t side = 6 + rng() % 8;
    Scene s = make_scene(Layout::Hexagonal, side * side, rng);
    const double r = s.disks.r[0];
    for (int k = 0; k < 20; ++k) {
      s.disks.push(s.disks.x[rng() % (side * side)] + 0.3 * r, s.disks.y[rng() % (side * side)], r);
    }
    const std::size_t n = s.disks.size();
    std::set<Pair> excluded;
    for (std::size_t i = 0; i < side * side; ++i) {
      for (std::size_t j = i + 1; j < side * side; ++j) {
        const double dx = s.disks.x[i] - s.disks.x[j], dy = s.disks.y[i] - s.disks.y[j];
        if (dx * dx + dy * dy < 4.41 * r * r) {
          excluded.insert({static_cast<std::int32_t>(i), static_cast<std::int32_t>(j)});
        }
      }
    }
    const Csr csr = to_csr(excluded, n, rng);
    Model model;
    model.build(s.disks, s.margin);
    // As CSR before or after build(), or as a list of bonds (either orientation).
    SweepPrune sp;
    const int mode = round % 3;
    if (mode == 0) sp.set_exclusions(csr.offsets.data(), csr.neighbours.data(), n);
    if (mode == 2) {
      std::vector<std::int32_t> bi, bj;
      for (const auto& [i, j] : excluded) {
        bi.push_back(rng() % 2 ? i : j);
        bj.push_back(bi.back() == i ? j : i);
      }
      sp.set_exclusion_pairs(bi.data(), bj.data(), bi.size(), n);
    }
    sp.build(s.disks.x.data(), s.disks.y.data(), s.disks.r.data(), n, s.margin);
    if (mode == 1) {
      ASSERT_NO_FATAL_FAILURE(expect_consistent(sp, model, s.disks, {}));
      sp.set_exclusions(csr.offsets.data(), csr.neighbours.data(), n);
    }
    for (const auto& [i, j] : excluded) {
      ASSERT_TRUE(sp.is_excluded(i, j));
      ASSERT_TRUE(sp.is_excluded(j, i));
    }
    ASSERT_NO_FATAL_FAILURE(expect_consistent(sp, model, s.disks, excluded));
    for (int step = 0; step < 12; ++step) {
      // Bonds break: their pairs become candidates.
      for (int k = 0; k < 5 && !excluded.empty(); ++k) {
        auto it = excluded.begin();
        std::advance(it, static_cast<std::ptrdiff_t>(rng() % excluded.size()));
        const Pair p = *it;
        excluded.erase(it);
        ASSERT_TRUE(rng() % 2 ? sp.remove_exclusion(p.first, p.second)
                              : sp.remove_exclusion(p.second, p.first));
        ASSERT_FALSE(sp.remove_exclusion(p.first, p.second));
        ASSERT_FALSE(sp.is_excluded(p.first, p.second));
      }
      move(s, rng);
      model.update(s.disks);
      sp.update(s.disks.x.data(), s.disks.y.data(), s.disks.r.data());
      ASSERT_NO_FATAL_FAILURE(expect_consistent(sp, model, s.disks, excluded)) << "step " << step;
    }
    sp.clear_exclusions();
    ASSERT_NO_FATAL_FAILURE(expect_consistent(sp, model, s.disks, {}));
  }
}

TEST(SweepPrune, BrokenBondEntersAtNextUpdate) {
  Disks d;
  d.push(0, 0, 1);
  d.push(2, 0, 1);
  d.push(4, 0, 1);
  const std::int32_t off[] = {0, 1, 2, 2};
  const std::int32_t nbr[] = {1, 2};  // bonds 0-1 and 1-2
  SweepPrune sp;
  sp.set_rebuild_fraction(2.0);  // exercise the incremental path
  sp.set_exclusions(off, nbr, 3);
  sp.build(d.x.data(), d.y.data(), d.r.data(), 3, 0.1);
  EXPECT_TRUE(sp.pairs().empty());
  EXPECT_TRUE(sp.remove_exclusion(2, 1));
  EXPECT_TRUE(sp.pairs().empty());  // takes effect at the next update
  EXPECT_TRUE(sp.update(d.x.data(), d.y.data(), d.r.data()));
  EXPECT_EQ(sp.pairs(), (PairList{{1, 2}}));
  EXPECT_FALSE(sp.remove_exclusion(0, 2));  // never excluded
  // Released and separated before the next update: never listed.
  EXPECT_TRUE(sp.remove_exclusion(0, 1));
  d.x[0] = -5;
  EXPECT_FALSE(sp.update(d.x.data(), d.y.data(), d.r.data()));
  EXPECT_EQ(sp.pairs(), (PairList{{1, 2}}));
}

TEST(SweepPrune, OrderDoesNotDependOnHistory) {
  std::mt19937_64 rng(99);
  for (int round = 0; round < 15; ++round) {
    const Layout layout = kLayouts[rng() % std::size(kLayouts)];
    Scene a = make_scene(layout, 120, rng);
    Scene b = make_scene(layout, 120, rng);
    b.margin = a.margin;
    // Instance 1 starts at a and moves every disk to b through the incremental path;
    // instance 2 starts at b. All boxes then come from b, so everything must agree.
    SweepPrune one, two;
    one.set_rebuild_fraction(2.0);
    one.build(a.disks.x.data(), a.disks.y.data(), a.disks.r.data(), 120, a.margin);
    for (int step = 0; step < 3; ++step) {
      move(a, rng);
      one.update(a.disks.x.data(), a.disks.y.data(), a.disks.r.data());
    }
    // Move everything far first so that every disk is refreshed at b.
    std::vector<double> far(120, 1e6);
    one.update(far.data(), far.data(), a.disks.r.data());
    one.update(b.disks.x.data(), b.disks.y.data(), b.disks.r.data());
    two.build(b.disks.x.data(), b.disks.y.data(), b.disks.r.data(), 120, b.margin);
    ASSERT_EQ(one.pairs(), two.pairs());
    for (std::int32_t i = 0; i < 120; ++i) {
      ASSERT_EQ(one.box(i).lo_x, two.box(i).lo_x);
      ASSERT_EQ(one.box(i).hi_y, two.box(i).hi_y);
    }
    // Repeating a run gives the same lists and the same work.
    SweepPrune three;
    three.set_rebuild_fraction(2.0);
    three.build(b.disks.x.data(), b.disks.y.data(), b.disks.r.data(), 120, b.margin);
    std::mt19937_64 r1(round), r2(round);
    Scene b1 = b, b2 = b;
    for (int step = 0; step < 5; ++step) {
      move(b1, r1);
      move(b2, r2);
      two.set_rebuild_fraction(2.0);
      two.update(b1.disks.x.data(), b1.disks.y.data(), b1.disks.r.data());
      three.update(b2.disks.x.data(), b2.disks.y.data(), b2.disks.r.data());
      ASSERT_EQ(two.pairs(), three.pairs());
      ASSERT_EQ(two.stats().swaps, three.stats().swaps);
    }
  }
}

TEST(SweepPrune, FewMovesCostFewSwaps) {
  // 10,000 disks on a hexagonal lattice, 1 % moved beyond half the margin: the work is local.
  std::mt19937_64 rng(3);
  Scene s = make_scene(Layout::Hexagonal, 10000, rng);
  const double r = s.disks.r[0];
  SweepPrune sp;
  sp.build(s.disks.x.data(), s.disks.y.data(), s.disks.r.data(), 10000, 0.2 * r);
  EXPECT_GT(sp.pairs().size(), 29000U);  // 3 lattice neighbours per disk, less the edges
  std::vector<std::size_t> order(10000);
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  for (std::size_t k = 0; k < 100; ++k) {
    s.disks.x[order[k]] += 0.15 * r;
    s.disks.y[order[k]] -= 0.05 * r;
  }
  sp.update(s.disks.x.data(), s.disks.y.data(), s.disks.r.data());
  EXPECT_EQ(sp.stats().refreshed, 100U);
  EXPECT_FALSE(sp.stats().rebuilt);
  // Each moved end point passes the end points within 0.15 r along its axis (about 15 in x,
  // 6 in y on this 200 r x 173 r patch) and, on an exact lattice, about half of the 50 to
  // 100 end points that share its old coordinate: some 160 swaps per disk, not N.
  EXPECT_GT(sp.stats().swaps, 0U);
  EXPECT_LT(sp.stats().swaps, 100U * 400U);
}

}  // namespace
}  // namespace hexdem::solver
