#include "vtkHexDEMFragmentCounter.h"

#include "vtkHexDEMFrameInternals.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkHexDEMFragmentCounter);

namespace {
using namespace vtkHexDEMInternals;

/// Union-find whose root is always the lowest disk index of its set (union by index, path
/// halving): the root then names the set and orders ties between fragments.
class DisjointSets {
 public:
  explicit DisjointSets(vtkIdType n) : Parent(static_cast<std::size_t>(n)) {
    std::iota(this->Parent.begin(), this->Parent.end(), vtkIdType(0));
  }

  vtkIdType Find(vtkIdType i) {
    vtkIdType* p = this->Parent.data();
    while (p[i] != i) {
      p[i] = p[p[i]];
      i = p[i];
    }
    return i;
  }

  void Union(vtkIdType a, vtkIdType b) {
    a = this->Find(a);
    b = this->Find(b);
    if (a < b) {
      this->Parent[static_cast<std::size_t>(b)] = a;
    } else if (b < a) {
      this->Parent[static_cast<std::size_t>(a)] = b;
    }
  }

 private:
  std::vector<vtkIdType> Parent;
};

template <typename T>
vtkSmartPointer<T> NewColumn(const char* name, vtkIdType n) {
  auto array = vtkSmartPointer<T>::New();
  array->SetName(name);
  array->SetNumberOfTuples(n);
  return array;
}

void SetCount(vtkFieldData* fd, const char* name, vtkIdType value) {
  vtkNew<vtkIdTypeArray> array;
  array->SetName(name);
  array->InsertNextValue(value);
  fd->AddArray(array);
}

}  // namespace

vtkHexDEMFragmentCounter::vtkHexDEMFragmentCounter()
    : MinimumDisks(1), Body(-1), BodyName(nullptr) {
  this->SetNumberOfOutputPorts(2);
}

vtkHexDEMFragmentCounter::~vtkHexDEMFragmentCounter() { this->SetBodyName(nullptr); }

vtkTable* vtkHexDEMFragmentCounter::GetTableOutput() {
  return vtkTable::SafeDownCast(this->GetOutputDataObject(1));
}

int vtkHexDEMFragmentCounter::FillOutputPortInformation(int port, vtkInformation* info) {
  if (port == 1) {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

int vtkHexDEMFragmentCounter::RequestData(vtkInformation* vtkNotUsed(request),
                                          vtkInformationVector** inputVector,
                                          vtkInformationVector* outputVector) {
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  vtkTable* table = vtkTable::GetData(outputVector, 1);
  if (!input || !output || !table) {
    vtkErrorMacro("Input or outputs are not of the expected types.");
    return 0;
  }
  try {
    const int status = this->Execute(input, output, table);
    if (status == 0) {
      output->Initialize();
      table->Initialize();
    }
    return status;
  } catch (const std::exception& e) {
    output->Initialize();
    table->Initialize();
    vtkErrorMacro("Failed: " << e.what());
    return 0;
  }
}

int vtkHexDEMFragmentCounter::Execute(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output,
                                      vtkTable* table) {
  const vtkIdType numDisks = input->GetNumberOfPoints();
  const vtkIdType numCells = input->GetNumberOfCells();
  if (numDisks == 0) {
    vtkErrorMacro("The input frame has no disks (empty grid).");
    return 0;
  }
  if (this->MinimumDisks < 1) {
    vtkErrorMacro("Bad property: MinimumDisks is " << this->MinimumDisks << " (expected >= 1).");
    return 0;
  }
  if (this->Body < -1) {
    vtkErrorMacro("Bad property: Body is " << this->Body
                                           << " (expected a body index >= 0, or -1: every body).");
    return 0;
  }
  std::string error;
  LineCells lines;
  ByteValues state;
  if (!state.Load(input->GetCellData()->GetArray("state"), numCells, "'state' cell", error,
                  Contact) ||
      !lines.Load(input, error)) {
    vtkErrorMacro("Bad input (is it a hexdem result frame?): " << error << ".");
    return 0;
  }

  // Optional per-disk arrays for the table.
  vtkPointData* inPD = input->GetPointData();
  DoubleValues points;
  DoubleValues mass;
  DoubleValues area;
  DoubleValues velocity;
  if (!points.Load(input->GetPoints()->GetData(), 3, numDisks, "point coordinates", error) ||
      !CheckFieldNumbers(input->GetFieldData(), error)) {
    vtkErrorMacro("Bad input: " << error << ".");
    return 0;
  }
  std::string missing;
  auto optional = [&](DoubleValues& values, const char* name, int components,
                      Domain domain) -> bool {
    vtkDataArray* array = inPD->GetArray(name);
    if (!array) {
      missing += std::string(missing.empty() ? "" : ", ") + "'" + name + "'";
      return false;
    }
    if (!values.Load(array, components, numDisks, std::string("'") + name + "' point", error,
                     domain)) {
      throw std::invalid_argument(error);
    }
    return true;
  };
  bool hasMass = false, hasArea = false, hasVelocity = false;
  try {
    hasMass = optional(mass, "mass", 1, Domain::Positive);
    hasArea = optional(area, "cell_area", 1, Domain::NonNegative);
    hasVelocity = optional(velocity, "velocity", 3, Domain::Finite);
  } catch (const std::invalid_argument& e) {
    vtkErrorMacro("Bad input: " << e.what() << ".");
    return 0;
  }
  if (!missing.empty()) {
    vtkWarningMacro("The frame has no " << missing
                                        << " point array: the table columns that need it are NaN.");
  }

  // Bodies: the `body` point array (optional without a body selection) and their names.
  IntValues bodies;
  vtkDataArray* bodyArray = inPD->GetArray("body");
  if (bodyArray && !bodies.Load(bodyArray, numDisks, "'body' point", error)) {
    vtkErrorMacro("Bad input: " << error << ".");
    return 0;
  }
  const int* body = bodyArray ? bodies.Data() : nullptr;
  vtkStringArray* bodyNames =
      vtkStringArray::SafeDownCast(input->GetFieldData()->GetAbstractArray("body_names"));
  // Body indices: integers >= 0, and below the number of names when the frame names them.
  const vtkIdType numNames = bodyNames ? bodyNames->GetNumberOfValues() : 0;
  if (bodyArray) {
    for (vtkIdType i = 0; i < numDisks; ++i) {
      const double b = bodyArray->GetComponent(i, 0);
      if (!(b >= 0 && b == std::floor(b) && b <= VTK_INT_MAX) ||
          (bodyNames && b >= static_cast<double>(numNames))) {
        vtkErrorMacro("Bad input: 'body' point array holds "
                      << FormatNumber(b) << " at tuple " << i << " (expected a body index 0 to "
                      << (bodyNames ? std::to_string(numNames - 1) + ", the frame names " +
                                          std::to_string(numNames) + " bodies"
                                    : std::string("2147483647"))
                      << ").");
        return 0;
      }
    }
  }
  int selectedBody = this->Body;
  if (selectedBody >= 0 && (!this->BodyName || this->BodyName[0] == '\0') && body) {
    // A body index the frame does not have is an error, as a body name it does not have.
    bool known = bodyNames ? selectedBody < numNames : false;
    for (vtkIdType i = 0; !known && i < numDisks; ++i) {
      known = body[i] == selectedBody;
    }
    if (!known) {
      vtkErrorMacro("Bad input: the frame has no body "
                    << selectedBody << " (bodies: "
                    << (bodyNames ? "0 to " + std::to_string(numNames - 1)
                                  : std::string("the values of the 'body' point array"))
                    << ").");
      return 0;
    }
  }
  if (this->BodyName && this->BodyName[0] != '\0') {
    selectedBody = -1;
    std::string known;
    for (vtkIdType b = 0; bodyNames && b < bodyNames->GetNumberOfValues(); ++b) {
      if (bodyNames->GetValue(b) == this->BodyName) {
        selectedBody = static_cast<int>(b);
      }
      known += std::string(known.empty() ? "" : ", ") + bodyNames->GetValue(b);
    }
    if (selectedBody < 0) {
      vtkErrorMacro("Bad input: the frame has no body named '"
                    << this->BodyName << "' (bodies: "
                    << (bodyNames ? known : std::string("no 'body_names' field data")) << ").");
      return 0;
    }
  }
  if (selectedBody >= 0 && !body) {
    vtkErrorMacro("Bad input: a body selection needs the 'body' point array.");
    return 0;
  }

  // Connected components over intact bonds.
  DisjointSets sets(numDisks);
  const std::uint8_t* st = state.Data();
  AbortCheck abort(this, 1 << 20);
  for (vtkIdType c = 0; c < numCells; ++c) {
    if (abort(c)) {
      return 0;
    }
    if (IsIntact(st[c])) {
      sets.Union(lines.First(c), lines.Second(c));
    }
  }

  // Components in order of their lowest disk (the roots), then sorted by size.
  std::vector<vtkIdType> component(static_cast<std::size_t>(numDisks));
  std::vector<vtkIdType> size;
  for (vtkIdType i = 0; i < numDisks; ++i) {
    const vtkIdType root = sets.Find(i);
    if (root == i) {
      component[static_cast<std::size_t>(i)] = static_cast<vtkIdType>(size.size());
      size.push_back(0);
    } else {
      component[static_cast<std::size_t>(i)] = component[static_cast<std::size_t>(root)];
    }
    ++size[static_cast<std::size_t>(component[static_cast<std::size_t>(i)])];
  }
  // Each component's body: that of its lowest disk (-1 if its disks disagree, or no `body`).
  const std::size_t numComponents = size.size();
  std::vector<int> componentBody(numComponents, -1);
  if (body) {
    std::vector<char> seen(numComponents, 0);
    for (vtkIdType i = 0; i < numDisks; ++i) {
      const auto c = static_cast<std::size_t>(component[static_cast<std::size_t>(i)]);
      if (!seen[c]) {
        seen[c] = 1;
        componentBody[c] = body[i];
      } else if (componentBody[c] != body[i]) {
        componentBody[c] = -1;
      }
    }
  }
  // The fragments: the components of the selected body (all without a selection), by size.
  std::vector<vtkIdType> order;
  order.reserve(numComponents);
  for (std::size_t c = 0; c < numComponents; ++c) {
    if (selectedBody < 0 || componentBody[c] == selectedBody) {
      order.push_back(static_cast<vtkIdType>(c));
    }
  }
  const vtkIdType numFragments = static_cast<vtkIdType>(order.size());
  std::stable_sort(order.begin(), order.end(), [&](vtkIdType a, vtkIdType b) {
    return size[static_cast<std::size_t>(a)] > size[static_cast<std::size_t>(b)];
  });
  std::vector<vtkIdType> rank(numComponents, -1);  // -1: not a fragment of the selection
  vtkIdType singleDisk = 0;
  for (vtkIdType k = 0; k < numFragments; ++k) {
    rank[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = k;
    singleDisk += size[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] == 1;
  }
  vtkIdType counted = 0;
  while (counted < numFragments &&
         size[static_cast<std::size_t>(order[static_cast<std::size_t>(counted)])] >=
             this->MinimumDisks) {
    ++counted;
  }

  // fragment_id and the per-fragment sums of the counted fragments.
  auto fragmentId = NewColumn<vtkIntArray>("fragment_id", numDisks);
  int* ids = fragmentId->GetPointer(0);
  auto fragmentDisks = NewColumn<vtkIntArray>("fragment_disks", numDisks);
  int* disksOf = fragmentDisks->GetPointer(0);
  const std::size_t n = static_cast<std::size_t>(counted);
  std::vector<double> sumMass(n, 0.0), sumArea(n, 0.0), sumAx(n, 0.0), sumAy(n, 0.0),
      sumMvx(n, 0.0), sumMvy(n, 0.0);
  const double* x = points.Data();
  const double* m = hasMass ? mass.Data() : nullptr;
  const double* a = hasArea ? area.Data() : nullptr;
  const double* v = hasVelocity ? velocity.Data() : nullptr;
  for (vtkIdType i = 0; i < numDisks; ++i) {
    const auto c = static_cast<std::size_t>(component[static_cast<std::size_t>(i)]);
    const vtkIdType f = rank[c];
    ids[i] = static_cast<int>(f);
    disksOf[i] = f < 0 ? 0 : static_cast<int>(size[c]);
    if (f < 0 || f >= counted) {
      continue;
    }
    const auto k = static_cast<std::size_t>(f);
    if (m) {
      sumMass[k] += m[i];
      if (v) {
        sumMvx[k] += m[i] * v[3 * i];
        sumMvy[k] += m[i] * v[3 * i + 1];
      }
    }
    if (a) {
      sumArea[k] += a[i];
      sumAx[k] += a[i] * x[3 * i];
      sumAy[k] += a[i] * x[3 * i + 1];
    }
  }

  output->ShallowCopy(input);
  output->GetPointData()->AddArray(fragmentId);
  output->GetPointData()->AddArray(fragmentDisks);
  output->GetPointData()->SetActiveScalars("fragment_id");
  SetCount(output->GetFieldData(), "fragment_count", counted);
  SetCount(output->GetFieldData(), "fragment_count_total", numFragments);
  SetCount(output->GetFieldData(), "single_disk_fragments", singleDisk);

  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto colId = NewColumn<vtkIntArray>("fragment_id", counted);
  auto colDisks = NewColumn<vtkIdTypeArray>("disks", counted);
  auto colMass = NewColumn<vtkDoubleArray>("mass", counted);
  auto colArea = NewColumn<vtkDoubleArray>("area", counted);
  auto colCx = NewColumn<vtkDoubleArray>("centroid_x", counted);
  auto colCy = NewColumn<vtkDoubleArray>("centroid_y", counted);
  auto colVx = NewColumn<vtkDoubleArray>("velocity_x", counted);
  auto colVy = NewColumn<vtkDoubleArray>("velocity_y", counted);
  auto colD = NewColumn<vtkDoubleArray>("equivalent_diameter", counted);
  vtkSmartPointer<vtkIntArray> colBody;
  vtkSmartPointer<vtkStringArray> colBodyName;
  if (body && bodyNames) {
    colBody = NewColumn<vtkIntArray>("body", counted);
    colBodyName = NewColumn<vtkStringArray>("body_name", counted);
  }
  for (vtkIdType f = 0; f < counted; ++f) {
    const auto k = static_cast<std::size_t>(f);
    if (colBody) {
      const int b = componentBody[static_cast<std::size_t>(order[k])];
      colBody->SetValue(f, b);
      if (colBodyName) {
        colBodyName->SetValue(f, b >= 0 && b < bodyNames->GetNumberOfValues()
                                     ? bodyNames->GetValue(b)
                                     : vtkStdString());
      }
    }
    const double fm = m ? sumMass[k] : nan;
    const double fa = a ? sumArea[k] : nan;
    colId->SetValue(f, static_cast<int>(f));
    colDisks->SetValue(f, size[static_cast<std::size_t>(order[k])]);
    colMass->SetValue(f, fm);
    colArea->SetValue(f, fa);
    colCx->SetValue(f, fa > 0 ? sumAx[k] / fa : nan);
    colCy->SetValue(f, fa > 0 ? sumAy[k] / fa : nan);
    colVx->SetValue(f, (v && fm > 0) ? sumMvx[k] / fm : nan);
    colVy->SetValue(f, (v && fm > 0) ? sumMvy[k] / fm : nan);
    colD->SetValue(f, fa >= 0 ? 2.0 * std::sqrt(fa / vtkMath::Pi()) : nan);
  }
  // Sums of finite values can still overflow: an infinite mass or area is not a result.
  for (vtkDoubleArray* column : {colMass.GetPointer(), colArea.GetPointer(), colCx.GetPointer(),
                                 colCy.GetPointer(), colVx.GetPointer(), colVy.GetPointer(),
                                 colD.GetPointer()}) {
    for (vtkIdType f = 0; f < counted; ++f) {
      if (std::isinf(column->GetValue(f))) {
        vtkErrorMacro("Bad input: the " << column->GetName() << " of fragment " << f << " is "
                                        << FormatNumber(column->GetValue(f))
                                        << " (the frame's values are too large).");
        return 0;
      }
    }
  }
  table->AddColumn(colId);
  table->AddColumn(colDisks);
  table->AddColumn(colMass);
  table->AddColumn(colArea);
  table->AddColumn(colCx);
  table->AddColumn(colCy);
  table->AddColumn(colVx);
  table->AddColumn(colVy);
  table->AddColumn(colD);
  if (colBody) {
    table->AddColumn(colBody);
  }
  if (colBodyName) {
    table->AddColumn(colBodyName);
  }
  vtkFieldData* tableFd = table->GetFieldData();
  SetCount(tableFd, "fragment_count", counted);
  SetCount(tableFd, "fragment_count_total", numFragments);
  SetCount(tableFd, "single_disk_fragments", singleDisk);
  for (const char* name : {"time", "step"}) {
    if (vtkAbstractArray* array = input->GetFieldData()->GetAbstractArray(name)) {
      tableFd->AddArray(array);
    }
  }
  return 1;
}

void vtkHexDEMFragmentCounter::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MinimumDisks: " << this->MinimumDisks << "\n";
  os << indent << "Body: " << this->Body << "\n";
  os << indent << "BodyName: " << (this->BodyName ? this->BodyName : "(none)") << "\n";
}
