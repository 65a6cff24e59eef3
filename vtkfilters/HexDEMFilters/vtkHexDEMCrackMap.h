/**
 * @class   vtkHexDEMCrackMap
 * @brief   cracks of a hexdem frame as line segments between the disks
 *
 * vtkHexDEMCrackMap draws one segment for every broken bond of a hexdem result frame (cell
 * array `state` 2 = broken in tension, 3 = in shear, 4 = in compression), where the two
 * disks' cells meet: for a bond from disk i to disk j (current centres x_i, x_j, radii r_i,
 * r_j, unit vector n from i to j) the segment is centred at
 *
 *     c = x_i + r_i / (r_i + r_j) * (x_j - x_i)
 *
 * (the contact point x_i + r_i n while the disks touch, and halfway between their surfaces
 * once they separate), perpendicular to n, of length 2 r / sqrt(3) with r = (r_i + r_j)/2:
 * the shared edge of the two hexagonal cells in the undeformed lattice. Cells of state 5
 * (contacts) and intact bonds are not cracks.
 *
 * With MergeSegments on (default), segments of the same failure mode whose end points lie
 * within MergeTolerance * r_min of each other (r_min the smallest mean radius of the broken
 * bonds) share one point and are joined into polylines: a polyline runs between end points
 * that join 1 or 3+ segments of its mode, and a closed loop repeats its first point. Cracks
 * of different modes that meet share the point but stay separate polylines, so every
 * output cell has one mode. Cell data: `mode` (2, 3, 4), `break_time` (earliest break time
 * of its segments, s; -1 if unknown), `segments` (broken bonds in it) and `length` (sum of
 * their nominal lengths, m). With MergeSegments off there is one line cell per broken
 * bond, with `mode`, `break_time`, `length` and `bond_id` (the cell index of the bond in
 * the input).
 *
 * Field data: `crack_count` (number of broken bonds drawn), `crack_length` (their total
 * nominal length, m), the same per mode (`crack_count_tension`, `crack_count_shear`,
 * `crack_count_compression`, `crack_length_tension`, ...), and `crack_line_count` (output
 * cells); the input's field data (time, step, ...) is passed through.
 *
 * With UseMaxBreakTime on only bonds with break_time <= MaxBreakTime are drawn (bonds whose
 * break time is unknown, i.e. negative, are kept). A missing or malformed input array is
 * reported with vtkErrorMacro and gives an empty output.
 */

#ifndef vtkHexDEMCrackMap_h
#define vtkHexDEMCrackMap_h

#include "HexDEMFiltersCoreModule.h"  // for export macro
#include "vtkPolyDataAlgorithm.h"

class vtkUnstructuredGrid;

class HEXDEMFILTERSCORE_EXPORT vtkHexDEMCrackMap : public vtkPolyDataAlgorithm {
 public:
  static vtkHexDEMCrackMap* New();
  // clang-format off
  vtkTypeMacro(vtkHexDEMCrackMap, vtkPolyDataAlgorithm)  // no ";": it ends with a definition
  void PrintSelf(ostream& os, vtkIndent indent) override;
  // clang-format on

  ///@{
  /**
   * Join adjoining segments of the same mode into polylines (default on). Off: one line cell
   * per broken bond.
   */
  vtkSetMacro(MergeSegments, vtkTypeBool);
  vtkGetMacro(MergeSegments, vtkTypeBool);
  vtkBooleanMacro(MergeSegments, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Distance within which segment end points are merged, as a fraction of the smallest mean
   * disk radius of the broken bonds (default 0.1). A value outside [0, 0.5] (or NaN) is not
   * clamped: the filter refuses to run with it (an error naming the value).
   */
  vtkSetMacro(MergeTolerance, double);
  vtkGetMacro(MergeTolerance, double);
  ///@}

  ///@{
  /**
   * Draw only bonds broken at or before MaxBreakTime (default off).
   */
  vtkSetMacro(UseMaxBreakTime, vtkTypeBool);
  vtkGetMacro(UseMaxBreakTime, vtkTypeBool);
  vtkBooleanMacro(UseMaxBreakTime, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Latest break time [s] drawn when UseMaxBreakTime is on (default 0).
   */
  vtkSetMacro(MaxBreakTime, double);
  vtkGetMacro(MaxBreakTime, double);
  ///@}

 protected:
  vtkHexDEMCrackMap();
  ~vtkHexDEMCrackMap() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  vtkTypeBool MergeSegments;
  double MergeTolerance;
  vtkTypeBool UseMaxBreakTime;
  double MaxBreakTime;

 private:
  vtkHexDEMCrackMap(const vtkHexDEMCrackMap&) = delete;
  void operator=(const vtkHexDEMCrackMap&) = delete;

  int Execute(vtkUnstructuredGrid* input, vtkPolyData* output);
};

#endif
