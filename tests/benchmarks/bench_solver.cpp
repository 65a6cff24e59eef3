// Benchmarks of the solver's per-step kernels on a square plate of material B (the paper's
// half-plane size: about 72,000 disks), for each shear model and thread count.
// Run: build/release/tests/benchmarks/bench_solver
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>

#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/solver/model.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;

Model plate_model(ShearModel shear, double side_disks) {
  const double r = 0.5e-3, L = side_disks * 2 * r;
  meshing::Outline o;
  meshing::BodyOutline b;
  b.name = "plate";
  b.where = "bench";
  meshing::Loop loop;
  loop.points = {{0, 0}, {L, 0}, {L, L}, {0, L}};
  loop.edge_set.assign(4, -1);
  loop.edge_straight.assign(4, 1);
  b.outers.push_back(loop);
  o.bodies.push_back(b);
  meshing::GeneratorOptions go;
  go.lattice.radius = r;
  static Material mat;
  mat.name = "material-B";
  mat.isotropic = false;
  mat.c = {5.0961e9, 1.2256e9, 3.5359e9, 1.2198e9};
  mat.density = 1244;
  std::vector<BodyMaterial> bm(1);
  bm[0].material = &mat;
  bm[0].springs = spring_constants(mat.c);
  Model m = build_model(meshing::generate_lattice(o, go), Geometry::PlaneStress, 1.0, shear, bm);
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    m.ux[i] = 1e-6 * std::sin(1000 * m.x0[i]) * std::cos(700 * m.y0[i]);
    m.uy[i] = 1e-6 * std::cos(900 * m.x0[i]);
  }
  return m;
}

void BM_InternalForces(benchmark::State& state) {
  const auto shear = state.range(0) == 0 ? ShearModel::LocalStrain : ShearModel::Rotation;
  omp_set_num_threads(static_cast<int>(state.range(1)));
  Model m = plate_model(shear, 250);  // 250 x 290 rows: about 72,000 disks
  for (auto _ : state) {
    compute_internal_forces(m, 1e-7);
    benchmark::DoNotOptimize(m.fx.data());
  }
  state.counters["disks"] = static_cast<double>(m.num_disks());
  state.counters["ns_per_disk"] = benchmark::Counter(
      static_cast<double>(m.num_disks()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_InternalForces)
    ->ArgNames({"rotation", "threads"})
    ->Args({0, 1})->Args({0, 2})->Args({1, 1})->Args({1, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
