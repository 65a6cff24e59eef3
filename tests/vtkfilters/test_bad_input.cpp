// Bad input to the three filters: a frame without `state` or `stress`, an empty grid, a
// grid that is not a hexdem frame, arrays of the wrong size. Each must report an error
// naming the problem and leave an empty output, never crash.

#include <gtest/gtest.h>

#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkHexDEMCrackMap.h>
#include <vtkHexDEMFragmentCounter.h>
#include <vtkHexDEMMaxShearStress.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <functional>
#include <limits>
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

// ---- values no run writes, and bad properties (hostile-input report 3, item 12) -----------
// Each was accepted: empty CSV fields ("max tau_max  Pa"), a state of 200 counted as neither
// intact nor broken, a negative fragment mass, Body = 999 "succeeding" with 0 fragments.

/// The good frame with one value of a numeric array replaced.
vtkSmartPointer<vtkUnstructuredGrid> frame_with(const char* where, const char* name, double value,
                                                vtkIdType tuple = 0, int component = 0) {
  auto frame = good_frame();
  vtkDataArray* array = nullptr;
  if (std::string(where) == "points") {
    array = frame->GetPoints()->GetData();
  } else if (std::string(where) == "point") {
    array = frame->GetPointData()->GetArray(name);
  } else if (std::string(where) == "cell") {
    // A copy as doubles: the frame's UInt8 `state` cannot hold NaN or -3.
    vtkNew<vtkDoubleArray> copy;
    copy->DeepCopy(frame->GetCellData()->GetArray(name));
    copy->SetName(name);
    frame->GetCellData()->AddArray(copy);
    array = copy;
  } else {
    array = vtkDataArray::SafeDownCast(frame->GetFieldData()->GetAbstractArray(name));
    if (!array) {
      vtkNew<vtkDoubleArray> added;
      added->SetName(name);
      added->SetNumberOfTuples(1);
      frame->GetFieldData()->AddArray(added);
      array = added;
    }
  }
  EXPECT_NE(array, nullptr) << name;
  array->SetComponent(tuple, component, value);
  return frame;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(BadValues, NonFiniteAndOutOfRangeFrameValuesAreRefused) {
  using MaxShear = vtkHexDEMMaxShearStress;
  using Cracks = vtkHexDEMCrackMap;
  using Fragments = vtkHexDEMFragmentCounter;
  // Points: every filter.
  auto frame = frame_with("points", "", kNaN, 3, 1);
  expect_failure<MaxShear>(frame, "point coordinates array holds nan at tuple 3, component 1");
  expect_failure<Cracks>(frame, "point coordinates array holds nan at tuple 3");
  expect_failure<Fragments>(frame, "point coordinates array holds nan at tuple 3");
  // Stress: NaN and one infinite value.
  expect_failure<MaxShear>(frame_with("point", "stress", kNaN), "'stress' point array holds nan");
  expect_failure<MaxShear>(frame_with("point", "stress", kInf, 5, 0),
                           "'stress' point array holds inf at tuple 5, component 0");
  // Finite stresses whose difference overflows.
  frame = frame_with("point", "stress", 1.5e308, 2, 0);
  frame->GetPointData()->GetArray("stress")->SetComponent(2, 4, -1.5e308);
  expect_failure<MaxShear>(frame, "'max_shear' of disk 2 is inf");
  // Bond states outside the enum.
  for (double state : {200.0, -3.0, 6.0, 2.5, kNaN}) {
    frame = frame_with("cell", "state", state, 4);
    SCOPED_TRACE(state);
    expect_failure<Cracks>(frame, "'state' cell array holds");
    expect_failure<Cracks>(frame, "at tuple 4 (expected an integer code 0 to 5)");
    expect_failure<Fragments>(frame, "'state' cell array holds");
    expect_failure<MaxShear>(frame, "'state' cell array holds",
                             [](MaxShear* f) { f->SetStressSourceToBondForces(); });
  }
  // Mass, area, velocity, radius (the fragment table, the crack map).
  expect_failure<Fragments>(frame_with("point", "mass", kNaN), "'mass' point array holds nan");
  expect_failure<Fragments>(frame_with("point", "mass", -55.0, 1), "'mass' point array holds -55 at tuple 1");
  expect_failure<Fragments>(frame_with("point", "cell_area", -1.0), "'cell_area' point array holds -1");
  expect_failure<Fragments>(frame_with("point", "velocity", kNaN, 0, 1), "'velocity' point array holds nan");
  expect_failure<Cracks>(frame_with("point", "radius", 0.0), "'radius' point array holds 0");
  expect_failure<Cracks>(frame_with("cell", "break_time", kInf), "'break_time' cell array holds inf");
  // Field data: a NaN time, a negative thickness, a p_max whose inverse overflows.
  for (auto* f : {"time", "step"}) {
    frame = frame_with("field", f, kNaN);
    expect_failure<MaxShear>(frame, std::string("field data '") + f + "' is nan");
    expect_failure<Cracks>(frame, std::string("field data '") + f + "' is nan");
    expect_failure<Fragments>(frame, std::string("field data '") + f + "' is nan");
  }
  expect_failure<MaxShear>(frame_with("field", "thickness", -1.0), "field data 'thickness' is -1");
  expect_failure<MaxShear>(frame_with("field", "p_max", 1e-320), "1/p_max overflows");
  // Body indices outside the named bodies.
  frame = frame_with("point", "body", 7.0, 2);
  vtkNew<vtkStringArray> names;
  names->SetName("body_names");
  names->InsertNextValue("plate");
  frame->GetFieldData()->AddArray(names);
  expect_failure<Fragments>(frame, "'body' point array holds 7 at tuple 2");
  expect_failure<Fragments>(frame_with("point", "body", -1.0), "'body' point array holds -1");
}

TEST(BadValues, BadPropertiesAreRefusedNotClamped) {
  using Fragments = vtkHexDEMFragmentCounter;
  auto frame = good_frame();
  // Was: Body = 999 "succeeded" with 0 fragments and Body = -5 counted every body.
  expect_failure<Fragments>(frame, "the frame has no body 999", [](Fragments* f) { f->SetBody(999); });
  expect_failure<Fragments>(frame, "Body is -5", [](Fragments* f) { f->SetBody(-5); });
  for (int n : {0, -5}) {
    expect_failure<Fragments>(frame, "MinimumDisks is " + std::to_string(n),
                              [n](Fragments* f) { f->SetMinimumDisks(n); });
  }
  for (double t : {kNaN, -1.0, 0.9}) {
    expect_failure<vtkHexDEMCrackMap>(frame, "MergeTolerance is",
                                      [t](vtkHexDEMCrackMap* f) { f->SetMergeTolerance(t); });
  }
  expect_failure<vtkHexDEMCrackMap>(frame, "MaxBreakTime is nan", [](vtkHexDEMCrackMap* f) {
    f->UseMaxBreakTimeOn();
    f->SetMaxBreakTime(kNaN);
  });
  for (double p : {kNaN, -1.0, kInf}) {
    expect_failure<vtkHexDEMMaxShearStress>(frame, "PMax is",
                                            [p](vtkHexDEMMaxShearStress* f) { f->SetPMax(p); });
    expect_failure<vtkHexDEMMaxShearStress>(
        frame, "Thickness is", [p](vtkHexDEMMaxShearStress* f) { f->SetThickness(p); });
  }
  expect_failure<vtkHexDEMMaxShearStress>(frame, "1/PMax overflows",
                                          [](vtkHexDEMMaxShearStress* f) { f->SetPMax(1e-320); });
  // A tiny thickness makes the recovered stress overflow: an error, not tau = inf.
  expect_failure<vtkHexDEMMaxShearStress>(frame_with("cell", "normal_force", 1e3), "is inf",
                                          [](vtkHexDEMMaxShearStress* f) {
    f->SetStressSourceToBondForces();
    f->SetThickness(1e-300);
  });
  // The valid ends still run.
  std::unique_ptr<MessageLog> log;
  vtkSmartPointer<Fragments> filter;
  const RunSizes r = run<Fragments>(frame, log, filter, [](Fragments* f) {
    f->SetBody(0);
    f->SetMinimumDisks(1);
  });
  EXPECT_EQ(r.points, 12);
  EXPECT_TRUE(log->errors.empty()) << log->errors[0];
}

}  // namespace
