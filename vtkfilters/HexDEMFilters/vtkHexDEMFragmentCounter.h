/**
 * @class   vtkHexDEMFragmentCounter
 * @brief   fragments of a hexdem frame: disks connected by intact bonds
 *
 * vtkHexDEMFragmentCounter finds the connected components of the disks of a hexdem result
 * frame over its intact bonds (cell array `state` 0 or 1); broken bonds (2-4) and contacts
 * (state 5) do not connect. A disk without intact bonds is a fragment of its own. It uses a
 * union-find over the bond arrays, linear in the number of bonds.
 *
 * Output 0 is the input (shallow copy) with the point array `fragment_id` (Int32): 0 for
 * the fragment with the most disks, then by decreasing number of disks, ties broken by the
 * lowest disk index in the fragment. Its field data gains `fragment_count` (fragments with
 * at least MinimumDisks disks) and `fragment_count_total` (all fragments).
 *
 * Output 1 is a vtkTable with one row per counted fragment, in fragment_id order (row k is
 * fragment k): `fragment_id`, `disks`, `mass` (sum of `mass`, kg, per radian in
 * axisymmetric frames), `area` (sum of `cell_area`, m^2), `centroid_x`, `centroid_y`
 * (area-weighted mean of the disk centres, m), `velocity_x`, `velocity_y` (mass-weighted
 * mean of `velocity`, m/s) and `equivalent_diameter` (2 sqrt(area/pi), m). It carries the
 * same counts, and `time` and `step` when the frame has them, as field data.
 *
 * Fragments with fewer than MinimumDisks disks (default 1: all count) keep their
 * fragment_id, which is always >= fragment_count since ids follow size, but are neither
 * counted in `fragment_count` nor listed in the table.
 *
 * Every disk also gets `fragment_disks` (Int32), the number of disks of its fragment: single-
 * disk debris is `fragment_disks == 1` (e.g. ParaView's Threshold on it), and the field data
 * `single_disk_fragments` counts it. When the frame names its bodies (point array `body` and
 * field data `body_names`, as every hexdem result frame), the table has the columns `body`
 * (the fragment's body index; bonds join disks of one body, -1 if its disks disagree) and
 * `body_name`.
 *
 * Body selection: with Body >= 0 (an index) or a non-empty BodyName (a name of the
 * `body_names` field data), only the fragments of that body are labelled, counted and listed,
 * so that a projectile is not counted as a fragment of its target; the other disks get
 * fragment_id = -1 and fragment_disks = 0. BodyName takes precedence over Body.
 *
 * Only `state` is required (and `body`, `body_names` for a body selection). Without `mass`,
 * `cell_area` or `velocity` the columns that need them are NaN and the filter warns. A
 * missing or malformed `state` array, or a body that the frame does not have, is reported
 * with vtkErrorMacro and gives empty outputs.
 */

#ifndef vtkHexDEMFragmentCounter_h
#define vtkHexDEMFragmentCounter_h

#include "HexDEMFiltersCoreModule.h"  // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

class vtkTable;

class HEXDEMFILTERSCORE_EXPORT vtkHexDEMFragmentCounter : public vtkUnstructuredGridAlgorithm {
 public:
  static vtkHexDEMFragmentCounter* New();
  // clang-format off
  vtkTypeMacro(vtkHexDEMFragmentCounter, vtkUnstructuredGridAlgorithm)  // no ";": it ends with a definition
  void PrintSelf(ostream& os, vtkIndent indent) override;
  // clang-format on

  ///@{
  /**
   * Smallest number of disks of a fragment that is counted and listed in the table
   * (default 1: every fragment, single disks included). A value below 1 is not clamped: the
   * filter refuses to run with it.
   */
  vtkSetMacro(MinimumDisks, int);
  vtkGetMacro(MinimumDisks, int);
  ///@}

  ///@{
  /**
   * Only the fragments of this body (index into the frame's bodies, point array `body`);
   * -1 (default): every body. A value below -1, or a body the frame does not have, is an
   * error (as a BodyName the frame does not have).
   */
  vtkSetMacro(Body, int);
  vtkGetMacro(Body, int);
  ///@}

  ///@{
  /**
   * Only the fragments of the body of this name (field data `body_names`); empty (default):
   * use Body. Takes precedence over Body.
   */
  vtkSetStringMacro(BodyName);
  vtkGetStringMacro(BodyName);
  ///@}

  /**
   * The fragment table (output port 1).
   */
  vtkTable* GetTableOutput();

 protected:
  vtkHexDEMFragmentCounter();
  ~vtkHexDEMFragmentCounter() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  int MinimumDisks;
  int Body;
  char* BodyName;

 private:
  vtkHexDEMFragmentCounter(const vtkHexDEMFragmentCounter&) = delete;
  void operator=(const vtkHexDEMFragmentCounter&) = delete;

  int Execute(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output, vtkTable* table);
};

#endif
