#include "vtkHexDEMFrameInternals.h"

#include "vtkAbstractArray.h"
#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <limits>

namespace vtkHexDEMInternals {
namespace {

bool CheckShape(vtkDataArray* array, int components, vtkIdType tuples, const std::string& what,
                std::string& error) {
  if (!array) {
    error = "no " + what + " array";
    return false;
  }
  if (array->GetNumberOfComponents() != components) {
    error = what + " array has " + std::to_string(array->GetNumberOfComponents()) +
            " components (expected " + std::to_string(components) + ")";
    return false;
  }
  if (array->GetNumberOfTuples() != tuples) {
    error = what + " array has " + std::to_string(array->GetNumberOfTuples()) +
            " tuples (expected " + std::to_string(tuples) + ")";
    return false;
  }
  return true;
}

template <typename T>
void ConvertToDouble(const T* in, vtkIdType n, double* out) {
  for (vtkIdType k = 0; k < n; ++k) {
    out[k] = static_cast<double>(in[k]);
  }
}

template <typename T>
void ConvertToByte(const T* in, vtkIdType n, std::uint8_t* out) {
  for (vtkIdType k = 0; k < n; ++k) {
    const double v = static_cast<double>(in[k]);
    out[k] = (v >= 0 && v <= 255 && v == std::floor(v)) ? static_cast<std::uint8_t>(v) : 255;
  }
}

bool InDomain(double v, Domain domain) {
  switch (domain) {
    case Domain::Finite:
      return std::isfinite(v);
    case Domain::NonNegative:
      return std::isfinite(v) && v >= 0;
    case Domain::Positive:
      return std::isfinite(v) && v > 0;
  }
  return false;
}

}  // namespace

std::string FormatNumber(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

vtkIdType FirstOutside(const double* values, vtkIdType n, Domain domain) {
  for (vtkIdType k = 0; k < n; ++k) {
    if (!InDomain(values[k], domain)) {
      return k;
    }
  }
  return -1;
}

const char* DomainText(Domain domain) {
  switch (domain) {
    case Domain::Finite:
      return "expected a finite number";
    case Domain::NonNegative:
      return "expected a finite number >= 0";
    case Domain::Positive:
      return "expected a finite number > 0";
  }
  return "";
}

bool DoubleValues::Load(vtkDataArray* array, int components, vtkIdType tuples,
                        const std::string& what, std::string& error, Domain domain) {
  if (!this->LoadValues(array, components, tuples, what, error)) {
    return false;
  }
  const vtkIdType bad = FirstOutside(this->Pointer, tuples * components, domain);
  if (bad >= 0) {
    error = what + " array holds " + FormatNumber(this->Pointer[bad]) + " at tuple " +
            std::to_string(bad / components) +
            (components > 1 ? ", component " + std::to_string(bad % components) : std::string()) +
            " (" + DomainText(domain) + ")";
    this->Pointer = nullptr;
    this->Copy.clear();
    return false;
  }
  return true;
}

bool DoubleValues::LoadValues(vtkDataArray* array, int components, vtkIdType tuples,
                              const std::string& what, std::string& error) {
  this->Pointer = nullptr;
  this->Copy.clear();
  if (!CheckShape(array, components, tuples, what, error)) {
    return false;
  }
  const vtkIdType n = tuples * components;
  if (n == 0) {
    this->Copy.resize(1);
    this->Pointer = this->Copy.data();
    return true;
  }
  if (auto* doubles = vtkDoubleArray::FastDownCast(array)) {
    this->Pointer = doubles->GetPointer(0);
    return true;
  }
  this->Copy.resize(static_cast<std::size_t>(n));
  if (array->HasStandardMemoryLayout()) {
    void* raw = array->GetVoidPointer(0);
    switch (array->GetDataType()) {
      vtkTemplateMacro(ConvertToDouble(static_cast<const VTK_TT*>(raw), n, this->Copy.data()));
      default:
        error = what + " array is not numeric";
        return false;
    }
  } else {
    for (vtkIdType k = 0; k < n; ++k) {
      this->Copy[static_cast<std::size_t>(k)] =
          array->GetComponent(k / components, static_cast<int>(k % components));
    }
  }
  this->Pointer = this->Copy.data();
  return true;
}

bool ByteValues::Load(vtkDataArray* array, vtkIdType tuples, const std::string& what,
                      std::string& error, int maxCode) {
  if (!this->LoadValues(array, tuples, what, error)) {
    return false;
  }
  if (maxCode < 255) {
    for (vtkIdType k = 0; k < tuples; ++k) {
      if (this->Pointer[k] > maxCode) {
        error = what + " array holds " + FormatNumber(array->GetComponent(k, 0)) + " at tuple " +
                std::to_string(k) + " (expected an integer code 0 to " + std::to_string(maxCode) +
                ")";
        this->Pointer = nullptr;
        this->Copy.clear();
        return false;
      }
    }
  }
  return true;
}

bool ByteValues::LoadValues(vtkDataArray* array, vtkIdType tuples, const std::string& what,
                            std::string& error) {
  this->Pointer = nullptr;
  this->Copy.clear();
  if (!CheckShape(array, 1, tuples, what, error)) {
    return false;
  }
  if (tuples == 0) {
    this->Copy.resize(1);
    this->Pointer = this->Copy.data();
    return true;
  }
  if (auto* bytes = vtkUnsignedCharArray::FastDownCast(array)) {
    this->Pointer = bytes->GetPointer(0);
    return true;
  }
  this->Copy.resize(static_cast<std::size_t>(tuples));
  if (array->HasStandardMemoryLayout()) {
    void* raw = array->GetVoidPointer(0);
    switch (array->GetDataType()) {
      vtkTemplateMacro(ConvertToByte(static_cast<const VTK_TT*>(raw), tuples, this->Copy.data()));
      default:
        error = what + " array is not numeric";
        return false;
    }
  } else {
    for (vtkIdType k = 0; k < tuples; ++k) {
      const double v = array->GetComponent(k, 0);
      this->Copy[static_cast<std::size_t>(k)] =
          (v >= 0 && v <= 255 && v == std::floor(v)) ? static_cast<std::uint8_t>(v) : 255;
    }
  }
  this->Pointer = this->Copy.data();
  return true;
}

bool IntValues::Load(vtkDataArray* array, vtkIdType tuples, const std::string& what,
                     std::string& error) {
  this->Copy.clear();
  if (!CheckShape(array, 1, tuples, what, error)) {
    return false;
  }
  this->Copy.resize(static_cast<std::size_t>(std::max<vtkIdType>(tuples, 1)), -1);
  for (vtkIdType k = 0; k < tuples; ++k) {
    const double v = array->GetComponent(k, 0);
    const bool integer = v == std::floor(v) && v >= std::numeric_limits<int>::min() &&
                         v <= std::numeric_limits<int>::max();
    this->Copy[static_cast<std::size_t>(k)] = integer ? static_cast<int>(v) : -1;
  }
  return true;
}

bool LineCells::Load(vtkUnstructuredGrid* grid, std::string& error) {
  this->Ids64 = nullptr;
  this->Ids32 = nullptr;
  this->NumberOfCells = grid->GetNumberOfCells();
  if (this->NumberOfCells == 0) {
    return true;
  }
  vtkCellArray* cells = grid->GetCells();
  if (!cells || cells->GetNumberOfCells() != this->NumberOfCells) {
    error = "the grid's cells are not stored as a cell array";
    return false;
  }
  // Every cell must have exactly two points: offsets 0, 2, 4, ...
  const vtkIdType points = grid->GetNumberOfPoints();
  auto check = [&](const auto* offsets, const auto* ids) -> bool {
    for (vtkIdType c = 0; c <= this->NumberOfCells; ++c) {
      if (static_cast<vtkIdType>(offsets[c]) != 2 * c) {
        const vtkIdType bad = c > 0 ? c - 1 : 0;
        error = "cell " + std::to_string(bad) +
                " is not a two-point line (hexdem frames hold "
                "bonds and contacts as line cells only)";
        return false;
      }
    }
    for (vtkIdType k = 0; k < 2 * this->NumberOfCells; ++k) {
      if (ids[k] < 0 || static_cast<vtkIdType>(ids[k]) >= points) {
        error = "cell " + std::to_string(k / 2) + " refers to point " +
                std::to_string(static_cast<long long>(ids[k])) + ", which does not exist";
        return false;
      }
    }
    return true;
  };
  if (cells->IsStorage64Bit()) {
    const vtkTypeInt64* offsets = cells->GetOffsetsArray64()->GetPointer(0);
    const vtkTypeInt64* ids = cells->GetConnectivityArray64()->GetPointer(0);
    if (!check(offsets, ids)) {
      return false;
    }
    this->Ids64 = ids;
  } else {
    const vtkTypeInt32* offsets = cells->GetOffsetsArray32()->GetPointer(0);
    const vtkTypeInt32* ids = cells->GetConnectivityArray32()->GetPointer(0);
    if (!check(offsets, ids)) {
      return false;
    }
    this->Ids32 = ids;
  }
  return true;
}

double FieldNumber(vtkFieldData* fieldData, const char* name, bool& found) {
  found = false;
  if (!fieldData) {
    return 0.0;
  }
  vtkDataArray* array = vtkDataArray::SafeDownCast(fieldData->GetAbstractArray(name));
  if (!array || array->GetNumberOfTuples() < 1 || array->GetNumberOfComponents() < 1) {
    return 0.0;
  }
  found = true;
  return array->GetComponent(0, 0);
}

std::string FieldString(vtkFieldData* fieldData, const char* name) {
  if (!fieldData) {
    return std::string();
  }
  vtkAbstractArray* array = fieldData->GetAbstractArray(name);
  if (!array || array->GetNumberOfValues() < 1) {
    return std::string();
  }
  return array->GetVariantValue(0).ToString();
}

bool CheckFieldNumbers(vtkFieldData* fieldData, std::string& error) {
  struct Check {
    const char* name;
    Domain domain;
  };
  for (const Check& check : {Check{"time", Domain::Finite}, Check{"step", Domain::Finite},
                             Check{"thickness", Domain::NonNegative},
                             Check{"p_max", Domain::NonNegative}}) {
    bool found = false;
    const double value = FieldNumber(fieldData, check.name, found);
    if (!found) {
      continue;
    }
    if (!InDomain(value, check.domain)) {
      error = std::string("field data '") + check.name + "' is " + FormatNumber(value) + " (" +
              DomainText(check.domain) + ")";
      return false;
    }
    if (std::string(check.name) == "p_max" && value > 0 && !std::isfinite(1.0 / value)) {
      error = "field data 'p_max' is " + FormatNumber(value) +
              " (too small: 1/p_max overflows; expected 0 or at least " + FormatNumber(DBL_MIN) +
              ")";
      return false;
    }
  }
  return true;
}

bool IsAxisymmetric(vtkFieldData* fieldData) {
  return FieldString(fieldData, "geometry") == "axisymmetric";
}

AbortCheck::AbortCheck(vtkAlgorithm* algorithm, vtkIdType interval)
    : Algorithm(algorithm), Interval(interval > 0 ? interval : 1) {}

bool AbortCheck::operator()(vtkIdType iteration) {
  if (iteration % this->Interval != 0) {
    return false;
  }
  return this->Algorithm->CheckAbort();
}

}  // namespace vtkHexDEMInternals
