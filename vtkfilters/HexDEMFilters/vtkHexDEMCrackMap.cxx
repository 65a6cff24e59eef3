#include "vtkHexDEMCrackMap.h"

#include "vtkHexDEMFrameInternals.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkHexDEMCrackMap);

namespace {
using namespace vtkHexDEMInternals;

constexpr std::array<const char*, 3> kModeNames = {"tension", "shear", "compression"};

/// The segments of the broken bonds, structure of arrays, in bond order.
struct Segments {
  std::vector<vtkIdType> Bond;
  std::vector<double> Ends;    // 6 per segment: end 0 (x, y, z), end 1 (x, y, z)
  std::vector<double> Length;  // nominal length 2 r / sqrt(3) [m]
  std::vector<double> BreakTime;
  std::vector<std::uint8_t> Mode;
  double MinRadius = std::numeric_limits<double>::infinity();  // smallest mean radius

  std::size_t Size() const { return this->Bond.size(); }
};

/// Merges points closer than a tolerance: a uniform grid of cells of twice the tolerance,
/// hashed with open addressing; each cell chains the representatives inserted in it. A
/// point within the tolerance of a representative lies in one of the 2x2 cells nearest to
/// it, so a query probes 4 cells. The first point of a cluster is its representative, so
/// the result depends only on the order of insertion (bond order), not on threads.
class PointMerger {
 public:
  PointMerger(std::size_t expected, double tolerance, double scale)
      : Tolerance2(tolerance * tolerance),
        InverseCell(1.0 / (tolerance > 0 ? 2.0 * tolerance : scale)) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected) {
      capacity *= 2;
    }
    this->Keys.assign(capacity, kEmpty);
    this->Heads.assign(capacity, -1);
    this->Points.reserve(3 * expected);
    this->Next.reserve(expected);
  }

  /// Index of the representative within the tolerance of p, inserting p when there is none.
  vtkIdType FindOrInsert(const double* p) {
    const double gx = p[0] * this->InverseCell;
    const double gy = p[1] * this->InverseCell;
    const std::int64_t x0 = static_cast<std::int64_t>(std::floor(gx - 0.5));
    const std::int64_t y0 = static_cast<std::int64_t>(std::floor(gy - 0.5));
    for (std::int64_t ix = x0; ix <= x0 + 1; ++ix) {
      for (std::int64_t iy = y0; iy <= y0 + 1; ++iy) {
        const std::size_t slot = this->Find(Key(ix, iy));
        if (this->Keys[slot] == kEmpty) {
          continue;
        }
        for (vtkIdType v = this->Heads[slot]; v >= 0; v = this->Next[static_cast<std::size_t>(v)]) {
          const double* q = &this->Points[static_cast<std::size_t>(3 * v)];
          const double dx = p[0] - q[0];
          const double dy = p[1] - q[1];
          const double dz = p[2] - q[2];
          if (dx * dx + dy * dy + dz * dz <= this->Tolerance2) {
            return v;
          }
        }
      }
    }
    const vtkIdType v = static_cast<vtkIdType>(this->Next.size());
    this->Points.insert(this->Points.end(), p, p + 3);
    const std::size_t slot = this->Find(
        Key(static_cast<std::int64_t>(std::floor(gx)), static_cast<std::int64_t>(std::floor(gy))));
    this->Keys[slot] = this->LastKey;
    this->Next.push_back(this->Heads[slot]);
    this->Heads[slot] = v;
    return v;
  }

  const std::vector<double>& GetPoints() const { return this->Points; }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);

  std::uint64_t Key(std::int64_t ix, std::int64_t iy) {
    this->LastKey = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix)) << 32) |
                    static_cast<std::uint32_t>(iy);
    if (this->LastKey == kEmpty) {
      this->LastKey = kEmpty - 1;  // a harmless collision: distances are always compared
    }
    return this->LastKey;
  }

  /// The slot holding `key`, or the empty slot where it would go.
  std::size_t Find(std::uint64_t key) const {
    const std::size_t mask = this->Keys.size() - 1;
    std::size_t slot = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 20) & mask;
    while (this->Keys[slot] != kEmpty && this->Keys[slot] != key) {
      slot = (slot + 1) & mask;
    }
    return slot;
  }

  double Tolerance2;
  double InverseCell;
  std::uint64_t LastKey = 0;
  std::vector<std::uint64_t> Keys;
  std::vector<vtkIdType> Heads;
  std::vector<vtkIdType> Next;
  std::vector<double> Points;
};

template <typename T>
vtkSmartPointer<T> NewCellArray(const char* name, vtkIdType n) {
  auto array = vtkSmartPointer<T>::New();
  array->SetName(name);
  array->SetNumberOfTuples(n);
  return array;
}

void AddCount(vtkFieldData* fd, const std::string& name, vtkIdType value) {
  vtkNew<vtkIdTypeArray> array;
  array->SetName(name.c_str());
  array->InsertNextValue(value);
  fd->AddArray(array);
}

void AddNumber(vtkFieldData* fd, const std::string& name, double value) {
  vtkNew<vtkDoubleArray> array;
  array->SetName(name.c_str());
  array->InsertNextValue(value);
  fd->AddArray(array);
}

}  // namespace

vtkHexDEMCrackMap::vtkHexDEMCrackMap()
    : MergeSegments(1), MergeTolerance(0.1), UseMaxBreakTime(0), MaxBreakTime(0.0) {}

vtkHexDEMCrackMap::~vtkHexDEMCrackMap() = default;

int vtkHexDEMCrackMap::FillInputPortInformation(int vtkNotUsed(port), vtkInformation* info) {
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  return 1;
}

int vtkHexDEMCrackMap::RequestData(vtkInformation* vtkNotUsed(request),
                                   vtkInformationVector** inputVector,
                                   vtkInformationVector* outputVector) {
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!input || !output) {
    vtkErrorMacro("Input is not an unstructured grid or output is not poly data.");
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

int vtkHexDEMCrackMap::Execute(vtkUnstructuredGrid* input, vtkPolyData* output) {
  const vtkIdType numDisks = input->GetNumberOfPoints();
  const vtkIdType numCells = input->GetNumberOfCells();
  if (numDisks == 0) {
    vtkErrorMacro("The input frame has no disks (empty grid).");
    return 0;
  }
  if (!(this->MergeTolerance >= 0 && this->MergeTolerance <= 0.5)) {
    vtkErrorMacro("Bad property: MergeTolerance is " << FormatNumber(this->MergeTolerance)
                                                     << " (expected 0 to 0.5).");
    return 0;
  }
  if (this->UseMaxBreakTime && !std::isfinite(this->MaxBreakTime)) {
    vtkErrorMacro("Bad property: MaxBreakTime is " << FormatNumber(this->MaxBreakTime)
                                                   << " (expected a finite number of seconds).");
    return 0;
  }
  vtkCellData* inCD = input->GetCellData();
  std::string error;
  LineCells lines;
  ByteValues state;
  DoubleValues points;
  DoubleValues radius;
  DoubleValues breakTime;
  if (!state.Load(inCD->GetArray("state"), numCells, "'state' cell", error, Contact) ||
      !radius.Load(input->GetPointData()->GetArray("radius"), 1, numDisks, "'radius' point",
                   error, Domain::Positive) ||
      !points.Load(input->GetPoints()->GetData(), 3, numDisks, "point coordinates", error) ||
      !lines.Load(input, error) || !CheckFieldNumbers(input->GetFieldData(), error)) {
    vtkErrorMacro("Bad input (is it a hexdem result frame?): " << error << ".");
    return 0;
  }
  const bool hasBreakTime = inCD->GetArray("break_time") != nullptr;
  if (hasBreakTime &&
      !breakTime.Load(inCD->GetArray("break_time"), 1, numCells, "'break_time' cell", error)) {
    vtkErrorMacro("Bad input: " << error << ".");
    return 0;
  }
  if (this->UseMaxBreakTime && !hasBreakTime) {
    vtkErrorMacro("UseMaxBreakTime is on but the frame has no 'break_time' cell array.");
    return 0;
  }

  // One segment per selected broken bond.
  const std::uint8_t* st = state.Data();
  const double* x = points.Data();
  const double* r = radius.Data();
  const double* bt = hasBreakTime ? breakTime.Data() : nullptr;
  const double halfFactor = 1.0 / std::sqrt(3.0);
  Segments seg;
  std::array<vtkIdType, 3> countPerMode = {0, 0, 0};
  std::array<double, 3> lengthPerMode = {0, 0, 0};
  vtkIdType coincident = 0;
  AbortCheck abort(this, 1 << 20);
  for (vtkIdType c = 0; c < numCells; ++c) {
    if (abort(c)) {
      return 0;
    }
    if (!IsBroken(st[c])) {
      continue;
    }
    const double time = bt ? bt[c] : -1.0;
    if (this->UseMaxBreakTime && time > this->MaxBreakTime) {
      continue;
    }
    const vtkIdType i = lines.First(c);
    const vtkIdType j = lines.Second(c);
    const double* xi = x + 3 * i;
    const double* xj = x + 3 * j;
    const double d[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
    const double dist = std::sqrt(d[0] * d[0] + d[1] * d[1]);
    const double rsum = r[i] + r[j];
    if (!(dist > 0) || !(rsum > 0)) {
      ++coincident;
      continue;
    }
    const double w = r[i] / rsum;
    const double centre[3] = {xi[0] + w * d[0], xi[1] + w * d[1], xi[2] + w * d[2]};
    const double rMean = 0.5 * rsum;
    const double half = rMean * halfFactor;
    // Perpendicular s = (-n_y, n_x).
    const double sx = -d[1] / dist;
    const double sy = d[0] / dist;
    seg.Bond.push_back(c);
    seg.Ends.insert(seg.Ends.end(), {centre[0] - half * sx, centre[1] - half * sy, centre[2],
                                     centre[0] + half * sx, centre[1] + half * sy, centre[2]});
    seg.Length.push_back(2.0 * half);
    seg.BreakTime.push_back(time);
    seg.Mode.push_back(st[c]);
    seg.MinRadius = std::min(seg.MinRadius, rMean);
    countPerMode[st[c] - BrokenTension] += 1;
    lengthPerMode[st[c] - BrokenTension] += 2.0 * half;
  }
  if (coincident > 0) {
    vtkWarningMacro(<< coincident
                    << " broken bond(s) join disks at the same position (or of zero radius) "
                       "and are not drawn.");
  }

  const vtkIdType numSegments = static_cast<vtkIdType>(seg.Size());
  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataTypeToDouble();
  vtkNew<vtkIdTypeArray> offsets;
  vtkNew<vtkIdTypeArray> connectivity;
  vtkCellData* outCD = output->GetCellData();

  if (!this->MergeSegments) {
    outPoints->SetNumberOfPoints(2 * numSegments);
    std::copy(seg.Ends.begin(), seg.Ends.end(),
              static_cast<double*>(outPoints->GetData()->GetVoidPointer(0)));
    offsets->SetNumberOfValues(numSegments + 1);
    connectivity->SetNumberOfValues(2 * numSegments);
    auto mode = NewCellArray<vtkUnsignedCharArray>("mode", numSegments);
    auto time = NewCellArray<vtkDoubleArray>("break_time", numSegments);
    auto length = NewCellArray<vtkDoubleArray>("length", numSegments);
    auto bond = NewCellArray<vtkIdTypeArray>("bond_id", numSegments);
    for (vtkIdType s = 0; s < numSegments; ++s) {
      const auto k = static_cast<std::size_t>(s);
      offsets->SetValue(s, 2 * s);
      connectivity->SetValue(2 * s, 2 * s);
      connectivity->SetValue(2 * s + 1, 2 * s + 1);
      mode->SetValue(s, seg.Mode[k]);
      time->SetValue(s, seg.BreakTime[k]);
      length->SetValue(s, seg.Length[k]);
      bond->SetValue(s, seg.Bond[k]);
    }
    offsets->SetValue(numSegments, 2 * numSegments);
    outCD->AddArray(mode);
    outCD->AddArray(time);
    outCD->AddArray(length);
    outCD->AddArray(bond);
  } else {
    // Merge the end points, then walk each mode's segment graph into polylines.
    const double tolerance = numSegments > 0 ? this->MergeTolerance * seg.MinRadius : 0.0;
    PointMerger merger(static_cast<std::size_t>(2 * numSegments), tolerance,
                       numSegments > 0 ? seg.MinRadius : 1.0);
    std::vector<vtkIdType> vertexOf(static_cast<std::size_t>(2 * numSegments));
    for (std::size_t e = 0; e < vertexOf.size(); ++e) {
      if (abort(static_cast<vtkIdType>(e))) {
        return 0;
      }
      vertexOf[e] = merger.FindOrInsert(&seg.Ends[3 * e]);
    }
    const std::vector<double>& vertices = merger.GetPoints();
    const vtkIdType numVertices = static_cast<vtkIdType>(vertices.size() / 3);
    outPoints->SetNumberOfPoints(numVertices);
    std::copy(vertices.begin(), vertices.end(),
              static_cast<double*>(outPoints->GetData()->GetVoidPointer(0)));

    std::vector<std::uint8_t> lineMode;
    std::vector<double> lineTime;
    std::vector<int> lineSegments;
    std::vector<double> lineLength;
    offsets->InsertNextValue(0);

    std::vector<vtkIdType> start(static_cast<std::size_t>(numVertices) + 1);
    std::vector<vtkIdType> incident;
    std::vector<std::uint8_t> visited(static_cast<std::size_t>(numSegments), 0);
    auto other = [&](vtkIdType s, vtkIdType v) {
      const vtkIdType a = vertexOf[static_cast<std::size_t>(2 * s)];
      return a == v ? vertexOf[static_cast<std::size_t>(2 * s + 1)] : a;
    };
    auto degree = [&](vtkIdType v) {
      return start[static_cast<std::size_t>(v) + 1] - start[static_cast<std::size_t>(v)];
    };
    for (std::uint8_t m = BrokenTension; m <= BrokenCompression; ++m) {
      // Incidence lists (CSR) of this mode's segments.
      std::fill(start.begin(), start.end(), 0);
      for (vtkIdType s = 0; s < numSegments; ++s) {
        if (seg.Mode[static_cast<std::size_t>(s)] == m) {
          ++start[static_cast<std::size_t>(vertexOf[static_cast<std::size_t>(2 * s)]) + 1];
          ++start[static_cast<std::size_t>(vertexOf[static_cast<std::size_t>(2 * s + 1)]) + 1];
        }
      }
      for (std::size_t v = 0; v < static_cast<std::size_t>(numVertices); ++v) {
        start[v + 1] += start[v];
      }
      incident.resize(static_cast<std::size_t>(start.back()));
      std::vector<vtkIdType> fill(start.begin(), start.end() - 1);
      for (vtkIdType s = 0; s < numSegments; ++s) {
        if (seg.Mode[static_cast<std::size_t>(s)] == m) {
          for (int e = 0; e < 2; ++e) {
            const auto v = static_cast<std::size_t>(vertexOf[static_cast<std::size_t>(2 * s + e)]);
            incident[static_cast<std::size_t>(fill[v]++)] = s;
          }
        }
      }

      // Walks from vertex v along segment s until a vertex that does not join exactly two
      // segments of this mode, or back to v (a closed loop).
      auto walk = [&](vtkIdType v, vtkIdType s) {
        const vtkIdType first = v;
        connectivity->InsertNextValue(v);
        double earliest = -1.0;
        double length = 0.0;
        int count = 0;
        while (true) {
          const auto k = static_cast<std::size_t>(s);
          visited[k] = 1;
          ++count;
          length += seg.Length[k];
          if (seg.BreakTime[k] >= 0 && (earliest < 0 || seg.BreakTime[k] < earliest)) {
            earliest = seg.BreakTime[k];
          }
          const vtkIdType w = other(s, v);
          connectivity->InsertNextValue(w);
          if (w == first || degree(w) != 2) {
            break;
          }
          vtkIdType next = -1;
          for (vtkIdType k2 = start[static_cast<std::size_t>(w)];
               k2 < start[static_cast<std::size_t>(w) + 1]; ++k2) {
            if (!visited[static_cast<std::size_t>(incident[static_cast<std::size_t>(k2)])]) {
              next = incident[static_cast<std::size_t>(k2)];
              break;
            }
          }
          if (next < 0) {
            break;
          }
          v = w;
          s = next;
        }
        offsets->InsertNextValue(connectivity->GetNumberOfValues());
        lineMode.push_back(m);
        lineTime.push_back(earliest);
        lineSegments.push_back(count);
        lineLength.push_back(length);
      };

      // Open chains first (from an end that joins 1 or 3+ segments), then closed loops.
      for (int pass = 0; pass < 2; ++pass) {
        for (vtkIdType s = 0; s < numSegments; ++s) {
          const auto k = static_cast<std::size_t>(s);
          if (seg.Mode[k] != m || visited[k]) {
            continue;
          }
          const vtkIdType a = vertexOf[2 * k];
          const vtkIdType b = vertexOf[2 * k + 1];
          if (degree(a) != 2) {
            walk(a, s);
          } else if (degree(b) != 2) {
            walk(b, s);
          } else if (pass == 1) {
            walk(a, s);
          }
        }
      }
    }

    const vtkIdType numLines = static_cast<vtkIdType>(lineMode.size());
    auto mode = NewCellArray<vtkUnsignedCharArray>("mode", numLines);
    auto time = NewCellArray<vtkDoubleArray>("break_time", numLines);
    auto count = NewCellArray<vtkIntArray>("segments", numLines);
    auto length = NewCellArray<vtkDoubleArray>("length", numLines);
    std::copy(lineMode.begin(), lineMode.end(), mode->GetPointer(0));
    std::copy(lineTime.begin(), lineTime.end(), time->GetPointer(0));
    std::copy(lineSegments.begin(), lineSegments.end(), count->GetPointer(0));
    std::copy(lineLength.begin(), lineLength.end(), length->GetPointer(0));
    outCD->AddArray(mode);
    outCD->AddArray(time);
    outCD->AddArray(count);
    outCD->AddArray(length);
  }

  vtkNew<vtkCellArray> outLines;
  outLines->SetData(offsets, connectivity);
  output->SetPoints(outPoints);
  output->SetLines(outLines);
  outCD->SetActiveScalars("mode");

  vtkFieldData* fd = output->GetFieldData();
  fd->ShallowCopy(input->GetFieldData());
  AddCount(fd, "crack_count", numSegments);
  double total = 0.0;
  for (double l : lengthPerMode) {
    total += l;
  }
  AddNumber(fd, "crack_length", total);
  for (std::size_t m = 0; m < kModeNames.size(); ++m) {
    AddCount(fd, std::string("crack_count_") + kModeNames[m], countPerMode[m]);
    AddNumber(fd, std::string("crack_length_") + kModeNames[m], lengthPerMode[m]);
  }
  AddCount(fd, "crack_line_count", output->GetNumberOfCells());
  return 1;
}

void vtkHexDEMCrackMap::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MergeSegments: " << (this->MergeSegments ? "On" : "Off") << "\n";
  os << indent << "MergeTolerance: " << this->MergeTolerance << "\n";
  os << indent << "UseMaxBreakTime: " << (this->UseMaxBreakTime ? "On" : "Off") << "\n";
  os << indent << "MaxBreakTime: " << this->MaxBreakTime << "\n";
}
