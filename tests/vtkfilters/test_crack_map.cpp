// Tests of vtkHexDEMCrackMap on lattices with known broken bonds: segment position, length
// and orientation; merged polylines along a straight crack, around a closed loop and at a
// junction; modes kept apart; per-mode counts and lengths; MaxBreakTime; contacts ignored.

#include <gtest/gtest.h>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkHexDEMCrackMap.h>
#include <vtkIdList.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "frame_builder.hpp"
#include "message_log.hpp"

namespace {

using hexdem::testing::bonds_crossing_y;
using hexdem::testing::FrameData;
using hexdem::testing::Lattice;
using hexdem::testing::make_frame;
using hexdem::testing::make_lattice;
using hexdem::testing::MessageLog;

constexpr double kR = 1e-3;
const double kSegment = 2 * kR / std::sqrt(3.0);  // nominal crack length per broken bond

double field(vtkPolyData* out, const char* name) {
  vtkDataArray* a = vtkDataArray::SafeDownCast(out->GetFieldData()->GetAbstractArray(name));
  return a ? a->GetComponent(0, 0) : std::nan("");
}

/// Runs the crack map on `frame`; `merge` selects polylines or one cell per bond.
vtkSmartPointer<vtkPolyData> crack_map(vtkUnstructuredGrid* frame, bool merge) {
  vtkNew<vtkHexDEMCrackMap> filter;
  filter->SetInputData(frame);
  filter->SetMergeSegments(merge);
  filter->Update();
  vtkSmartPointer<vtkPolyData> out = filter->GetOutput();
  return out;
}

/// Point ids of cell `c` of a poly data's lines.
std::vector<vtkIdType> cell_points(vtkPolyData* pd, vtkIdType c) {
  vtkNew<vtkIdList> ids;
  pd->GetCellPoints(c, ids);
  std::vector<vtkIdType> out;
  for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) out.push_back(ids->GetId(k));
  return out;
}

TEST(CrackMap, OneSegmentBetweenTwoDisks) {
  const Lattice lattice = make_lattice(2, 2, kR);
  FrameData data;
  data.state = {2, 0, 0, 0, 0};  // bond 0: disk 0 (0, 0) - disk 1 (2r, 0), tension
  data.break_time = {1.5e-5, -1, -1, -1, -1};
  auto out = crack_map(make_frame(lattice, data), false);
  ASSERT_EQ(out->GetNumberOfCells(), 1);
  ASSERT_EQ(out->GetNumberOfPoints(), 2);
  double p0[3], p1[3];
  out->GetPoint(0, p0);
  out->GetPoint(1, p1);
  // Centred at the contact point (r, 0), perpendicular to the bond, length 2r/sqrt(3).
  EXPECT_NEAR(0.5 * (p0[0] + p1[0]), kR, 1e-15);
  EXPECT_NEAR(0.5 * (p0[1] + p1[1]), 0.0, 1e-15);
  EXPECT_NEAR(p0[0], p1[0], 1e-15);
  EXPECT_NEAR(std::abs(p1[1] - p0[1]), kSegment, 1e-15);
  vtkCellData* cd = out->GetCellData();
  EXPECT_EQ(cd->GetArray("mode")->GetComponent(0, 0), 2);
  EXPECT_EQ(cd->GetArray("break_time")->GetComponent(0, 0), 1.5e-5);
  EXPECT_EQ(cd->GetArray("bond_id")->GetComponent(0, 0), 0);
  EXPECT_NEAR(cd->GetArray("length")->GetComponent(0, 0), kSegment, 1e-15);
  EXPECT_EQ(field(out, "crack_count"), 1);
  EXPECT_NEAR(field(out, "crack_length"), kSegment, 1e-15);
  EXPECT_EQ(field(out, "crack_count_tension"), 1);
  EXPECT_EQ(field(out, "crack_count_shear"), 0);
  EXPECT_EQ(field(out, "crack_count_compression"), 0);
  EXPECT_EQ(field(out, "crack_length_shear"), 0);
  // The frame's field data is passed through.
  EXPECT_EQ(field(out, "thickness"), 0.01);
}

TEST(CrackMap, SegmentOfUnequalDisksAndDiagonalBond) {
  Lattice lattice = make_lattice(2, 2, kR);
  FrameData data;
  data.state = {0, 4, 0, 0, 0};  // bond 1: disk 0 (0, 0) - disk 2 (r, sqrt(3) r), compression
  auto frame = make_frame(lattice, data);
  frame->GetPointData()->GetArray("radius")->SetComponent(2, 0, 3 * kR);  // r_j = 3 r_i
  auto out = crack_map(frame, false);
  ASSERT_EQ(out->GetNumberOfCells(), 1);
  double p0[3], p1[3];
  out->GetPoint(0, p0);
  out->GetPoint(1, p1);
  // Centre at x_i + r_i/(r_i + r_j) (x_j - x_i) = (r/4, sqrt(3) r/4); length 2 (2r)/sqrt(3).
  EXPECT_NEAR(0.5 * (p0[0] + p1[0]), 0.25 * kR, 1e-15);
  EXPECT_NEAR(0.5 * (p0[1] + p1[1]), 0.25 * std::sqrt(3.0) * kR, 1e-15);
  const double dx = p1[0] - p0[0], dy = p1[1] - p0[1];
  EXPECT_NEAR(std::hypot(dx, dy), 2 * kSegment, 1e-15);
  EXPECT_NEAR(dx * 0.5 + dy * std::sqrt(3.0) / 2, 0.0, 1e-15);  // perpendicular to n
  EXPECT_EQ(field(out, "crack_count_compression"), 1);
  EXPECT_NEAR(field(out, "crack_length_compression"), 2 * kSegment, 1e-15);
}

TEST(CrackMap, IntactBondsAndContactsAreNotCracks) {
  const Lattice lattice = make_lattice(2, 2, kR);
  FrameData data;
  data.state = {0, 1, 0, 1, 0};
  data.contact_i = {0};
  data.contact_j = {3};
  auto out = crack_map(make_frame(lattice, data), true);
  EXPECT_EQ(out->GetNumberOfCells(), 0);
  EXPECT_EQ(out->GetNumberOfPoints(), 0);
  EXPECT_EQ(field(out, "crack_count"), 0);
  EXPECT_EQ(field(out, "crack_length"), 0);
}

/// A 10 x 6 lattice cracked along y = 2.5 h (h = sqrt(3) r, between rows 2 and 3).
struct StraightCrack {
  Lattice lattice = make_lattice(10, 6, kR);
  std::vector<std::int64_t> bonds = bonds_crossing_y(lattice, 2.5 * std::sqrt(3.0) * kR);
  FrameData data;
  StraightCrack() {
    data.state.assign(lattice.bonds(), 0);
    data.break_time.assign(lattice.bonds(), -1.0);
    for (std::size_t k = 0; k < bonds.size(); ++k) {
      data.state[bonds[k]] = 2;
      data.break_time[bonds[k]] = 1e-6 * (k + 1);
    }
  }
};

TEST(CrackMap, StraightCrackIsOnePolyline) {
  StraightCrack crack;
  ASSERT_EQ(crack.bonds.size(), 19u);  // 10 + 9 bonds cross between rows 2 and 3
  auto out = crack_map(make_frame(crack.lattice, crack.data), true);
  ASSERT_EQ(out->GetNumberOfCells(), 1);
  const auto ids = cell_points(out, 0);
  EXPECT_EQ(ids.size(), 20u);
  EXPECT_EQ(out->GetNumberOfPoints(), 20);
  EXPECT_EQ(std::set<vtkIdType>(ids.begin(), ids.end()).size(), 20u);  // open chain
  // The crack zigzags through the cells' corners at y = 2h + h/3 and 2h + 2h/3.
  const double h = std::sqrt(3.0) * kR;
  for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p) {
    const double y = out->GetPoint(p)[1];
    EXPECT_TRUE(std::abs(y - (2 * h + h / 3)) < 1e-12 || std::abs(y - (2 * h + 2 * h / 3)) < 1e-12)
        << "point " << p << " y = " << y;
  }
  vtkCellData* cd = out->GetCellData();
  EXPECT_EQ(cd->GetArray("mode")->GetComponent(0, 0), 2);
  EXPECT_EQ(cd->GetArray("segments")->GetComponent(0, 0), 19);
  EXPECT_NEAR(cd->GetArray("length")->GetComponent(0, 0), 19 * kSegment, 1e-14);
  EXPECT_DOUBLE_EQ(cd->GetArray("break_time")->GetComponent(0, 0), 1e-6);  // earliest
  EXPECT_EQ(field(out, "crack_count"), 19);
  EXPECT_EQ(field(out, "crack_line_count"), 1);
  EXPECT_NEAR(field(out, "crack_length"), 19 * kSegment, 1e-14);
}

TEST(CrackMap, DisplacedDisksStillMerge) {
  StraightCrack crack;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.01 * kR, 0.01 * kR);
  for (std::size_t k = 0; k < crack.lattice.x.size(); ++k) {
    crack.lattice.x[k] += jitter(rng);
    crack.lattice.y[k] += jitter(rng);
  }
  auto out = crack_map(make_frame(crack.lattice, crack.data), true);
  EXPECT_EQ(out->GetNumberOfCells(), 1);
  EXPECT_EQ(out->GetNumberOfPoints(), 20);
}

TEST(CrackMap, UnmergedGivesOneCellPerBond) {
  StraightCrack crack;
  auto out = crack_map(make_frame(crack.lattice, crack.data), false);
  ASSERT_EQ(out->GetNumberOfCells(), 19);
  EXPECT_EQ(out->GetNumberOfPoints(), 38);
  vtkDataArray* bond = out->GetCellData()->GetArray("bond_id");
  for (vtkIdType c = 0; c < 19; ++c) {
    EXPECT_EQ(bond->GetComponent(c, 0), crack.bonds[c]);  // in bond order
    EXPECT_EQ(out->GetCellData()->GetArray("break_time")->GetComponent(c, 0), 1e-6 * (c + 1));
  }
}

TEST(CrackMap, ModesAreSplitIntoSeparatePolylines) {
  StraightCrack crack;
  // Bonds are ordered by their first disk, so the first 9 lie on the left: make them shear.
  for (std::size_t k = 0; k < 9; ++k) crack.data.state[crack.bonds[k]] = 3;
  auto out = crack_map(make_frame(crack.lattice, crack.data), true);
  ASSERT_EQ(out->GetNumberOfCells(), 2);
  EXPECT_EQ(out->GetNumberOfPoints(), 20);  // the two polylines share their meeting point
  vtkCellData* cd = out->GetCellData();
  int shear = -1, tension = -1;
  for (int c = 0; c < 2; ++c) (cd->GetArray("mode")->GetComponent(c, 0) == 3 ? shear : tension) = c;
  ASSERT_GE(shear, 0);
  ASSERT_GE(tension, 0);
  EXPECT_EQ(cd->GetArray("segments")->GetComponent(shear, 0), 9);
  EXPECT_EQ(cd->GetArray("segments")->GetComponent(tension, 0), 10);
  const auto a = cell_points(out, shear), b = cell_points(out, tension);
  std::set<vtkIdType> shared;
  for (vtkIdType p : a) {
    if (std::find(b.begin(), b.end(), p) != b.end()) shared.insert(p);
  }
  EXPECT_EQ(shared.size(), 1u);
  EXPECT_EQ(field(out, "crack_count_shear"), 9);
  EXPECT_EQ(field(out, "crack_count_tension"), 10);
  EXPECT_NEAR(field(out, "crack_length_shear"), 9 * kSegment, 1e-14);
  EXPECT_NEAR(field(out, "crack_length_tension"), 10 * kSegment, 1e-14);
  EXPECT_EQ(field(out, "crack_count"), 19);
}

TEST(CrackMap, IsolatedDiskGivesClosedHexagon) {
  const Lattice lattice = make_lattice(5, 5, kR);
  const std::int64_t centre = lattice.id(2, 2);
  FrameData data;
  data.state.assign(lattice.bonds(), 0);
  int broken = 0;
  for (std::int64_t b = 0; b < lattice.bonds(); ++b) {
    if (lattice.bond_i[b] == centre || lattice.bond_j[b] == centre) {
      data.state[b] = 3;
      ++broken;
    }
  }
  ASSERT_EQ(broken, 6);
  auto out = crack_map(make_frame(lattice, data), true);
  ASSERT_EQ(out->GetNumberOfCells(), 1);
  const auto ids = cell_points(out, 0);
  ASSERT_EQ(ids.size(), 7u);
  EXPECT_EQ(ids.front(), ids.back());  // closed loop
  EXPECT_EQ(out->GetNumberOfPoints(), 6);
  // The loop is the disk's cell: every corner at 2r/sqrt(3) from the centre.
  for (vtkIdType p = 0; p < 6; ++p) {
    const double* q = out->GetPoint(p);
    EXPECT_NEAR(std::hypot(q[0] - lattice.x[centre], q[1] - lattice.y[centre]), kSegment, 1e-15);
  }
  EXPECT_EQ(out->GetCellData()->GetArray("segments")->GetComponent(0, 0), 6);
}

TEST(CrackMap, JunctionEndsPolylines) {
  // The three bonds of one triangle of disks meet at its centroid: three polylines.
  const Lattice lattice = make_lattice(2, 2, kR);
  FrameData data;
  data.state = {2, 2, 2, 0, 0};  // bonds 0-1, 0-2, 1-2
  auto out = crack_map(make_frame(lattice, data), true);
  ASSERT_EQ(out->GetNumberOfCells(), 3);
  EXPECT_EQ(out->GetNumberOfPoints(), 4);
  std::vector<int> uses(4, 0);
  for (vtkIdType c = 0; c < 3; ++c) {
    for (vtkIdType p : cell_points(out, c)) ++uses[p];
  }
  EXPECT_EQ(std::count(uses.begin(), uses.end(), 3), 1);  // the centroid
  EXPECT_EQ(std::count(uses.begin(), uses.end(), 1), 3);
}

TEST(CrackMap, MaxBreakTimeKeepsEarlierBonds) {
  StraightCrack crack;
  vtkNew<vtkHexDEMCrackMap> filter;
  filter->SetInputData(make_frame(crack.lattice, crack.data));
  filter->UseMaxBreakTimeOn();
  filter->SetMaxBreakTime(5e-6);  // bonds 0..4 broke at 1..5 us
  filter->Update();
  vtkPolyData* out = filter->GetOutput();
  EXPECT_EQ(field(out, "crack_count"), 5);
  EXPECT_NEAR(field(out, "crack_length"), 5 * kSegment, 1e-14);
  filter->UseMaxBreakTimeOff();
  filter->Update();
  EXPECT_EQ(field(filter->GetOutput(), "crack_count"), 19);
}

TEST(CrackMap, MaxBreakTimeNeedsBreakTimes) {
  StraightCrack crack;
  auto frame = make_frame(crack.lattice, crack.data);
  frame->GetCellData()->RemoveArray("break_time");
  vtkNew<vtkHexDEMCrackMap> filter;
  MessageLog log(filter);
  filter->SetInputData(frame);
  filter->Update();
  EXPECT_EQ(field(filter->GetOutput(), "crack_count"), 19);  // fine without the option
  EXPECT_EQ(filter->GetOutput()->GetCellData()->GetArray("break_time")->GetComponent(0, 0), -1);
  filter->UseMaxBreakTimeOn();
  filter->Update();
  EXPECT_TRUE(log.has_error("break_time"));
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
}

TEST(CrackMap, PrintSelfListsProperties) {
  vtkNew<vtkHexDEMCrackMap> filter;
  filter->MergeSegmentsOff();
  filter->SetMergeTolerance(0.9);  // not clamped: refused when the filter runs (test_bad_input)
  filter->SetMaxBreakTime(2.5e-5);
  std::ostringstream os;
  filter->Print(os);
  for (const char* key : {"MergeSegments: Off", "MergeTolerance: 0.9", "UseMaxBreakTime: Off",
                          "MaxBreakTime: 2.5e-05"}) {
    EXPECT_NE(os.str().find(key), std::string::npos) << key;
  }
}

TEST(CrackMap, AcceptsIntegerStateOfAnyType) {
  StraightCrack crack;
  auto frame = make_frame(crack.lattice, crack.data);
  vtkNew<vtkIntArray> state;
  state->DeepCopy(frame->GetCellData()->GetArray("state"));
  state->SetName("state");
  frame->GetCellData()->AddArray(state);
  auto out = crack_map(frame, true);
  EXPECT_EQ(field(out, "crack_count"), 19);
}

}  // namespace
