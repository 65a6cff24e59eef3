// Tests of vtkHexDEMFragmentCounter on lattices cut in known places: exact fragment count,
// sizes, masses, areas, centroids, mean velocities, the ordering of fragment_id (size, then
// lowest disk), MinimumDisks, and contacts and broken bonds not connecting.

#include <gtest/gtest.h>

#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkHexDEMFragmentCounter.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkUnstructuredGrid.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "frame_builder.hpp"
#include "message_log.hpp"

namespace {

using hexdem::testing::bonds_crossing_x;
using hexdem::testing::bonds_crossing_y;
using hexdem::testing::FrameData;
using hexdem::testing::Lattice;
using hexdem::testing::make_frame;
using hexdem::testing::make_lattice;
using hexdem::testing::MessageLog;

constexpr double kR = 1e-3;

double field(vtkFieldData* fd, const char* name) {
  vtkDataArray* a = vtkDataArray::SafeDownCast(fd->GetAbstractArray(name));
  return a ? a->GetComponent(0, 0) : std::nan("");
}

double column(vtkTable* t, const char* name, vtkIdType row) {
  return t->GetColumnByName(name)->GetVariantValue(row).ToDouble();
}

/// A 12 x 10 lattice cut between rows 3 and 4 and at x = 11.5 r (6 disks left, 6 right in
/// every row), with disk (2, 7) isolated, contacts across the cuts and a yielded bond:
/// fragments of 36 (top right), 35 (top left), 24, 24 (bottom) and 1 disk.
struct CutLattice {
  Lattice lattice = make_lattice(12, 10, kR);
  FrameData data;
  std::int64_t lonely = lattice.id(2, 7);
  CutLattice() {
    data.state.assign(lattice.bonds(), 0);
    for (auto b : bonds_crossing_y(lattice, 3.5 * std::sqrt(3.0) * kR)) data.state[b] = 2;
    for (auto b : bonds_crossing_x(lattice, 11.5 * kR)) data.state[b] = 3;
    for (std::int64_t b = 0; b < lattice.bonds(); ++b) {
      if (lattice.bond_i[b] == lonely || lattice.bond_j[b] == lonely) data.state[b] = 4;
    }
    data.state[0] = 1;  // yielded but intact: still connects
    data.contact_i = {lattice.id(5, 8), lattice.id(2, 3), lonely};
    data.contact_j = {lattice.id(6, 8), lattice.id(2, 4), lattice.id(3, 7)};
    for (std::int64_t k = 0; k < lattice.disks(); ++k) {
      data.velocity.insert(data.velocity.end(), {1.0 + lattice.x[k], -lattice.y[k], 0.0});
    }
    data.density = 2400.0;
    data.thickness = 0.02;
  }
  /// Which fragment a disk belongs to, by construction.
  int region(std::int64_t k) const {
    if (k == lonely) return 4;
    const bool top = k / lattice.nx >= 4;
    const bool right = k % lattice.nx >= 6;
    return top ? (right ? 0 : 1) : (right ? 3 : 2);
  }
};

TEST(FragmentCounter, IntactLatticeIsOneFragment) {
  const Lattice lattice = make_lattice(7, 5, kR);
  vtkNew<vtkHexDEMFragmentCounter> filter;
  filter->SetInputData(make_frame(lattice, FrameData{}));
  filter->Update();
  EXPECT_EQ(field(filter->GetOutput()->GetFieldData(), "fragment_count"), 1);
  EXPECT_EQ(filter->GetTableOutput()->GetNumberOfRows(), 1);
  EXPECT_EQ(column(filter->GetTableOutput(), "disks", 0), 35);
  vtkDataArray* ids = filter->GetOutput()->GetPointData()->GetArray("fragment_id");
  ASSERT_NE(ids, nullptr);
  EXPECT_EQ(ids->GetRange()[0], 0);
  EXPECT_EQ(ids->GetRange()[1], 0);
}

TEST(FragmentCounter, CutLatticeGivesKnownFragments) {
  CutLattice cut;
  auto frame = make_frame(cut.lattice, cut.data);
  vtkNew<vtkHexDEMFragmentCounter> filter;
  MessageLog log(filter);
  filter->SetInputData(frame);
  filter->Update();
  EXPECT_TRUE(log.errors.empty());
  EXPECT_TRUE(log.warnings.empty());
  vtkUnstructuredGrid* out = filter->GetOutput();
  EXPECT_EQ(field(out->GetFieldData(), "fragment_count"), 5);
  EXPECT_EQ(field(out->GetFieldData(), "fragment_count_total"), 5);
  EXPECT_EQ(field(out->GetFieldData(), "time"), 0.0);                       // passed through
  EXPECT_TRUE(std::isnan(field(frame->GetFieldData(), "fragment_count")));  // input untouched

  // fragment_id: 0 = top right (36 disks), 1 = top left (35), 2 = bottom left (24, lowest
  // disk 0), 3 = bottom right (24, lowest disk 6), 4 = the isolated disk.
  vtkDataArray* ids = out->GetPointData()->GetArray("fragment_id");
  ASSERT_NE(ids, nullptr);
  for (std::int64_t k = 0; k < cut.lattice.disks(); ++k) {
    ASSERT_EQ(ids->GetComponent(k, 0), cut.region(k)) << "disk " << k;
  }

  vtkTable* table = filter->GetTableOutput();
  ASSERT_EQ(table->GetNumberOfRows(), 5);
  const double area = 2 * std::sqrt(3.0) * kR * kR;
  const double disk_mass = 2400.0 * area * 0.02;
  const int sizes[] = {36, 35, 24, 24, 1};
  for (int f = 0; f < 5; ++f) {
    double sx = 0, sy = 0;
    for (std::int64_t k = 0; k < cut.lattice.disks(); ++k) {
      if (cut.region(k) == f) {
        sx += cut.lattice.x[k];
        sy += cut.lattice.y[k];
      }
    }
    const double cx = sx / sizes[f], cy = sy / sizes[f];
    EXPECT_EQ(column(table, "fragment_id", f), f);
    EXPECT_EQ(column(table, "disks", f), sizes[f]) << "fragment " << f;
    EXPECT_NEAR(column(table, "mass", f), sizes[f] * disk_mass, 1e-15) << "fragment " << f;
    EXPECT_NEAR(column(table, "area", f), sizes[f] * area, 1e-18) << "fragment " << f;
    EXPECT_NEAR(column(table, "centroid_x", f), cx, 1e-15) << "fragment " << f;
    EXPECT_NEAR(column(table, "centroid_y", f), cy, 1e-15) << "fragment " << f;
    EXPECT_NEAR(column(table, "velocity_x", f), 1.0 + cx, 1e-13) << "fragment " << f;
    EXPECT_NEAR(column(table, "velocity_y", f), -cy, 1e-13) << "fragment " << f;
    EXPECT_NEAR(column(table, "equivalent_diameter", f),
                2 * std::sqrt(sizes[f] * area / std::numbers::pi), 1e-15);
  }
  EXPECT_EQ(field(table->GetFieldData(), "fragment_count"), 5);
}

TEST(FragmentCounter, MinimumDisksCountsOnlyLargeFragments) {
  CutLattice cut;
  vtkNew<vtkHexDEMFragmentCounter> filter;
  filter->SetInputData(make_frame(cut.lattice, cut.data));
  filter->SetMinimumDisks(25);
  filter->Update();
  vtkUnstructuredGrid* out = filter->GetOutput();
  EXPECT_EQ(field(out->GetFieldData(), "fragment_count"), 2);
  EXPECT_EQ(field(out->GetFieldData(), "fragment_count_total"), 5);
  EXPECT_EQ(filter->GetTableOutput()->GetNumberOfRows(), 2);
  // Smaller fragments keep their ids.
  EXPECT_EQ(out->GetPointData()->GetArray("fragment_id")->GetComponent(cut.lonely, 0), 4);
  EXPECT_EQ(out->GetPointData()->GetArray("fragment_id")->GetComponent(0, 0), 2);
}

TEST(FragmentCounter, AllBondsBrokenGivesSingleDisks) {
  const Lattice lattice = make_lattice(6, 4, kR);
  FrameData data;
  data.state.assign(lattice.bonds(), 2);
  vtkNew<vtkHexDEMFragmentCounter> filter;
  filter->SetInputData(make_frame(lattice, data));
  filter->Update();
  EXPECT_EQ(field(filter->GetOutput()->GetFieldData(), "fragment_count"), 24);
  vtkDataArray* ids = filter->GetOutput()->GetPointData()->GetArray("fragment_id");
  for (vtkIdType k = 0; k < 24; ++k) EXPECT_EQ(ids->GetComponent(k, 0), k);  // ties: lowest disk
  EXPECT_EQ(column(filter->GetTableOutput(), "disks", 23), 1);
}

TEST(FragmentCounter, MissingMassGivesNaNColumnsAndAWarning) {
  CutLattice cut;
  auto frame = make_frame(cut.lattice, cut.data);
  frame->GetPointData()->RemoveArray("mass");
  vtkNew<vtkHexDEMFragmentCounter> filter;
  MessageLog log(filter);
  filter->SetInputData(frame);
  filter->Update();
  EXPECT_TRUE(log.has_warning("'mass'"));
  EXPECT_EQ(field(filter->GetOutput()->GetFieldData(), "fragment_count"), 5);
  EXPECT_TRUE(std::isnan(column(filter->GetTableOutput(), "mass", 0)));
  EXPECT_TRUE(std::isnan(column(filter->GetTableOutput(), "velocity_x", 0)));
  EXPECT_FALSE(std::isnan(column(filter->GetTableOutput(), "centroid_x", 0)));
}

/// The cut lattice with its top-right fragment (region 0, 36 disks) as a second body,
/// "projectile", and the rest as "target"; body_names as the solver writes it.
vtkSmartPointer<vtkUnstructuredGrid> two_bodies(const CutLattice& cut, bool names = true) {
  auto frame = make_frame(cut.lattice, cut.data);
  vtkDataArray* body = frame->GetPointData()->GetArray("body");
  for (std::int64_t k = 0; k < cut.lattice.disks(); ++k) body->SetComponent(k, 0, cut.region(k) == 0 ? 1 : 0);
  if (names) {
    vtkNew<vtkStringArray> body_names;
    body_names->SetName("body_names");
    body_names->InsertNextValue("target");
    body_names->InsertNextValue("projectile");
    frame->GetFieldData()->AddArray(body_names);
  }
  return frame;
}

TEST(FragmentCounter, TableNamesTheBodyOfEveryFragment) {
  CutLattice cut;
  vtkNew<vtkHexDEMFragmentCounter> filter;
  filter->SetInputData(two_bodies(cut));
  filter->Update();
  vtkTable* table = filter->GetTableOutput();
  ASSERT_EQ(table->GetNumberOfRows(), 5);
  ASSERT_NE(table->GetColumnByName("body"), nullptr);
  ASSERT_NE(table->GetColumnByName("body_name"), nullptr);
  EXPECT_EQ(column(table, "disks", 0), 36);
  EXPECT_EQ(column(table, "body", 0), 1);
  EXPECT_EQ(table->GetValueByName(0, "body_name").ToString(), "projectile");
  for (vtkIdType row = 1; row < 5; ++row) {
    EXPECT_EQ(column(table, "body", row), 0) << row;
    EXPECT_EQ(table->GetValueByName(row, "body_name").ToString(), "target") << row;
  }
  // Without body_names (frames of other tools): no body columns, the table as before.
  filter->SetInputData(two_bodies(cut, false));
  filter->Update();
  EXPECT_EQ(filter->GetTableOutput()->GetColumnByName("body"), nullptr);
  EXPECT_EQ(filter->GetTableOutput()->GetColumnByName("body_name"), nullptr);
  EXPECT_EQ(filter->GetTableOutput()->GetNumberOfColumns(), 9);
}

TEST(FragmentCounter, BodySelectionLeavesTheProjectileOut) {
  CutLattice cut;
  auto frame = two_bodies(cut);
  vtkNew<vtkHexDEMFragmentCounter> filter;
  MessageLog log(filter);
  filter->SetInputData(frame);
  filter->SetBodyName("target");
  filter->Update();
  vtkUnstructuredGrid* out = filter->GetOutput();
  EXPECT_EQ(field(out->GetFieldData(), "fragment_count"), 4);
  EXPECT_EQ(field(out->GetFieldData(), "fragment_count_total"), 4);
  EXPECT_EQ(field(out->GetFieldData(), "single_disk_fragments"), 1);
  vtkTable* table = filter->GetTableOutput();
  ASSERT_EQ(table->GetNumberOfRows(), 4);
  EXPECT_EQ(column(table, "disks", 0), 35);  // the target's largest piece is fragment 0
  EXPECT_EQ(column(table, "disks", 3), 1);
  vtkDataArray* ids = out->GetPointData()->GetArray("fragment_id");
  vtkDataArray* sizes = out->GetPointData()->GetArray("fragment_disks");
  for (std::int64_t k = 0; k < cut.lattice.disks(); ++k) {
    if (cut.region(k) == 0) {
      EXPECT_EQ(ids->GetComponent(k, 0), -1) << k;
      EXPECT_EQ(sizes->GetComponent(k, 0), 0) << k;
    } else {
      EXPECT_GE(ids->GetComponent(k, 0), 0) << k;
    }
  }
  // The same by index; and the projectile alone.
  filter->SetBodyName(nullptr);
  filter->SetBody(0);
  filter->Update();
  EXPECT_EQ(field(filter->GetOutput()->GetFieldData(), "fragment_count"), 4);
  filter->SetBody(1);
  filter->Update();
  EXPECT_EQ(field(filter->GetOutput()->GetFieldData(), "fragment_count"), 1);
  EXPECT_EQ(column(filter->GetTableOutput(), "disks", 0), 36);
  EXPECT_TRUE(log.errors.empty());
}

TEST(FragmentCounter, UnknownBodyNameIsAnErrorNamingTheBodies) {
  CutLattice cut;
  vtkNew<vtkHexDEMFragmentCounter> filter;
  MessageLog log(filter);
  filter->SetInputData(two_bodies(cut));
  filter->SetBodyName("nose");
  filter->Update();
  EXPECT_TRUE(log.has_error("no body named 'nose' (bodies: target, projectile)"))
      << (log.errors.empty() ? "" : log.errors[0]);
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  // A body selection without a 'body' array.
  auto frame = two_bodies(cut);
  frame->GetPointData()->RemoveArray("body");
  filter->SetInputData(frame);
  filter->SetBodyName(nullptr);
  filter->SetBody(0);
  filter->Update();
  EXPECT_TRUE(log.has_error("needs the 'body' point array"));
}

TEST(FragmentCounter, FragmentDisksSeparatesSingleDiskDebris) {
  CutLattice cut;
  vtkNew<vtkHexDEMFragmentCounter> filter;
  filter->SetInputData(make_frame(cut.lattice, cut.data));
  filter->Update();
  vtkUnstructuredGrid* out = filter->GetOutput();
  vtkDataArray* sizes = out->GetPointData()->GetArray("fragment_disks");
  ASSERT_NE(sizes, nullptr);
  const int expected[] = {36, 35, 24, 24, 1};
  for (std::int64_t k = 0; k < cut.lattice.disks(); ++k) {
    EXPECT_EQ(sizes->GetComponent(k, 0), expected[cut.region(k)]) << k;
  }
  EXPECT_EQ(field(out->GetFieldData(), "single_disk_fragments"), 1);
  EXPECT_EQ(field(filter->GetTableOutput()->GetFieldData(), "single_disk_fragments"), 1);
  // ParaView colours by the active scalars when the output is first shown.
  ASSERT_NE(out->GetPointData()->GetScalars(), nullptr);
  EXPECT_STREQ(out->GetPointData()->GetScalars()->GetName(), "fragment_id");
}

TEST(FragmentCounter, PrintSelfListsProperties) {
  vtkNew<vtkHexDEMFragmentCounter> filter;
  filter->SetMinimumDisks(7);
  std::ostringstream os;
  filter->Print(os);
  EXPECT_NE(os.str().find("MinimumDisks: 7"), std::string::npos);
  EXPECT_NE(os.str().find("Body: -1"), std::string::npos);
  EXPECT_NE(os.str().find("BodyName: (none)"), std::string::npos);
  filter->SetMinimumDisks(0);  // not clamped: refused when the filter runs (test_bad_input)
  EXPECT_EQ(filter->GetMinimumDisks(), 0);
}

}  // namespace
