#pragma once
/// \file material.hpp
/// Elastic materials and the lattice spring constants (physics.md section 3; the paper's
/// Eqs. 6-14, with the sign of k_s1 corrected). SI units: Pa, kg/m^3, N/m.

#include <optional>
#include <string>

namespace hexdem::solver {

/// Plane-stress, plane-strain, or axisymmetric (meridian plane, per radian).
enum class Geometry { PlaneStress, PlaneStrain, Axisymmetric };

/// Name as written to files: "plane-stress", "plane-strain", "axisymmetric".
const char* geometry_name(Geometry g);

/// The paper's rotation shear model (Eq. 1) or the energy-consistent local-strain model.
enum class ShearModel { Rotation, LocalStrain };
const char* shear_model_name(ShearModel m);

/// How a plastic material yields (docs/model.md, "Plasticity"): `Spring`, every spring
/// bilinear with kinematic hardening (the paper's Eq. 16); `J2`, von Mises plasticity with
/// linear kinematic hardening per disk, the plastic strain acting as an eigenstrain of the
/// springs (plane strain and axisymmetry); `Auto`, Spring when both shear springs are
/// positive, else J2.
/// DruckerPrager: the J2 machinery with a pressure-dependent yield stress, fitted to the
/// material's Mohr-Coulomb cohesion and friction angle (Material::drucker_prager).
enum class PlasticityModel { Auto, Spring, J2, DruckerPrager };
/// Name as written in case files: "auto", "spring", "j2", "drucker-prager".
const char* plasticity_model_name(PlasticityModel p);

/// 2D stiffness in the lattice frame (x = lattice axis) [Pa]:
/// e = c11 e11^2/2 + c22 e22^2/2 + c12 e11 e22 + 2 c66 e12^2.
struct Stiffness2D {
  double c11 = 0, c12 = 0, c22 = 0, c66 = 0;
};

/// Spring constants per unit thickness [N/m per m = Pa]: class 1 along the lattice axis,
/// class 2 the other two directions.
struct SpringConstants {
  double kn1 = 0, kn2 = 0, ks1 = 0, ks2 = 0;
};

/// A failed check of Material::validate(): the case-file key at fault and what is wrong.
struct MaterialIssue {
  std::string key;      ///< the offending key, e.g. "density", "nu", "tensile_strength"
  std::string problem;  ///< e.g. "must be > 0 (got -1)"
};

/// A material as given in a case file.
struct Material {
  int id = 1;                ///< referenced by bodies
  std::string name;          ///< for messages and output
  double density = 0;        ///< rho [kg/m^3]
  bool isotropic = true;
  double E = 0, nu = 0;      ///< isotropic: Young's modulus [Pa], Poisson's ratio [-]
  Stiffness2D c;             ///< orthotropic: c11, c12, c22, c66 [Pa] in the lattice frame

  // Plasticity (isotropic materials). Spring model (Eq. 16, physics.md section 7): bilinear
  // kinematic hardening of every spring, yield force f_y = sigma_y 2r w, hardening springs as
  // the elastic ones with the tangent modulus in place of E. J2 model: von Mises yield stress
  // sigma_y and Prager hardening H = E E_t / (E - E_t) per disk.
  double yield_stress = 0;     ///< sigma_y [Pa]; 0: elastic springs
  double tangent_modulus = 0;  ///< E_t [Pa], 0 <= E_t < E
  PlasticityModel plasticity = PlasticityModel::Auto;  ///< resolved by the solver

  // Failure (Eqs. 17-20, physics.md section 8): on when the strengths are given.
  bool breakable = false;
  double tensile_strength = 0;      ///< f_t [Pa]
  double compressive_strength = 0;  ///< f_c [Pa]
  double cohesion = 0;              ///< c [Pa]
  double friction_angle = 0;        ///< phi [deg], in [0, 90)
  bool rate_dependent = true;       ///< Eq. 20 strain-rate factors
  /// Fracture energy G_F [J/m^2]: > 0 turns on softening failure with an orientation-free
  /// criterion on the continuum stress (docs/model.md, "Fracture energy and softening");
  /// 0: the brittle bond criterion of Eq. 19.
  double fracture_energy = 0;
  /// Softening: the Mohr-Coulomb shear criterion starts a softening crack that dissipates
  /// G_F per unit bond section (docs/model.md, "Shear cracks that soften") instead of breaking
  /// the bond at once; false: shear breaks are brittle, as in earlier builds.
  bool shear_softening = false;
  /// Axisymmetric softening: the number of radial cracks that hoop tension opens, which sets
  /// the hoop crack band 2 pi b / n of a ring at radius b [-].
  double radial_cracks = 6;
  /// Softening: the radius R [m] over which the criteria average the disks' strains
  /// (docs/model.md, "Nonlocal criterion"); 0: each bond reads its own two disks.
  double nonlocal_radius = 0;
  /// Softening: smeared damage (docs/model.md, "Smeared damage"). > 0: a bond's damage grows
  /// with the criteria's value at the (nonlocal) continuum strain of its midpoint, not with its
  /// own stretch, and the bond stays in its disks' strain fits until it breaks; the width w [m]
  /// of the band over which a crack dissipates G_F sets the softening. 0: the bond's own
  /// elongation drives its damage (the default).
  double damage_band = 0;

  double friction = 0.5;  ///< Coulomb friction coefficient of contacts [-]

  [[nodiscard]] bool plastic() const { return yield_stress > 0 || plasticity == PlasticityModel::DruckerPrager; }

  /// Drucker-Prager cone through the Mohr-Coulomb compression meridian (cohesion c,
  /// friction angle phi): von Mises q <= k - alpha p with p the mean stress (tension > 0),
  /// alpha = 6 sin(phi) / (3 - sin(phi)), k = 6 c cos(phi) / (3 - sin(phi)) [Pa]. Uniaxial
  /// compression then yields at k / (1 - alpha / 3) = 2 c cos(phi) / (1 - sin(phi)), as
  /// Mohr-Coulomb (Chen and Han, Plasticity for Structural Engineers, 1988, section 5.4).
  struct DruckerPragerCone {
    double k = 0, alpha = 0;
  };
  [[nodiscard]] DruckerPragerCone drucker_prager() const;

  /// The 2D stiffness for a geometry: isotropic E, nu become plane-stress or plane-strain
  /// constants (axisymmetric uses plane strain in the meridian plane); orthotropic c is used
  /// as given.
  [[nodiscard]] Stiffness2D stiffness(Geometry g) const;

  /// Lame constants of an isotropic material (3D) [Pa]; used for the hoop term in
  /// axisymmetric runs (physics.md section 10).
  [[nodiscard]] double lame_lambda() const;
  [[nodiscard]] double lame_mu() const;

  /// Checks values (density > 0, E > 0, -1 < nu < 0.5, positive-definite c) and throws
  /// InputError "<where>: <key>: ... (got <value>)".
  void validate(const std::string& where) const;

  /// The first check of validate() that fails, or nothing when the values are valid. Lets a
  /// reader point at the offending key's own line.
  [[nodiscard]] std::optional<MaterialIssue> check() const;
};

/// Spring constants from the 2D stiffness (physics.md section 3):
///   k_n1 = sqrt(3)/6 (3 c11 + 2 c12 - c22), k_n2 = sqrt(3)/3 (c12 + c22),
///   k_s1 = 2 sqrt(3)/3 (3 c66 - c22),       k_s2 = sqrt(3)/3 (c22 - 3 c12).
SpringConstants spring_constants(const Stiffness2D& c);

}  // namespace hexdem::solver
