#include "vtkHexDEMMaxShearStress.h"

#include "vtkHexDEMFrameInternals.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkHexDEMMaxShearStress);

namespace {
using namespace vtkHexDEMInternals;

/// In-plane maximum shear of a row-major 3x3 stress tensor (physics.md section 6).
inline double InPlaneMaxShear(const double* s) {
  const double half_difference = 0.5 * (s[0] - s[4]);
  const double s_xy = 0.5 * (s[1] + s[3]);
  return std::sqrt(half_difference * half_difference + s_xy * s_xy);
}

/// (s_1 - s_3)/2 of the symmetrised tensor. Exact for the in-plane tensors of hexdem frames
/// (xz = yz = 0), where the principal stresses are c +- tau_max and s_zz.
inline double ThreeDimensionalMaxShear(const double* s) {
  const double s_xz = 0.5 * (s[2] + s[6]);
  const double s_yz = 0.5 * (s[5] + s[7]);
  if (s_xz == 0.0 && s_yz == 0.0) {
    const double tau = InPlaneMaxShear(s);
    const double centre = 0.5 * (s[0] + s[4]);
    const double high = std::max(centre + tau, s[8]);
    const double low = std::min(centre - tau, s[8]);
    return 0.5 * (high - low);
  }
  const double s_xy = 0.5 * (s[1] + s[3]);
  const double a[3][3] = {{s[0], s_xy, s_xz}, {s_xy, s[4], s_yz}, {s_xz, s_yz, s[8]}};
  double w[3];
  double v[3][3];
  vtkMath::Diagonalize3x3(a, w, v);
  return 0.5 * (std::max({w[0], w[1], w[2]}) - std::min({w[0], w[1], w[2]}));
}

/// Per-disk kernel: max_shear (and max_shear_3d, and the ratios when p_max > 0).
struct MaxShearKernel {
  const double* Stress;
  double* Tau;
  double* Tau3D;       // null unless requested
  double* Ratio;       // null without p_max
  double* Ratio3D;     // null without p_max or 3D
  double InversePMax;  // 1 / p_max
  vtkHexDEMMaxShearStress* Filter;

  void operator()(vtkIdType begin, vtkIdType end) const {
    const bool isFirst = vtkSMPTools::GetSingleThread();
    const vtkIdType interval = std::min<vtkIdType>((end - begin) / 10 + 1, 100000);
    for (vtkIdType i = begin; i < end; ++i) {
      if (i % interval == 0) {
        if (isFirst) {
          this->Filter->CheckAbort();
        }
        if (this->Filter->GetAbortOutput()) {
          return;
        }
      }
      const double* s = this->Stress + 9 * i;
      const double tau = InPlaneMaxShear(s);
      this->Tau[i] = tau;
      if (this->Ratio) {
        this->Ratio[i] = tau * this->InversePMax;
      }
      if (this->Tau3D) {
        const double tau3 = ThreeDimensionalMaxShear(s);
        this->Tau3D[i] = tau3;
        if (this->Ratio3D) {
          this->Ratio3D[i] = tau3 * this->InversePMax;
        }
      }
    }
  }
};

vtkSmartPointer<vtkDoubleArray> NewPointArray(const char* name, vtkIdType n, int components = 1) {
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(n);
  return array;
}

}  // namespace

vtkHexDEMMaxShearStress::vtkHexDEMMaxShearStress()
    : StressSource(STRESS_AUTOMATIC),
      ComputeThreeDimensional(0),
      PMax(0.0),
      Thickness(0.0),
      RatioMode(RATIO_AUTOMATIC),
      NoPMaxWarningTime(0) {}

vtkHexDEMMaxShearStress::~vtkHexDEMMaxShearStress() = default;

int vtkHexDEMMaxShearStress::RequestData(vtkInformation* vtkNotUsed(request),
                                         vtkInformationVector** inputVector,
                                         vtkInformationVector* outputVector) {
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  if (!input || !output) {
    vtkErrorMacro("Input or output is not an unstructured grid.");
    return 0;
  }
  try {
    const int status = this->Execute(input, output);
    if (status == 0) {
      output->Initialize();
    }
    return status;
  } catch (const std::exception& e) {
    output->Initialize();
    vtkErrorMacro("Failed: " << e.what());
    return 0;
  }
}

int vtkHexDEMMaxShearStress::Execute(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output) {
  const vtkIdType numDisks = input->GetNumberOfPoints();
  if (numDisks == 0) {
    vtkErrorMacro("The input frame has no disks (empty grid).");
    return 0;
  }
  // The properties: finite, >= 0, and 1/PMax must not overflow.
  for (const auto& property : {std::make_pair("PMax", this->PMax),
                               std::make_pair("Thickness", this->Thickness)}) {
    if (!(std::isfinite(property.second) && property.second >= 0)) {
      vtkErrorMacro("Bad property: " << property.first << " is "
                                     << FormatNumber(property.second)
                                     << " (expected a finite number >= 0; 0: from the frame).");
      return 0;
    }
  }
  if (this->PMax > 0 && !std::isfinite(1.0 / this->PMax)) {
    vtkErrorMacro("Bad property: PMax is " << FormatNumber(this->PMax)
                                           << " (too small: 1/PMax overflows).");
    return 0;
  }
  std::string error;
  {
    DoubleValues points;
    if (!points.Load(input->GetPoints()->GetData(), 3, numDisks, "point coordinates", error) ||
        !CheckFieldNumbers(input->GetFieldData(), error)) {
      vtkErrorMacro("Bad input: " << error << ".");
      return 0;
    }
  }
  vtkPointData* inPD = input->GetPointData();
  vtkDataArray* stressArray = inPD->GetArray("stress");
  const bool recover = this->StressSource == STRESS_BOND_FORCES ||
                       (this->StressSource == STRESS_AUTOMATIC && !stressArray);
  if (!recover && !stressArray) {
    vtkErrorMacro(
        "The input frame has no 'stress' point array (9 components, Pa); is it a "
        "hexdem result frame? (The stress source 'bond forces' recovers the stress "
        "from the bond forces.)");
    return 0;
  }

  DoubleValues stress;
  std::vector<double> recovered;
  if (recover) {
    LineCells lines;
    DoubleValues points;
    DoubleValues radius;
    DoubleValues cellArea;
    DoubleValues normalForce;
    DoubleValues shearForce;
    ByteValues state;
    const vtkIdType numCells = input->GetNumberOfCells();
    vtkCellData* inCD = input->GetCellData();
    if (!points.Load(input->GetPoints()->GetData(), 3, numDisks, "point coordinates", error) ||
        !radius.Load(inPD->GetArray("radius"), 1, numDisks, "'radius' point", error,
                     Domain::Positive) ||
        !cellArea.Load(inPD->GetArray("cell_area"), 1, numDisks, "'cell_area' point", error,
                       Domain::NonNegative) ||
        !lines.Load(input, error) ||
        !state.Load(inCD->GetArray("state"), numCells, "'state' cell", error, Contact) ||
        !normalForce.Load(inCD->GetArray("normal_force"), 1, numCells, "'normal_force' cell",
                          error) ||
        !shearForce.Load(inCD->GetArray("shear_force"), 1, numCells, "'shear_force' cell", error)) {
      vtkErrorMacro("Cannot recover the stress from the bond forces: " << error << ".");
      return 0;
    }
    vtkFieldData* fd = input->GetFieldData();
    const bool axisymmetric = IsAxisymmetric(fd);
    // Ring radius of each disk in axisymmetric frames: the `ring_radius` point array when the
    // frame has one (the cell centroid's distance from the axis), else the point's x.
    DoubleValues ringRadius;
    const bool hasRingRadius = axisymmetric && inPD->GetArray("ring_radius");
    if (hasRingRadius && !ringRadius.Load(inPD->GetArray("ring_radius"), 1, numDisks,
                                          "'ring_radius' point", error,
                                          Domain::NonNegative)) {
      vtkErrorMacro("Cannot recover the stress from the bond forces: " << error << ".");
      return 0;
    }
    double thickness = this->Thickness;
    if (!axisymmetric && !(thickness > 0)) {
      bool found = false;
      thickness = FieldNumber(fd, "thickness", found);
      if (!found || !(thickness > 0)) {
        vtkErrorMacro(
            "Cannot recover the stress of a plane frame from the bond forces: no "
            "positive 'thickness' field data and the Thickness property is 0.");
        return 0;
      }
    }

    // Sum of r sym(n (x) f) per disk (in-plane terms xx, yy, xy), over intact bonds and
    // contacts; both disks of a cell get the same dyad scaled by their own radius.
    std::vector<double> sum(static_cast<std::size_t>(3 * numDisks), 0.0);
    const double* x = points.Data();
    const double* r = radius.Data();
    const double* fn = normalForce.Data();
    const double* fs = shearForce.Data();
    const std::uint8_t* st = state.Data();
    AbortCheck abort(this, 1 << 20);
    for (vtkIdType c = 0; c < numCells; ++c) {
      if (abort(c)) {
        return 0;
      }
      if (!(IsIntact(st[c]) || st[c] == Contact)) {
        continue;
      }
      const vtkIdType i = lines.First(c);
      const vtkIdType j = lines.Second(c);
      const double dx = x[3 * j] - x[3 * i];
      const double dy = x[3 * j + 1] - x[3 * i + 1];
      const double length = std::sqrt(dx * dx + dy * dy);
      if (!(length > 0)) {
        continue;
      }
      const double nx = dx / length;
      const double ny = dy / length;
      // Force on i: f_n n + f_s s with s = (-n_y, n_x).
      const double fx = fn[c] * nx - fs[c] * ny;
      const double fy = fn[c] * ny + fs[c] * nx;
      const double dxx = nx * fx;
      const double dyy = ny * fy;
      const double dxy = 0.5 * (nx * fy + ny * fx);
      double* si = &sum[static_cast<std::size_t>(3 * i)];
      double* sj = &sum[static_cast<std::size_t>(3 * j)];
      si[0] += r[i] * dxx;
      si[1] += r[i] * dyy;
      si[2] += r[i] * dxy;
      sj[0] += r[j] * dxx;
      sj[1] += r[j] * dyy;
      sj[2] += r[j] * dxy;
    }
    recovered.assign(static_cast<std::size_t>(9 * numDisks), 0.0);
    const double* area = cellArea.Data();
    const double* ring = hasRingRadius ? ringRadius.Data() : nullptr;
    vtkIdType unusable = 0;
    for (vtkIdType i = 0; i < numDisks; ++i) {
      const double volume = area[i] * (axisymmetric ? (ring ? ring[i] : x[3 * i]) : thickness);
      if (!(volume > 0)) {
        ++unusable;
        continue;
      }
      const double* s = &sum[static_cast<std::size_t>(3 * i)];
      double* out = &recovered[static_cast<std::size_t>(9 * i)];
      out[0] = s[0] / volume;
      out[4] = s[1] / volume;
      out[1] = out[3] = s[2] / volume;
    }
    // Forces over a tiny volume (e.g. a thickness of 1e-300 m) overflow: not a result.
    const vtkIdType overflow = FirstOutside(recovered.data(), 9 * numDisks, Domain::Finite);
    if (overflow >= 0) {
      const vtkIdType disk = overflow / 9;
      vtkErrorMacro("Bad input: the stress recovered for disk "
                    << disk << " is " << FormatNumber(recovered[overflow]) << " (cell_area "
                    << FormatNumber(area[disk]) << " m^2 times "
                    << (axisymmetric ? "ring radius " : "thickness ")
                    << FormatNumber(axisymmetric ? (ring ? ring[disk] : x[3 * disk]) : thickness)
                    << " m is too small a volume).");
      return 0;
    }
    if (unusable > 0) {
      vtkWarningMacro(<< unusable << " disk(s) have no positive volume (cell_area * "
                      << (axisymmetric ? "ring radius" : "thickness")
                      << "); their recovered stress is set to 0.");
    }
  } else if (!stress.Load(stressArray, 9, numDisks, "'stress' point", error, Domain::Finite)) {
    vtkErrorMacro("Bad input: " << error << " (a 3x3 tensor per disk, Pa).");
    return 0;
  }
  const double* stressData = recover ? recovered.data() : stress.Data();

  // p_max: the property overrides the field data. A missing p_max is only worth a warning
  // when the ratio was asked for (RatioMode On), and then once for the current settings:
  // not on every frame of a series (the filter's MTime does not change with the time step).
  double pMax = 0.0;
  if (this->RatioMode != RATIO_OFF) {
    pMax = this->PMax;
    if (!(pMax > 0)) {
      bool found = false;
      pMax = FieldNumber(input->GetFieldData(), "p_max", found);
      if (!found || !(pMax > 0)) {
        pMax = 0.0;
        if (this->RatioMode == RATIO_ON && this->NoPMaxWarningTime != this->GetMTime()) {
          this->NoPMaxWarningTime = this->GetMTime();
          vtkWarningMacro(
              "No peak pressure: the frame has no positive 'p_max' field data and the "
              "PMax property is 0, so 'max_shear_ratio' is not computed.");
        }
      }
    }
  }

  output->ShallowCopy(input);
  vtkPointData* outPD = output->GetPointData();
  auto tau = NewPointArray("max_shear", numDisks);
  vtkSmartPointer<vtkDoubleArray> tau3, ratio, ratio3;
  if (this->ComputeThreeDimensional) {
    tau3 = NewPointArray("max_shear_3d", numDisks);
  }
  if (pMax > 0) {
    ratio = NewPointArray("max_shear_ratio", numDisks);
    if (tau3) {
      ratio3 = NewPointArray("max_shear_3d_ratio", numDisks);
    }
  }
  MaxShearKernel kernel{stressData,
                        tau->GetPointer(0),
                        tau3 ? tau3->GetPointer(0) : nullptr,
                        ratio ? ratio->GetPointer(0) : nullptr,
                        ratio3 ? ratio3->GetPointer(0) : nullptr,
                        pMax > 0 ? 1.0 / pMax : 0.0,
                        this};
  vtkSMPTools::For(0, numDisks, kernel);
  if (this->GetAbortOutput()) {
    return 0;
  }
  // Finite stresses can still overflow (s_xx - s_yy of two values near DBL_MAX), and so can
  // tau / p_max: an infinite result is not a result.
  for (vtkDoubleArray* result : {tau.GetPointer(), tau3.GetPointer(), ratio.GetPointer(),
                                 ratio3.GetPointer()}) {
    if (!result) {
      continue;
    }
    const vtkIdType bad = FirstOutside(result->GetPointer(0), numDisks, Domain::Finite);
    if (bad >= 0) {
      vtkErrorMacro("Bad input: '" << result->GetName() << "' of disk " << bad << " is "
                                   << FormatNumber(result->GetValue(bad))
                                   << " (the stress of that disk, or 1/p_max, is too large).");
      return 0;
    }
  }

  if (recover) {
    auto copy = NewPointArray("recovered_stress", numDisks, 9);
    std::copy(recovered.begin(), recovered.end(), copy->GetPointer(0));
    outPD->AddArray(copy);
  }
  outPD->AddArray(tau);
  if (tau3) {
    outPD->AddArray(tau3);
  }
  if (ratio) {
    outPD->AddArray(ratio);
  }
  if (ratio3) {
    outPD->AddArray(ratio3);
  }
  outPD->SetActiveScalars(ratio ? "max_shear_ratio" : "max_shear");
  return 1;
}

void vtkHexDEMMaxShearStress::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  const char* sources[] = {"Automatic", "PointArray", "BondForces"};
  os << indent << "StressSource: " << sources[this->StressSource] << "\n";
  os << indent << "ComputeThreeDimensional: " << (this->ComputeThreeDimensional ? "On" : "Off")
     << "\n";
  const char* ratioModes[] = {"Automatic", "On", "Off"};
  os << indent << "RatioMode: " << ratioModes[this->RatioMode] << "\n";
  os << indent << "PMax: " << this->PMax << "\n";
  os << indent << "Thickness: " << this->Thickness << "\n";
}
