// Benchmark of the three hexdem filters on a frame of 1,000,000 disks and about 3,000,000
// bonds with 10 % of them broken at random, single-threaded, and of the chain ParaView users
// would run instead to count fragments: vtkThreshold (cell array `state` in [0, 1]) followed by
// vtkConnectivityFilter (all regions), plus the disks that Threshold drops (no intact bond).
// Run: build/release/tests/vtkfilters/bench_filters   (targets: docs/filters.md)
#include <benchmark/benchmark.h>

#include <vtkCellData.h>
#include <vtkConnectivityFilter.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkFieldData.h>
#include <vtkHexDEMCrackMap.h>
#include <vtkHexDEMFragmentCounter.h>
#include <vtkHexDEMMaxShearStress.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSMPTools.h>
#include <vtkSmartPointer.h>
#include <vtkThreshold.h>
#include <vtkUnstructuredGrid.h>

#include <cstdint>
#include <random>

#include "frame_builder.hpp"

namespace {

using namespace hexdem::testing;

/// The benchmark frame, built once: 1000 x 1000 disks, 10 % of the bonds broken.
vtkUnstructuredGrid* frame() {
  static vtkSmartPointer<vtkUnstructuredGrid> grid = [] {
    vtkSMPTools::SetBackend("Sequential");
    const Lattice l = make_lattice(1000, 1000, 5e-4);
    FrameData d;
    d.p_max = 1e7;
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    d.state.resize(l.bonds());
    d.break_time.resize(l.bonds());
    d.normal_force.resize(l.bonds());
    d.shear_force.resize(l.bonds());
    for (std::int64_t b = 0; b < l.bonds(); ++b) {
      const bool broken = unit(rng) < 0.10;
      d.state[b] = broken ? static_cast<std::uint8_t>(2 + (rng() % 3)) : 0;
      d.break_time[b] = broken ? 1e-4 * unit(rng) : -1.0;
      d.normal_force[b] = 100.0 * (unit(rng) - 0.5);
      d.shear_force[b] = 10.0 * (unit(rng) - 0.5);
    }
    d.stress.resize(9 * l.disks());
    for (double& s : d.stress) s = 1e6 * (unit(rng) - 0.5);
    return make_frame(l, d);
  }();
  return grid;
}

double field(vtkDataObject* data, const char* name) {
  return vtkDataArray::SafeDownCast(data->GetFieldData()->GetAbstractArray(name))
      ->GetComponent(0, 0);
}

template <typename Filter>
void run(benchmark::State& state, Filter* filter) {
  filter->SetInputData(frame());
  for (auto _ : state) {
    filter->Modified();
    filter->Update();
  }
  state.counters["disks"] = static_cast<double>(frame()->GetNumberOfPoints());
  state.counters["bonds"] = static_cast<double>(frame()->GetNumberOfCells());
}

void BM_MaxShearStress(benchmark::State& state) {
  vtkNew<vtkHexDEMMaxShearStress> filter;
  run(state, filter.Get());
}

void BM_MaxShearStressFromBondForces(benchmark::State& state) {
  vtkNew<vtkHexDEMMaxShearStress> filter;
  filter->SetStressSourceToBondForces();
  run(state, filter.Get());
}

void BM_CrackMap(benchmark::State& state) {
  vtkNew<vtkHexDEMCrackMap> filter;
  filter->SetMergeSegments(state.range(0) != 0);
  run(state, filter.Get());
  state.counters["cracks"] = field(filter->GetOutput(), "crack_count");
  state.counters["lines"] = static_cast<double>(filter->GetOutput()->GetNumberOfCells());
}

void BM_FragmentCounter(benchmark::State& state) {
  vtkNew<vtkHexDEMFragmentCounter> filter;
  run(state, filter.Get());
  state.counters["fragments"] = field(filter->GetOutput(), "fragment_count");
}

/// ParaView's way: Threshold on intact bonds, then Connectivity; disks without an intact
/// bond vanish in Threshold and are counted as one-disk fragments.
void BM_ThresholdConnectivity(benchmark::State& state) {
  vtkNew<vtkThreshold> threshold;
  threshold->SetInputData(frame());
  threshold->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "state");
  threshold->SetLowerThreshold(0.0);
  threshold->SetUpperThreshold(1.0);
  threshold->SetThresholdFunction(vtkThreshold::THRESHOLD_BETWEEN);
  vtkNew<vtkConnectivityFilter> connectivity;
  connectivity->SetInputConnection(threshold->GetOutputPort());
  connectivity->SetExtractionModeToAllRegions();
  connectivity->ColorRegionsOn();
  double fragments = 0;
  for (auto _ : state) {
    threshold->Modified();
    connectivity->Update();
    auto* regions = vtkUnstructuredGrid::SafeDownCast(connectivity->GetOutput());
    const vtkIdType isolated = frame()->GetNumberOfPoints() - regions->GetNumberOfPoints();
    fragments = static_cast<double>(connectivity->GetNumberOfExtractedRegions() + isolated);
    benchmark::DoNotOptimize(fragments);
  }
  state.counters["fragments"] = fragments;
}

}  // namespace

BENCHMARK(BM_MaxShearStress)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_MaxShearStressFromBondForces)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
BENCHMARK(BM_CrackMap)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_FragmentCounter)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_ThresholdConnectivity)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

BENCHMARK_MAIN();
