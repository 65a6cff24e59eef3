// Bad input to the three filters: a frame without `state` or `stress`, an empty grid, a
// grid that is not a hexdem frame, arrays of the wrong size. Each must report an error
// naming the problem and leave an empty output, never crash.

#include <gtest/gtest.h>

#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkHexDEMCrackMap.h>
#include <vtkHexDEMFragmentCounter.h>
#include <vtkHexDEMMaxShearStress.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkTable.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <functional>
#include <memory>
#include <string>

#include "frame_builder.hpp"
#include "message_log.hpp"

namespace {

using hexdem::testing::FrameData;
using hexdem::testing::make_frame;
using hexdem::testing::make_lattice;
using hexdem::testing::MessageLog;

vtkSmartPointer<vtkUnstructuredGrid> good_frame() {
  FrameData data;
  data.p_max = 1.0;
  return make_frame(make_lattice(4, 3, 1e-3), data);
}

/// A triangle with a temperature: a valid .vtu, but not a hexdem frame.
vtkSmartPointer<vtkUnstructuredGrid> foreign_grid() {
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  points->InsertNextPoint(1, 0, 0);
  points->InsertNextPoint(0, 1, 0);
  grid->SetPoints(points);
  vtkIdType ids[3] = {0, 1, 2};
  grid->InsertNextCell(VTK_TRIANGLE, 3, ids);
  vtkNew<vtkDoubleArray> temperature;
  temperature->SetName("temperature");
  temperature->SetNumberOfTuples(3);
  temperature->FillValue(300.0);
  grid->GetPointData()->AddArray(temperature);
  return grid;
}

/// Sizes of the outputs of a run.
struct RunSizes {
  vtkIdType points = -1;
  vtkIdType cells = -1;
  vtkIdType table_rows = -1;
};

/// Runs a new `Filter` on `input`, recording its messages in `log`.
template <typename Filter>
RunSizes run(vtkUnstructuredGrid* input, std::unique_ptr<MessageLog>& log,
             vtkSmartPointer<Filter>& filter, const std::function<void(Filter*)>& configure = {}) {
  filter = vtkSmartPointer<Filter>::New();
  log = std::make_unique<MessageLog>(filter);
  if (configure) configure(filter);
  filter->SetInputData(input);
  filter->Update();
  RunSizes r;
  auto* out = vtkDataSet::SafeDownCast(filter->GetOutputDataObject(0));
  r.points = out->GetNumberOfPoints();
  r.cells = out->GetNumberOfCells();
  if (filter->GetNumberOfOutputPorts() > 1) {
    r.table_rows = vtkTable::SafeDownCast(filter->GetOutputDataObject(1))->GetNumberOfRows();
  }
  return r;
}

/// Expects an error containing `part` and empty outputs.
template <typename Filter>
void expect_failure(vtkUnstructuredGrid* input, const std::string& part,
                    const std::function<void(Filter*)>& configure = {}) {
  std::unique_ptr<MessageLog> log;
  vtkSmartPointer<Filter> filter;
  const RunSizes r = run<Filter>(input, log, filter, configure);
  EXPECT_TRUE(log->has_error(part))
      << filter->GetClassName() << ": " << (log->errors.empty() ? "no error" : log->errors[0]);
  EXPECT_EQ(r.points, 0);
  EXPECT_EQ(r.cells, 0);
  if (r.table_rows >= 0) {
    EXPECT_EQ(r.table_rows, 0);
  }
}

TEST(BadInput, FrameWithoutState) {
  auto frame = good_frame();
  frame->GetCellData()->RemoveArray("state");
  expect_failure<vtkHexDEMCrackMap>(frame, "'state'");
  expect_failure<vtkHexDEMFragmentCounter>(frame, "'state'");
  // The maximum shear needs `state` only to recover the stress from the bond forces.
  expect_failure<vtkHexDEMMaxShearStress>(
      frame, "'state'", [](vtkHexDEMMaxShearStress* f) { f->SetStressSourceToBondForces(); });
}

TEST(BadInput, FrameWithoutStress) {
  auto frame = good_frame();
  frame->GetPointData()->RemoveArray("stress");
  expect_failure<vtkHexDEMMaxShearStress>(
      frame, "'stress'", [](vtkHexDEMMaxShearStress* f) { f->SetStressSourceToPointArray(); });
  // Automatic: recovered from the bond forces instead.
  std::unique_ptr<MessageLog> log;
  vtkSmartPointer<vtkHexDEMMaxShearStress> filter;
  const RunSizes r = run<vtkHexDEMMaxShearStress>(frame, log, filter);
  EXPECT_EQ(r.points, 12);
  EXPECT_TRUE(log->errors.empty());
  EXPECT_NE(filter->GetOutput()->GetPointData()->GetArray("recovered_stress"), nullptr);
  // Without stress and without forces: an error naming what is missing.
  frame->GetCellData()->RemoveArray("normal_force");
  expect_failure<vtkHexDEMMaxShearStress>(frame, "'normal_force'");
}

TEST(BadInput, EmptyGrid) {
  vtkNew<vtkUnstructuredGrid> empty;
  expect_failure<vtkHexDEMMaxShearStress>(empty, "no disks");
  expect_failure<vtkHexDEMCrackMap>(empty, "no disks");
  expect_failure<vtkHexDEMFragmentCounter>(empty, "no disks");
}

TEST(BadInput, ForeignGrid) {
  auto grid = foreign_grid();
  expect_failure<vtkHexDEMMaxShearStress>(
      grid, "'stress'", [](vtkHexDEMMaxShearStress* f) { f->SetStressSourceToPointArray(); });
  expect_failure<vtkHexDEMMaxShearStress>(grid, "'radius'");
  expect_failure<vtkHexDEMCrackMap>(grid, "'state'");
  expect_failure<vtkHexDEMFragmentCounter>(grid, "'state'");
  // With a state array, the triangle is still not a bond.
  vtkNew<vtkUnsignedCharArray> state;
  state->SetName("state");
  state->InsertNextValue(0);
  grid->GetCellData()->AddArray(state);
  expect_failure<vtkHexDEMFragmentCounter>(grid, "not a two-point line");
}

TEST(BadInput, ArraysOfTheWrongSize) {
  auto frame = good_frame();
  vtkNew<vtkUnsignedCharArray> state;
  state->SetName("state");
  state->SetNumberOfTuples(3);
  state->FillValue(2);
  frame->GetCellData()->AddArray(state);
  expect_failure<vtkHexDEMCrackMap>(frame, "tuples");
  expect_failure<vtkHexDEMFragmentCounter>(frame, "tuples");

  auto frame2 = good_frame();
  vtkNew<vtkDoubleArray> stress;
  stress->SetName("stress");
  stress->SetNumberOfComponents(6);
  stress->SetNumberOfTuples(12);
  stress->FillValue(0.0);
  frame2->GetPointData()->AddArray(stress);
  expect_failure<vtkHexDEMMaxShearStress>(frame2, "6 components");
}

TEST(BadInput, FilterRecoversOnGoodInputAfterAFailure) {
  vtkNew<vtkHexDEMFragmentCounter> filter;
  MessageLog log(filter);
  vtkNew<vtkUnstructuredGrid> empty;
  filter->SetInputData(empty);
  filter->Update();
  EXPECT_FALSE(log.errors.empty());
  filter->SetInputData(good_frame());
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 12);
  EXPECT_EQ(filter->GetTableOutput()->GetNumberOfRows(), 1);
}

}  // namespace
