/// \file material.cpp
/// Elastic materials and the lattice spring constants (physics.md section 3; the paper's
/// Eqs. 6-14).

#include "hexdem/solver/material.hpp"

#include <charconv>
#include <cmath>
#include <numbers>

#include "hexdem/error.hpp"

namespace hexdem::solver {
namespace {

/// Shortest round-trip rendering of a number for messages.
std::string format_number(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

MaterialIssue issue(const char* key, const std::string& problem, double value) {
  return {key, problem + " (got " + format_number(value) + ")"};
}

}  // namespace

const char* geometry_name(Geometry g) {
  switch (g) {
    case Geometry::PlaneStress:
      return "plane-stress";
    case Geometry::PlaneStrain:
      return "plane-strain";
    case Geometry::Axisymmetric:
      return "axisymmetric";
  }
  return "unknown";
}

const char* shear_model_name(ShearModel m) {
  switch (m) {
    case ShearModel::Rotation:
      return "rotation";
    case ShearModel::LocalStrain:
      return "local-strain";
  }
  return "unknown";
}

const char* plasticity_model_name(PlasticityModel p) {
  switch (p) {
    case PlasticityModel::Auto:
      return "auto";
    case PlasticityModel::Spring:
      return "spring";
    case PlasticityModel::J2:
      return "j2";
    case PlasticityModel::DruckerPrager:
      return "drucker-prager";
  }
  return "unknown";
}

Material::DruckerPragerCone Material::drucker_prager() const {
  const double phi = friction_angle * std::numbers::pi / 180.0, s = std::sin(phi);
  return {6 * cohesion * std::cos(phi) / (3 - s), 6 * s / (3 - s)};
}

Stiffness2D Material::stiffness(Geometry g) const {
  if (!isotropic) return c;
  Stiffness2D s;
  if (g == Geometry::PlaneStress) {
    // sigma_zz = 0: c11 = c22 = E / (1 - nu^2), c12 = nu c11.
    s.c11 = E / (1.0 - nu * nu);
    s.c12 = nu * s.c11;
  } else {
    // eps_zz = 0 (plane strain; the meridian plane of an axisymmetric body): the 3D
    // constants lambda + 2 mu and lambda.
    const double f = E / ((1.0 + nu) * (1.0 - 2.0 * nu));
    s.c11 = f * (1.0 - nu);
    s.c12 = f * nu;
  }
  s.c22 = s.c11;
  s.c66 = E / (2.0 * (1.0 + nu));
  return s;
}

double Material::lame_lambda() const {
  HEXDEM_VERIFY(isotropic, "Lame constants of orthotropic material '" + name + "'");
  return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
}

double Material::lame_mu() const {
  HEXDEM_VERIFY(isotropic, "Lame constants of orthotropic material '" + name + "'");
  return E / (2.0 * (1.0 + nu));
}

std::optional<MaterialIssue> Material::check() const {
  // Written as !(x > 0) so that NaN fails too.
  if (!(density > 0.0) || !std::isfinite(density))
    return issue("density", "must be > 0 [kg/m^3]", density);
  if (!(friction >= 0.0) || !std::isfinite(friction)) return issue("friction", "must be >= 0", friction);
  if (!(yield_stress >= 0.0) || !std::isfinite(yield_stress))
    return issue("yield_stress", "must be >= 0 [Pa]", yield_stress);
  if (breakable) {
    if (!(tensile_strength >= 0.0) || !std::isfinite(tensile_strength))
      return issue("tensile_strength", "must be >= 0 [Pa]", tensile_strength);
    if (!(compressive_strength > 0.0) || !std::isfinite(compressive_strength))
      return issue("compressive_strength", "must be > 0 [Pa]", compressive_strength);
    if (!(cohesion >= 0.0) || !std::isfinite(cohesion)) return issue("cohesion", "must be >= 0 [Pa]", cohesion);
    if (tensile_strength > compressive_strength)
      return issue("tensile_strength",
                   "must not exceed compressive_strength = " + format_number(compressive_strength), tensile_strength);
  }
  const bool drucker_prager = plasticity == PlasticityModel::DruckerPrager;
  if (drucker_prager) {
    // The cone's k = 6 c cos(phi) / (3 - sin(phi)) must be > 0: a zero yield stress marks a
    // disk without plasticity (DiskPlasticity::sigma_y).
    if (!(cohesion > 0.0) || !std::isfinite(cohesion))
      return issue("cohesion", "must be > 0 [Pa] with plasticity = \"drucker-prager\"", cohesion);
    if (breakable)
      return issue("plasticity", "\"drucker-prager\" disks do not break (docs/model.md, \"Drucker-Prager disks\")",
                   tensile_strength);
  }
  // The Mohr-Coulomb angle of the failure criteria and of the Drucker-Prager cone.
  if ((breakable || drucker_prager) && !(friction_angle >= 0.0 && friction_angle < 90.0))
    return issue("friction_angle", "must lie in [0, 90) degrees", friction_angle);
  if (!(fracture_energy >= 0.0) || !std::isfinite(fracture_energy))
    return issue("fracture_energy", "must be >= 0 [J/m^2]", fracture_energy);
  if (fracture_energy > 0) {
    if (!breakable)
      return issue("fracture_energy", "needs the strengths (tensile_strength, compressive_strength, cohesion, "
                   "friction_angle)", fracture_energy);
    if (!(tensile_strength > 0.0))
      return issue("tensile_strength", "must be > 0 [Pa] with a fracture_energy", tensile_strength);
    if (!isotropic) return issue("fracture_energy", "softening needs an isotropic material (E, nu)", fracture_energy);
    if (plastic()) return issue("fracture_energy", "softening and plasticity in one material are not supported", fracture_energy);
  }
  if (!(radial_cracks >= 1.0 && radial_cracks <= 1e6)) return issue("radial_cracks", "must lie in [1, 1e6]", radial_cracks);
  if (!(nonlocal_radius >= 0.0) || !std::isfinite(nonlocal_radius))
    return issue("nonlocal_radius", "must be >= 0 [m]", nonlocal_radius);
  if (shear_softening && !(fracture_energy > 0))
    return MaterialIssue{"shear_softening", "softens shear cracks with the fracture energy: it needs a fracture_energy > 0 (got true)"};
  if (!(damage_band >= 0.0) || !std::isfinite(damage_band)) return issue("damage_band", "must be >= 0 [m]", damage_band);
  if (damage_band > 0 && !(fracture_energy > 0))
    return issue("damage_band", "spreads the fracture energy over a band: it needs a fracture_energy", damage_band);
  if (nonlocal_radius > 0 && !(fracture_energy > 0))
    return issue("nonlocal_radius", "averages the softening criteria: it needs a fracture_energy", nonlocal_radius);
  if (isotropic) {
    if (!(E > 0.0) || !std::isfinite(E)) return issue("E", "must be > 0 [Pa]", E);
    if (!(nu > -1.0 && nu < 0.5)) return issue("nu", "must lie in (-1, 0.5)", nu);
    if (plastic() && !(tangent_modulus >= 0.0 && tangent_modulus < E))
      return issue("tangent_modulus", "must lie in [0, E) with E = " + format_number(E), tangent_modulus);
    return std::nullopt;
  }
  if (drucker_prager) return issue("c11", "plasticity = \"drucker-prager\" needs an isotropic material (E, nu)", c.c11);
  if (plastic()) return issue("yield_stress", "plasticity needs an isotropic material (E, nu)", yield_stress);
  if (!(c.c11 > 0.0) || !std::isfinite(c.c11)) return issue("c11", "must be > 0 [Pa]", c.c11);
  if (!(c.c22 > 0.0) || !std::isfinite(c.c22)) return issue("c22", "must be > 0 [Pa]", c.c22);
  if (!(c.c66 > 0.0) || !std::isfinite(c.c66)) return issue("c66", "must be > 0 [Pa]", c.c66);
  if (!std::isfinite(c.c12)) return issue("c12", "must be finite", c.c12);
  // Positive-definite strain energy: c11 c22 > c12^2 (with c11, c22, c66 > 0).
  if (!(c.c11 * c.c22 > c.c12 * c.c12))
    return issue("c12",
                 "stiffness is not positive definite: needs c12^2 < c11 c22 = " +
                     format_number(c.c11 * c.c22),
                 c.c12);
  return std::nullopt;
}

void Material::validate(const std::string& where) const {
  if (const auto found = check())
    throw InputError(where + ": " + found->key + ": " + found->problem);
}

SpringConstants spring_constants(const Stiffness2D& c) {
  // Equal strain energy of the lattice and the continuum under affine strain (physics.md
  // section 3, re-deriving Eqs. 6-13; Eq. 14 is the isotropic plane-stress case). The paper
  // prints k_s1 with the opposite sign.
  const double sqrt3 = std::sqrt(3.0);
  SpringConstants k;
  k.kn1 = sqrt3 / 6.0 * (3.0 * c.c11 + 2.0 * c.c12 - c.c22);
  k.kn2 = sqrt3 / 3.0 * (c.c12 + c.c22);
  k.ks1 = 2.0 * sqrt3 / 3.0 * (3.0 * c.c66 - c.c22);
  k.ks2 = sqrt3 / 3.0 * (c.c22 - 3.0 * c.c12);
  return k;
}

}  // namespace hexdem::solver
