/**
 * @file vtkHexDEMFrameInternals.h
 * @brief Private helpers shared by the hexdem filters: typed, validated views of the arrays
 * of a hexdem result frame (see docs/filters.md, "The frame").
 *
 * Every view checks the array's presence, component count and tuple count once, up front, so
 * that the kernels can run on raw pointers without further checks. A view of an array that
 * already has the wanted type and a contiguous layout (Float64 for numbers, UInt8 for codes)
 * points into the array's memory and copies nothing; any other numeric type is converted
 * into a copy owned by the view. Views never own or extend the lifetime of the VTK array:
 * the array must outlive the view.
 */
#ifndef vtkHexDEMFrameInternals_h
#define vtkHexDEMFrameInternals_h

#include "vtkType.h"

#include <cstdint>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkDataArray;
class vtkFieldData;
class vtkUnstructuredGrid;

namespace vtkHexDEMInternals {

/// Codes of the frame's `state` cell array.
enum BondState : std::uint8_t {
  Intact = 0,
  Yielded = 1,  ///< intact and yielded (hardening spring)
  BrokenTension = 2,
  BrokenShear = 3,
  BrokenCompression = 4,
  Contact = 5,  ///< a force-carrying contact written after the bonds: not a bond
};

/// True for the states of an intact bond (0 and 1).
inline bool IsIntact(std::uint8_t state) {
  return state <= Yielded;
}

/// True for the states of a broken bond (2, 3 and 4).
inline bool IsBroken(std::uint8_t state) {
  return state >= BrokenTension && state <= BrokenCompression;
}

/// What the values of a number array may be. A hexdem result frame never holds NaN or
/// infinite values, negative masses or areas, or radii <= 0: such a frame is refused.
enum class Domain {
  Finite,       ///< any finite number
  NonNegative,  ///< finite and >= 0
  Positive,     ///< finite and > 0
};

/// A number for messages: "%.10g" ("nan", "inf", "-1", "1e-300").
std::string FormatNumber(double value);

/// Index of the first of `n` values that is not in `domain`, or -1.
vtkIdType FirstOutside(const double* values, vtkIdType n, Domain domain);

/// "expected a finite number", "... >= 0", "... > 0".
const char* DomainText(Domain domain);

/// The numbers of an array as contiguous doubles, `components` per tuple.
class DoubleValues {
 public:
  /// Loads `array`. Returns false and sets `error` (naming `what`) when the array is null,
  /// not numeric, has another number of components or tuples than expected, or holds a
  /// value outside `domain` (the error names the first such value and its tuple).
  bool Load(vtkDataArray* array, int components, vtkIdType tuples, const std::string& what,
            std::string& error, Domain domain = Domain::Finite);
  const double* Data() const { return this->Pointer; }

 private:
  bool LoadValues(vtkDataArray* array, int components, vtkIdType tuples, const std::string& what,
                  std::string& error);
  const double* Pointer = nullptr;
  std::vector<double> Copy;
};

/// The values of an integer-valued array (state, kind) as bytes: values that are not an
/// integer in 0..255 become 255, which no filter treats as a known code.
class ByteValues {
 public:
  /// As DoubleValues::Load, for one-component arrays. With `maxCode` < 255, a value that
  /// is not an integer in 0..maxCode is an error naming the first such value.
  bool Load(vtkDataArray* array, vtkIdType tuples, const std::string& what, std::string& error,
            int maxCode = 255);
  const std::uint8_t* Data() const { return this->Pointer; }

 private:
  bool LoadValues(vtkDataArray* array, vtkIdType tuples, const std::string& what,
                  std::string& error);
  const std::uint8_t* Pointer = nullptr;
  std::vector<std::uint8_t> Copy;
};

/// The values of an integer-valued array (body) as int: values that are not an integer in
/// int's range become -1.
class IntValues {
 public:
  /// As DoubleValues::Load, for one-component arrays.
  bool Load(vtkDataArray* array, vtkIdType tuples, const std::string& what, std::string& error);
  const int* Data() const { return this->Copy.data(); }

 private:
  std::vector<int> Copy;
};

/// The two point ids of every cell of a grid made of two-point line cells (bonds and
/// contacts). Points into the grid's cell array, which must outlive this object.
class LineCells {
 public:
  /// Returns false and sets `error` when a cell is not a two-point line or refers to a point
  /// that does not exist.
  bool Load(vtkUnstructuredGrid* grid, std::string& error);
  vtkIdType Size() const { return this->NumberOfCells; }
  vtkIdType First(vtkIdType cell) const {
    return this->Ids64 ? static_cast<vtkIdType>(this->Ids64[2 * cell])
                       : static_cast<vtkIdType>(this->Ids32[2 * cell]);
  }
  vtkIdType Second(vtkIdType cell) const {
    return this->Ids64 ? static_cast<vtkIdType>(this->Ids64[2 * cell + 1])
                       : static_cast<vtkIdType>(this->Ids32[2 * cell + 1]);
  }

 private:
  const vtkTypeInt64* Ids64 = nullptr;
  const vtkTypeInt32* Ids32 = nullptr;
  vtkIdType NumberOfCells = 0;
};

/// The first value of a numeric field-data array; `found` tells whether it exists.
double FieldNumber(vtkFieldData* fieldData, const char* name, bool& found);

/// The first value of a string (or numeric) field-data array, or "" when absent.
std::string FieldString(vtkFieldData* fieldData, const char* name);

/// Checks the frame's numeric field data: `time` and `step` finite, `thickness` and `p_max`
/// finite and >= 0, and a positive `p_max` no smaller than 1/DBL_MAX (1/p_max is taken).
/// Returns false and sets `error` naming the first bad one.
bool CheckFieldNumbers(vtkFieldData* fieldData, std::string& error);

/// True when the frame's `geometry` field data says "axisymmetric".
bool IsAxisymmetric(vtkFieldData* fieldData);

/// Calls algorithm->CheckAbort() every `interval` iterations of a serial loop; returns true
/// when the algorithm should stop.
class AbortCheck {
 public:
  AbortCheck(vtkAlgorithm* algorithm, vtkIdType interval);
  bool operator()(vtkIdType iteration);

 private:
  vtkAlgorithm* Algorithm;
  vtkIdType Interval;
};

}  // namespace vtkHexDEMInternals

#endif
// VTK-HeaderTest-Exclude: vtkHexDEMFrameInternals.h
