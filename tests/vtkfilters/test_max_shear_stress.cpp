// Tests of vtkHexDEMMaxShearStress on four-disk frames built in code: tau_max of known
// tensors, the 3D variant, the ratio to p_max, and the stress recovered from bond forces in
// plane and axisymmetric frames, checked against hand-computed Love-Weber sums.

#include <gtest/gtest.h>

#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkHexDEMMaxShearStress.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "frame_builder.hpp"
#include "message_log.hpp"

namespace {

using hexdem::testing::FrameData;
using hexdem::testing::Lattice;
using hexdem::testing::make_frame;
using hexdem::testing::make_lattice;
using hexdem::testing::MessageLog;

constexpr double kR = 1e-3;
constexpr double kThickness = 0.01;

/// Stress tensor (row-major 3x3) from the in-plane terms, s_zz and the xz term.
std::vector<double> tensor(double xx, double yy, double xy, double zz = 0.0, double xz = 0.0) {
  return {xx, xy, xz, xy, yy, 0.0, xz, 0.0, zz};
}

/// The 2 x 2 lattice (4 disks, 5 bonds: 0-1, 0-2, 1-2, 1-3, 2-3) with the given stresses.
vtkSmartPointer<vtkUnstructuredGrid> four_disks(const std::vector<std::vector<double>>& stresses,
                                                double p_max) {
  const Lattice lattice = make_lattice(2, 2, kR);
  FrameData data;
  for (const auto& s : stresses) data.stress.insert(data.stress.end(), s.begin(), s.end());
  data.p_max = p_max;
  data.thickness = kThickness;
  return make_frame(lattice, data);
}

vtkDataArray* point_array(vtkUnstructuredGrid* grid, const char* name) {
  return grid->GetPointData()->GetArray(name);
}

TEST(MaxShearStress, InPlaneKnownTensors) {
  auto frame = four_disks(
      {tensor(100, 0, 0), tensor(0, 0, 30), tensor(10, -30, 15), tensor(-50, -50, 0, -50)}, 100.0);
  vtkNew<vtkHexDEMMaxShearStress> filter;
  filter->SetInputData(frame);
  filter->Update();
  vtkUnstructuredGrid* out = filter->GetOutput();
  ASSERT_EQ(out->GetNumberOfPoints(), 4);
  vtkDataArray* tau = point_array(out, "max_shear");
  vtkDataArray* ratio = point_array(out, "max_shear_ratio");
  ASSERT_NE(tau, nullptr);
  ASSERT_NE(ratio, nullptr);
  const double expected[] = {50.0, 30.0, 25.0, 0.0};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(tau->GetComponent(i, 0), expected[i], 1e-12) << "disk " << i;
    EXPECT_NEAR(ratio->GetComponent(i, 0), expected[i] / 100.0, 1e-14) << "disk " << i;
  }
  EXPECT_EQ(point_array(out, "max_shear_3d"), nullptr);
  EXPECT_EQ(point_array(out, "recovered_stress"), nullptr);
  // The input is untouched and every input array is passed through.
  EXPECT_EQ(point_array(frame, "max_shear"), nullptr);
  EXPECT_NE(point_array(out, "stress"), nullptr);
  EXPECT_EQ(out->GetNumberOfCells(), frame->GetNumberOfCells());
}

TEST(MaxShearStress, AsymmetricOffDiagonalTermsAreAveraged) {
  std::vector<double> s = tensor(0, 0, 0);
  s[1] = 10;  // xy
  s[3] = 30;  // yx: symmetric part 20
  auto frame = four_disks({s, s, s, s}, 0.0);
  vtkNew<vtkHexDEMMaxShearStress> filter;
  filter->SetInputData(frame);
  filter->SetPMax(40.0);
  filter->Update();
  EXPECT_NEAR(point_array(filter->GetOutput(), "max_shear")->GetComponent(0, 0), 20.0, 1e-12);
  EXPECT_NEAR(point_array(filter->GetOutput(), "max_shear_ratio")->GetComponent(0, 0), 0.5, 1e-14);
}

TEST(MaxShearStress, ThreeDimensionalFromPrincipalStresses) {
  // Equibiaxial in-plane with s_zz (tau_3d from s_zz), uniaxial, an xz shear (general
  // eigenvalue path), and an axisymmetric state with a tensile hoop stress.
  auto frame = four_disks(
      {tensor(10, 10, 0, -30), tensor(100, 0, 0), tensor(0, 0, 0, 0, 40), tensor(-20, -60, 0, 40)},
      50.0);
  vtkNew<vtkHexDEMMaxShearStress> filter;
  filter->SetInputData(frame);
  filter->ComputeThreeDimensionalOn();
  filter->Update();
  vtkUnstructuredGrid* out = filter->GetOutput();
  vtkDataArray* tau = point_array(out, "max_shear");
  vtkDataArray* tau3 = point_array(out, "max_shear_3d");
  vtkDataArray* ratio3 = point_array(out, "max_shear_3d_ratio");
  ASSERT_NE(tau3, nullptr);
  ASSERT_NE(ratio3, nullptr);
  const double in_plane[] = {0.0, 50.0, 0.0, 20.0};
  const double three_d[] = {20.0, 50.0, 40.0, 50.0};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(tau->GetComponent(i, 0), in_plane[i], 1e-12) << "disk " << i;
    EXPECT_NEAR(tau3->GetComponent(i, 0), three_d[i], 1e-9) << "disk " << i;
    EXPECT_NEAR(ratio3->GetComponent(i, 0), three_d[i] / 50.0, 1e-11) << "disk " << i;
  }
}

TEST(MaxShearStress, PMaxPropertyOverridesFieldData) {
  auto frame = four_disks(
      {tensor(100, 0, 0), tensor(100, 0, 0), tensor(100, 0, 0), tensor(100, 0, 0)}, 100.0);
  vtkNew<vtkHexDEMMaxShearStress> filter;
  filter->SetInputData(frame);
  filter->SetPMax(200.0);
  filter->Update();
  EXPECT_NEAR(point_array(filter->GetOutput(), "max_shear_ratio")->GetComponent(2, 0), 0.25, 1e-14);
}

TEST(MaxShearStress, WithoutPMaxAutomaticIsSilentAndMakesNoRatio) {
  // An impact case has no p_max: by default no ratio and no warning, on any frame.
  auto frame =
      four_disks({tensor(1, 0, 0), tensor(1, 0, 0), tensor(1, 0, 0), tensor(1, 0, 0)}, 0.0);
  vtkNew<vtkHexDEMMaxShearStress> filter;
  MessageLog log(filter);
  filter->SetInputData(frame);
  for (int frame_index = 0; frame_index < 3; ++frame_index) {
    frame->Modified();  // the next frame of a series
    filter->Update();
    EXPECT_NE(point_array(filter->GetOutput(), "max_shear"), nullptr);
    EXPECT_EQ(point_array(filter->GetOutput(), "max_shear_ratio"), nullptr);
    EXPECT_STREQ(filter->GetOutput()->GetPointData()->GetScalars()->GetName(), "max_shear");
  }
  EXPECT_TRUE(log.warnings.empty()) << log.warnings[0];
  EXPECT_TRUE(log.errors.empty());
}

TEST(MaxShearStress, RatioOnWithoutPMaxWarnsOnceUntilAPropertyChanges) {
  auto frame =
      four_disks({tensor(1, 0, 0), tensor(1, 0, 0), tensor(1, 0, 0), tensor(1, 0, 0)}, 0.0);
  vtkNew<vtkHexDEMMaxShearStress> filter;
  MessageLog log(filter);
  filter->SetInputData(frame);
  filter->SetRatioMode(vtkHexDEMMaxShearStress::RATIO_ON);
  for (int frame_index = 0; frame_index < 5; ++frame_index) {
    frame->Modified();  // every frame of a series re-executes the filter
    filter->Update();
    EXPECT_EQ(point_array(filter->GetOutput(), "max_shear_ratio"), nullptr);
  }
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_TRUE(log.has_warning("No peak pressure")) << log.warnings[0];
  // A changed setting that still leaves no p_max is worth one more warning.
  filter->SetComputeThreeDimensional(1);
  filter->Update();
  frame->Modified();
  filter->Update();
  EXPECT_EQ(log.warnings.size(), 2u);
  EXPECT_TRUE(log.errors.empty());
}

TEST(MaxShearStress, RatioOffMakesNoRatioEvenWithPMax) {
  auto frame =
      four_disks({tensor(1, 0, 0), tensor(1, 0, 0), tensor(1, 0, 0), tensor(1, 0, 0)}, 100.0);
  vtkNew<vtkHexDEMMaxShearStress> filter;
  MessageLog log(filter);
  filter->SetInputData(frame);
  filter->Update();
  EXPECT_NE(point_array(filter->GetOutput(), "max_shear_ratio"), nullptr);
  filter->SetRatioMode(vtkHexDEMMaxShearStress::RATIO_OFF);
  filter->Update();
  EXPECT_EQ(point_array(filter->GetOutput(), "max_shear_ratio"), nullptr);
  EXPECT_NE(point_array(filter->GetOutput(), "max_shear"), nullptr);
  EXPECT_TRUE(log.warnings.empty());
}

TEST(MaxShearStress, AcceptsFloat32Stress) {
  auto frame =
      four_disks({tensor(10, -30, 15), tensor(0, 0, 0), tensor(0, 0, 0), tensor(0, 0, 0)}, 0.0);
  vtkNew<vtkFloatArray> single;
  single->DeepCopy(frame->GetPointData()->GetArray("stress"));
  single->SetName("stress");
  frame->GetPointData()->AddArray(single);
  vtkNew<vtkHexDEMMaxShearStress> filter;
  filter->SetInputData(frame);
  filter->SetPMax(1.0);
  filter->Update();
  EXPECT_NEAR(point_array(filter->GetOutput(), "max_shear")->GetComponent(0, 0), 25.0, 1e-5);
}

/// Frame for the recovery tests: bond 0 (disk 0 -> 1, n = (1, 0)) in tension with shear,
/// bond 1 (0 -> 2) broken (its force must be ignored), and a compressive contact 0 -> 3
/// with n = (sqrt(3)/2, 1/2).
FrameData recovery_data() {
  FrameData data;
  data.state = {0, 2, 0, 1, 0};
  data.normal_force = {10.0, 100.0, 0.0, 0.0, 0.0};
  data.shear_force = {4.0, 50.0, 0.0, 0.0, 0.0};
  data.contact_i = {0};
  data.contact_j = {3};
  data.contact_normal_force = {-5.0};
  data.contact_shear_force = {0.0};
  data.thickness = kThickness;
  return data;
}

/// Hand-computed sums r * sym(n (x) f) per disk: {xx, yy, xy}.
std::vector<std::vector<double>> expected_sums() {
  const double s3 = std::sqrt(3.0);
  const std::vector<double> bond = {10.0 * kR, 0.0, 2.0 * kR};  // n=(1,0), f=(10,4)
  const std::vector<double> contact = {-3.75 * kR, -1.25 * kR, -1.25 * s3 * kR};  // f = -5 n
  return {{bond[0] + contact[0], bond[1] + contact[1], bond[2] + contact[2]},
          bond,
          {0.0, 0.0, 0.0},
          contact};
}

TEST(MaxShearStress, RecoversPlaneStressFromBondForces) {
  const Lattice lattice = make_lattice(2, 2, kR);
  FrameData data = recovery_data();
  auto frame = make_frame(lattice, data);
  frame->GetPointData()->RemoveArray("stress");
  vtkNew<vtkHexDEMMaxShearStress> filter;
  filter->SetInputData(frame);
  filter->SetPMax(1.0);
  filter->Update();
  vtkUnstructuredGrid* out = filter->GetOutput();
  vtkDataArray* recovered = point_array(out, "recovered_stress");
  ASSERT_NE(recovered, nullptr);
  ASSERT_EQ(recovered->GetNumberOfComponents(), 9);
  const double volume = 2 * std::sqrt(3.0) * kR * kR * kThickness;
  const auto sums = expected_sums();
  for (int i = 0; i < 4; ++i) {
    const double xx = sums[i][0] / volume, yy = sums[i][1] / volume, xy = sums[i][2] / volume;
    const double scale = 1e-9 * (std::abs(xx) + std::abs(yy) + std::abs(xy) + 1.0);
    EXPECT_NEAR(recovered->GetComponent(i, 0), xx, scale) << "disk " << i;
    EXPECT_NEAR(recovered->GetComponent(i, 4), yy, scale) << "disk " << i;
    EXPECT_NEAR(recovered->GetComponent(i, 1), xy, scale) << "disk " << i;
    EXPECT_NEAR(recovered->GetComponent(i, 3), xy, scale) << "disk " << i;
    EXPECT_EQ(recovered->GetComponent(i, 8), 0.0);
    const double tau = std::sqrt(0.25 * (xx - yy) * (xx - yy) + xy * xy);
    EXPECT_NEAR(point_array(out, "max_shear")->GetComponent(i, 0), tau, scale) << "disk " << i;
  }
}

TEST(MaxShearStress, BondForcesSourceIgnoresStressArray) {
  const Lattice lattice = make_lattice(2, 2, kR);
  FrameData data = recovery_data();
  data.stress.assign(36, 1e9);  // must not be used
  data.thickness = 0.5;         // overridden by the property below
  auto frame = make_frame(lattice, data);
  vtkNew<vtkHexDEMMaxShearStress> filter;
  filter->SetInputData(frame);
  filter->SetStressSourceToBondForces();
  filter->SetThickness(kThickness);
  filter->SetPMax(1.0);
  filter->Update();
  vtkDataArray* recovered = point_array(filter->GetOutput(), "recovered_stress");
  ASSERT_NE(recovered, nullptr);
  const double volume = 2 * std::sqrt(3.0) * kR * kR * kThickness;
  EXPECT_NEAR(recovered->GetComponent(1, 0), 10.0 * kR / volume, 1e-6);
  EXPECT_NEAR(recovered->GetComponent(1, 1), 2.0 * kR / volume, 1e-6);
}

TEST(MaxShearStress, RecoversAxisymmetricStressPerRadian) {
  Lattice lattice = make_lattice(2, 2, kR);
  const double offset = 0.02;  // ring radius of disk i = x_i
  for (double& x : lattice.x) x += offset;
  FrameData data = recovery_data();
  data.geometry = "axisymmetric";
  data.thickness = 0.0;  // not used in axisymmetric frames
  auto frame = make_frame(lattice, data);
  frame->GetPointData()->RemoveArray("stress");
  vtkNew<vtkHexDEMMaxShearStress> filter;
  MessageLog log(filter);
  filter->SetInputData(frame);
  filter->SetPMax(1.0);
  filter->Update();
  vtkDataArray* recovered = point_array(filter->GetOutput(), "recovered_stress");
  ASSERT_NE(recovered, nullptr) << (log.errors.empty() ? "" : log.errors[0]);
  const auto sums = expected_sums();
  const double area = 2 * std::sqrt(3.0) * kR * kR;
  for (int i = 0; i < 4; ++i) {
    const double volume = area * lattice.x[i];
    EXPECT_NEAR(recovered->GetComponent(i, 0), sums[i][0] / volume,
                1e-9 * (std::abs(sums[i][0] / volume) + 1))
        << "disk " << i;
    EXPECT_NEAR(recovered->GetComponent(i, 1), sums[i][2] / volume,
                1e-9 * (std::abs(sums[i][2] / volume) + 1))
        << "disk " << i;
  }
}

TEST(MaxShearStress, AxisymmetricRecoveryUsesRingRadiusArray) {
  Lattice lattice = make_lattice(2, 2, kR);  // disk 0 sits on the axis (x = 0)
  FrameData data = recovery_data();
  data.geometry = "axisymmetric";
  auto frame = make_frame(lattice, data);
  frame->GetPointData()->RemoveArray("stress");
  vtkNew<vtkDoubleArray> ring;
  ring->SetName("ring_radius");
  for (double b : {0.4 * kR, 2.1 * kR, 1.1 * kR, 3.2 * kR}) ring->InsertNextValue(b);
  frame->GetPointData()->AddArray(ring);
  vtkNew<vtkHexDEMMaxShearStress> filter;
  MessageLog log(filter);
  filter->SetInputData(frame);
  filter->Update();
  EXPECT_TRUE(log.errors.empty());
  EXPECT_FALSE(log.has_warning("volume"));
  vtkDataArray* recovered = point_array(filter->GetOutput(), "recovered_stress");
  ASSERT_NE(recovered, nullptr);
  const auto sums = expected_sums();
  const double area = 2 * std::sqrt(3.0) * kR * kR;
  for (int i = 0; i < 4; ++i) {
    const double xx = sums[i][0] / (area * ring->GetValue(i));
    EXPECT_NEAR(recovered->GetComponent(i, 0), xx, 1e-9 * (std::abs(xx) + 1)) << "disk " << i;
  }
  // Without the array, disk 0 (on the axis) has no volume: 0 and a warning.
  frame->GetPointData()->RemoveArray("ring_radius");
  filter->Modified();
  filter->Update();
  EXPECT_TRUE(log.has_warning("1 disk(s) have no positive volume"));
  EXPECT_EQ(point_array(filter->GetOutput(), "recovered_stress")->GetComponent(0, 0), 0.0);
}

TEST(MaxShearStress, RecoveryWithoutThicknessIsAnError) {
  const Lattice lattice = make_lattice(2, 2, kR);
  FrameData data = recovery_data();
  auto frame = make_frame(lattice, data);
  frame->GetPointData()->RemoveArray("stress");
  frame->GetFieldData()->RemoveArray("thickness");
  vtkNew<vtkHexDEMMaxShearStress> filter;
  MessageLog log(filter);
  filter->SetInputData(frame);
  filter->Update();
  EXPECT_TRUE(log.has_error("thickness"));
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
}

TEST(MaxShearStress, PrintSelfListsProperties) {
  vtkNew<vtkHexDEMMaxShearStress> filter;
  filter->SetStressSourceToBondForces();
  filter->SetPMax(3.5);
  std::ostringstream os;
  filter->Print(os);
  const std::string text = os.str();
  for (const char* key :
       {"StressSource: BondForces", "ComputeThreeDimensional: Off", "RatioMode: Automatic", "PMax: 3.5",
        "Thickness: 0"}) {
    EXPECT_NE(text.find(key), std::string::npos) << key;
  }
}

}  // namespace
