// Benchmark of the contact broad phase (docs/contact-detection.md): N disks of radius
// r = 0.5 mm on a hexagonal lattice, margin 0.2 r. The lattice is exact with its rows along x
// (lattice 0: whole rows and columns share a coordinate), jittered by up to 0.01 r (1), or
// turned by 17 degrees (2: no shared coordinates). Per step a
// fixed random subset of the disks jumps by 0.6 margin (beyond margin / 2, so each of them
// gets a new box every step) and back on the next step. Compared with building everything
// from scratch every step, and with sorting the end points alone.
// Run: build/release/tests/benchmarks/bench_sweep_prune
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "hexdem/solver/sweep_prune.hpp"

namespace {

using hexdem::solver::SweepPrune;

constexpr double kRadius = 0.5e-3;         // [m]
constexpr double kMargin = 0.2 * kRadius;  // [m]
constexpr double kJump = 0.6 * kMargin;    // [m], > margin / 2

/// Two position sets: the lattice sites, and the sites with `percent` % of the disks moved.
struct Scene {
  std::vector<double> x0, y0, x1, y1, r;

  Scene(std::size_t n, double percent, int lattice = 0) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> jit(-0.01 * kRadius, 0.01 * kRadius);
    const double c = std::cos(17 * 3.14159265358979323846 / 180);
    const double s = std::sin(17 * 3.14159265358979323846 / 180);
    const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t row = i / side, col = i % side;
      double x = 2 * kRadius * static_cast<double>(col) + kRadius * static_cast<double>(row % 2);
      double y = std::sqrt(3.0) * kRadius * static_cast<double>(row);
      if (lattice == 1) {
        x += jit(rng);
        y += jit(rng);
      } else if (lattice == 2) {
        const double xr = c * x - s * y;
        y = s * x + c * y;
        x = xr;
      }
      x0.push_back(x);
      y0.push_back(y);
      r.push_back(kRadius);
    }
    x1 = x0;
    y1 = y0;
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    std::uniform_real_distribution<double> angle(0, 2 * 3.14159265358979323846);
    const auto moving =
        static_cast<std::size_t>(std::llround(percent / 100 * static_cast<double>(n)));
    for (std::size_t k = 0; k < moving; ++k) {
      const double t = angle(rng);
      x1[order[k]] += kJump * std::cos(t);
      y1[order[k]] += kJump * std::sin(t);
    }
  }
};

void set_counters(benchmark::State& state, const SweepPrune& sp, std::size_t swaps = 0,
                  std::size_t steps = 0) {
  state.counters["pairs"] = static_cast<double>(sp.pairs().size());
  if (steps > 0) {
    state.counters["swaps_per_step"] = static_cast<double>(swaps) / static_cast<double>(steps);
  }
  state.counters["disks_per_s"] = benchmark::Counter(static_cast<double>(sp.size()),
                                                     benchmark::Counter::kIsIterationInvariantRate);
}

/// Build from scratch: full sort of both axes and the banded pair search.
void BM_Build(benchmark::State& state) {
  const Scene s(static_cast<std::size_t>(state.range(0)), 0);
  SweepPrune sp;
  for (auto _ : state) {
    sp.build(s.x0.data(), s.y0.data(), s.r.data(), s.r.size(), kMargin);
    benchmark::DoNotOptimize(sp.pairs().data());
  }
  set_counters(state, sp);
  state.counters["bytes_per_disk"] =
      static_cast<double>(sp.memory_bytes()) / static_cast<double>(sp.size());
}

/// update() with range(1) % of the disks refreshed per step, on lattice range(2) (see
/// above); range(3) = 1: never rebuild (swaps only), 0: the default switch.
void BM_Update(benchmark::State& state) {
  const Scene s(static_cast<std::size_t>(state.range(0)), static_cast<double>(state.range(1)),
                static_cast<int>(state.range(2)));
  SweepPrune sp;
  if (state.range(3) == 1) sp.set_rebuild_fraction(2.0);
  sp.build(s.x0.data(), s.y0.data(), s.r.data(), s.r.size(), kMargin);
  bool moved = false;
  std::size_t swaps = 0, steps = 0;
  for (auto _ : state) {
    moved = !moved;
    const bool changed = moved ? sp.update(s.x1.data(), s.y1.data(), s.r.data())
                               : sp.update(s.x0.data(), s.y0.data(), s.r.data());
    benchmark::DoNotOptimize(changed);
    swaps += sp.stats().swaps;
    ++steps;
  }
  set_counters(state, sp, swaps, steps);
}

/// The common case: range(1) % of the disks oscillate about their sites with amplitude
/// `margin` and a period of 64 steps (at most 0.1 margin per step), so each of them gets a new
/// box every 12 steps or so. The motion is computed inside the timed loop (a cos per moving
/// disk; under 2 % of the time).
void BM_UpdateSmallMoves(benchmark::State& state) {
  Scene s(static_cast<std::size_t>(state.range(0)), static_cast<double>(state.range(1)));
  std::vector<std::size_t> moving;
  std::vector<double> ux, uy, phase;
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> angle(0, 2 * 3.14159265358979323846);
  for (std::size_t i = 0; i < s.r.size(); ++i) {
    if (s.x1[i] == s.x0[i] && s.y1[i] == s.y0[i]) continue;
    const double t = angle(rng);
    moving.push_back(i);
    ux.push_back(kMargin * std::cos(t));
    uy.push_back(kMargin * std::sin(t));
    phase.push_back(angle(rng));
  }
  std::vector<double> x = s.x0, y = s.y0;
  SweepPrune sp;
  sp.build(x.data(), y.data(), s.r.data(), s.r.size(), kMargin);
  const double omega = 2 * 3.14159265358979323846 / 64;
  std::size_t step = 0, refreshed = 0, swaps = 0;
  for (auto _ : state) {
    ++step;
    for (std::size_t k = 0; k < moving.size(); ++k) {
      const double a = std::sin(omega * static_cast<double>(step) + phase[k]);
      x[moving[k]] = s.x0[moving[k]] + a * ux[k];
      y[moving[k]] = s.y0[moving[k]] + a * uy[k];
    }
    benchmark::DoNotOptimize(sp.update(x.data(), y.data(), s.r.data()));
    refreshed += sp.stats().refreshed;
    swaps += sp.stats().swaps;
  }
  set_counters(state, sp, swaps, step);
  state.counters["refreshed_per_step"] = static_cast<double>(refreshed) / static_cast<double>(step);
}

/// update() when every disk moves but none beyond margin / 2: the displacement scan alone.
void BM_UpdateWithinMargin(benchmark::State& state) {
  Scene s(static_cast<std::size_t>(state.range(0)), 0);
  for (std::size_t i = 0; i < s.r.size(); ++i) s.x1[i] += 0.1 * kMargin;
  SweepPrune sp;
  sp.build(s.x0.data(), s.y0.data(), s.r.data(), s.r.size(), kMargin);
  bool moved = false;
  for (auto _ : state) {
    moved = !moved;
    benchmark::DoNotOptimize(moved ? sp.update(s.x1.data(), s.y1.data(), s.r.data())
                                   : sp.update(s.x0.data(), s.y0.data(), s.r.data()));
  }
  set_counters(state, sp);
}

/// The alternative to updating: build() from scratch every step, with the same motion.
void BM_RebuildEachStep(benchmark::State& state) {
  const Scene s(static_cast<std::size_t>(state.range(0)), static_cast<double>(state.range(1)));
  SweepPrune sp;
  bool moved = false;
  for (auto _ : state) {
    moved = !moved;
    if (moved) {
      sp.build(s.x1.data(), s.y1.data(), s.r.data(), s.r.size(), kMargin);
    } else {
      sp.build(s.x0.data(), s.y0.data(), s.r.data(), s.r.size(), kMargin);
    }
    benchmark::DoNotOptimize(sp.pairs().data());
  }
  set_counters(state, sp);
}

/// Lower bound of any full re-sort: std::sort of the 2N end points of each axis, no pairs.
void BM_SortEndPoints(benchmark::State& state) {
  const Scene s(static_cast<std::size_t>(state.range(0)), 0);
  const std::size_t n = s.r.size();
  struct End {
    double value;
    std::uint32_t tag;
  };
  std::vector<End> ends(2 * n);
  for (auto _ : state) {
    for (const std::vector<double>* c : {&s.x1, &s.y1}) {
      for (std::size_t i = 0; i < n; ++i) {
        const double w = s.r[i] + 0.5 * kMargin;
        ends[2 * i] = {(*c)[i] - w, static_cast<std::uint32_t>(i)};
        ends[2 * i + 1] = {(*c)[i] + w, 0x80000000u | static_cast<std::uint32_t>(i)};
      }
      std::sort(ends.begin(), ends.end(), [](const End& a, const End& b) {
        return a.value < b.value || (a.value == b.value && a.tag < b.tag);
      });
      benchmark::DoNotOptimize(ends.data());
    }
  }
  state.counters["disks_per_s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(BM_Build)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Update)
    ->ArgNames({"n", "percent", "lattice", "swaps_only"})
    ->ArgsProduct({{10000, 100000}, {1, 10, 100}, {0, 1, 2}, {0}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Update)
    ->ArgNames({"n", "percent", "lattice", "swaps_only"})
    ->ArgsProduct({{10000, 100000}, {10, 25, 50, 100}, {0, 2}, {1}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UpdateSmallMoves)
    ->ArgNames({"n", "percent"})
    ->ArgsProduct({{10000, 100000}, {1, 10}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UpdateWithinMargin)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RebuildEachStep)
    ->ArgNames({"n", "percent"})
    ->ArgsProduct({{10000, 100000}, {1}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SortEndPoints)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
