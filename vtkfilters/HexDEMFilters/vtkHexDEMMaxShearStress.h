/**
 * @class   vtkHexDEMMaxShearStress
 * @brief   maximum shear stress of every disk of a hexdem frame
 *
 * vtkHexDEMMaxShearStress reads the Love-Weber stress of each disk (point array `stress`,
 * 9 components, row-major, Pa) of a hexdem result frame and adds the point array
 * `max_shear`, the in-plane maximum shear stress
 *
 *     tau_max = sqrt(((s_xx - s_yy)/2)^2 + s_xy^2)    [Pa]
 *
 * with s_xy the mean of the two off-diagonal terms. With ComputeThreeDimensional on it also
 * adds `max_shear_3d` = (s_1 - s_3)/2 from the principal stresses of the whole symmetrised
 * tensor, which includes s_zz (the hoop stress in axisymmetric runs, the out-of-plane stress
 * in plane strain).
 *
 * When a peak pressure p_max is known (the PMax property when > 0, else the frame's field
 * data `p_max` when > 0) the filter adds `max_shear_ratio` = tau_max / p_max (and
 * `max_shear_3d_ratio`), the quantity of the paper's Figs. 4 and 5. Without p_max these
 * arrays are not made. RatioMode says whether the ratio is wanted: Automatic (default) makes
 * it when p_max is known and stays silent otherwise (an impact case has no p_max); On warns,
 * once for the filter's current settings (not on every time step), when there is no p_max;
 * Off never makes it.
 *
 * The stress can instead be recovered from the bond forces (StressSource), for frames
 * written without `stress`: for each disk i,
 *
 *     sigma_i = 1/V_i * sum_c sym(x_c (x) f_c),   x_c = r_i n,   f_c = f_n n + f_s s,
 *
 * over the cells of state 0, 1 (intact bonds) and 5 (contacts) that touch disk i; n is the
 * unit vector from disk i to the other disk (current positions), s = (-n_y, n_x), f_n and
 * f_s the cell arrays `normal_force` and `shear_force` (N, tension positive), r_i the disk's
 * `radius`. V_i = cell_area * thickness in plane frames (thickness from the property, else
 * the field data `thickness`); in axisymmetric frames forces are per radian and
 * V_i = cell_area * b_i, b_i the ring radius: the point array `ring_radius` when the frame has
 * one (the cell centroid's distance from the axis, as in lattice files), else the disk's
 * distance from the axis (point x). The recovered
 * tensor is in-plane (its zz, xz and yz terms are 0) and is added as the point array
 * `recovered_stress`. Broken bonds (states 2-4) are skipped: a broken pair that still
 * touches is written by the solver as a contact (state 5).
 *
 * The output is the input (shallow copy) with the added arrays. A missing or malformed
 * input array is reported with vtkErrorMacro and gives an empty output.
 */

#ifndef vtkHexDEMMaxShearStress_h
#define vtkHexDEMMaxShearStress_h

#include "HexDEMFiltersCoreModule.h"  // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

class HEXDEMFILTERSCORE_EXPORT vtkHexDEMMaxShearStress : public vtkUnstructuredGridAlgorithm {
 public:
  static vtkHexDEMMaxShearStress* New();
  // clang-format off
  vtkTypeMacro(vtkHexDEMMaxShearStress, vtkUnstructuredGridAlgorithm)  // no ";": it ends with a definition
  void PrintSelf(ostream& os, vtkIndent indent) override;
  // clang-format on

  /// Where the stress tensor comes from.
  enum StressSources {
    /// The `stress` point array when the frame has one, else recovered from the bond forces.
    STRESS_AUTOMATIC = 0,
    /// The `stress` point array only (an error when it is missing).
    STRESS_POINT_ARRAY = 1,
    /// Always recovered from the bond forces.
    STRESS_BOND_FORCES = 2
  };

  ///@{
  /**
   * Where the stress comes from: STRESS_AUTOMATIC (default), STRESS_POINT_ARRAY or
   * STRESS_BOND_FORCES.
   */
  vtkSetClampMacro(StressSource, int, STRESS_AUTOMATIC, STRESS_BOND_FORCES);
  vtkGetMacro(StressSource, int);
  void SetStressSourceToAutomatic() { this->SetStressSource(STRESS_AUTOMATIC); }
  void SetStressSourceToPointArray() { this->SetStressSource(STRESS_POINT_ARRAY); }
  void SetStressSourceToBondForces() { this->SetStressSource(STRESS_BOND_FORCES); }
  ///@}

  ///@{
  /**
   * Also compute `max_shear_3d` = (s_1 - s_3)/2 from the principal stresses of the full
   * tensor (including s_zz). Off by default.
   */
  vtkSetMacro(ComputeThreeDimensional, vtkTypeBool);
  vtkGetMacro(ComputeThreeDimensional, vtkTypeBool);
  vtkBooleanMacro(ComputeThreeDimensional, vtkTypeBool);
  ///@}

  /// When `max_shear_ratio` is made (RatioMode).
  enum RatioModes { RATIO_AUTOMATIC = 0, RATIO_ON = 1, RATIO_OFF = 2 };

  ///@{
  /**
   * RATIO_AUTOMATIC (default): the ratio arrays when p_max is known, silently nothing
   * otherwise. RATIO_ON: the same, but a missing p_max is warned about, once until a property
   * of the filter changes. RATIO_OFF: never the ratio arrays.
   */
  vtkSetClampMacro(RatioMode, int, RATIO_AUTOMATIC, RATIO_OFF);
  vtkGetMacro(RatioMode, int);
  ///@}

  ///@{
  /**
   * Peak pressure p_max [Pa] for `max_shear_ratio`. When > 0 it overrides the frame's
   * `p_max` field data; 0 (default) uses the field data.
   */
  vtkSetMacro(PMax, double);
  vtkGetMacro(PMax, double);
  ///@}

  ///@{
  /**
   * Thickness [m] used to recover the stress of plane frames from the bond forces. When > 0
   * it overrides the frame's `thickness` field data; 0 (default) uses the field data.
   */
  vtkSetMacro(Thickness, double);
  vtkGetMacro(Thickness, double);
  ///@}

 protected:
  vtkHexDEMMaxShearStress();
  ~vtkHexDEMMaxShearStress() override;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  int StressSource;
  vtkTypeBool ComputeThreeDimensional;
  double PMax;
  double Thickness;
  int RatioMode;
  /// The filter's MTime when "No peak pressure" was last warned (0: never).
  vtkMTimeType NoPMaxWarningTime;

 private:
  vtkHexDEMMaxShearStress(const vtkHexDEMMaxShearStress&) = delete;
  void operator=(const vtkHexDEMMaxShearStress&) = delete;

  int Execute(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output);
};

#endif
