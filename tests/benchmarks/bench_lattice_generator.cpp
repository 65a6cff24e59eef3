// Benchmark of the lattice generator: a 1,000-vertex polygon with 10 holes filled with
// about 1,000,000 disks (the same outline as scripts/make_bench_outline.py writes).
// Run: build/release/tests/benchmarks/bench_lattice_generator
#include <benchmark/benchmark.h>

#include <cmath>

#include "hexdem/meshing/lattice_generator.hpp"

namespace {

using namespace hexdem::meshing;
constexpr double kPi = 3.14159265358979323846;

Loop wobbly(double cx, double cy, double R, int n, bool ccw) {
  Loop l;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * kPi * k / n * (ccw ? 1 : -1);
    const double rr = R * (1 + 0.08 * std::sin(7 * t) + 0.04 * std::sin(13 * t));
    l.points.push_back({cx + rr * std::cos(t), cy + rr * std::sin(t)});
  }
  l.edge_set.assign(n, -1);
  l.edge_straight.assign(n, 1);
  l.where = "bench";
  return l;
}

/// Outer radius chosen so that r = 1 gives about `disks` disks.
Outline bench_outline(double disks) {
  const double hex = 2 * std::sqrt(3.0);
  const double R = std::sqrt(disks * hex / kPi * 1.02);
  Outline o;
  BodyOutline b;
  b.name = "bench";
  b.where = "bench";
  b.outers.push_back(wobbly(0, 0, R, 1000, true));
  for (int h = 0; h < 10; ++h) {
    const double a = 2 * kPi * h / 10;
    b.holes.push_back(wobbly(0.6 * R * std::cos(a), 0.6 * R * std::sin(a), 0.05 * R, 100, false));
  }
  o.bodies.push_back(b);
  return o;
}

void BM_GenerateLattice(benchmark::State& state) {
  const Outline o = bench_outline(static_cast<double>(state.range(0)));
  GeneratorOptions opt;
  opt.lattice.radius = 1.0;
  std::size_t disks = 0;
  for (auto _ : state) {
    Lattice lat = generate_lattice(o, opt);
    disks = lat.num_disks();
    benchmark::DoNotOptimize(lat.x.data());
  }
  state.counters["disks"] = static_cast<double>(disks);
  state.counters["disks_per_s"] = benchmark::Counter(static_cast<double>(disks), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_GenerateLattice)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
