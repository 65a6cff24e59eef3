#pragma once
/// \file plate_impact.hpp
/// A steel disk (5 mm radius) thrown at 50 m/s onto a concrete plate (80 x 20 mm on a fixed
/// base; plane strain, 10 mm thick, r = 1 mm disks, contact damping 0.5): the impact of
/// tests/solver/test_break_energy.cpp and tests/solver/test_contact_radii.cpp. Lengths in mm in
/// the text.
#include <string>

namespace hexdem::testing {

/// The case's text up to its `[contact]` table, which it opens and leaves open (the caller
/// adds contact keys, then `[time]`): `mesh` further `[mesh]` lines, `concrete` further lines of
/// the plate's material.
inline std::string plate_impact_case(const std::string& mesh, const std::string& concrete) {
  return std::string(R"(units = "mm"
[case]
name = "plate_impact"
geometry = "plane-strain"
thickness = 0.01
[mesh]
radius = 1.0e-3
)") + mesh + R"([[body]]
name = "plate"
material = 1
  [[body.shape]]
  type = "rectangle"
  min = [-40.0, -20.0]
  max = [40.0, 0.0]
  boundary = { bottom = "base", right = "far", top = "face", left = "far" }
[[body]]
name = "disk"
material = 2
  [[body.shape]]
  type = "circle"
  center = [0.0, 6.0]
  radius = 5.0
  boundary = "skin"
[[material]]
id = 1
name = "concrete"
density = 2400.0
E = 30e9
nu = 0.2
tensile_strength = 3e6
compressive_strength = 30e6
cohesion = 6e6
friction_angle = 30.0
)" + concrete + R"([[material]]
id = 2
name = "steel"
density = 7850.0
E = 210e9
nu = 0.3
[[boundary]]
set = "base"
type = "fixed"
[[initial_velocity]]
body = "disk"
velocity = [0.0, -50.0]
[contact]
damping = 0.5
)";
}

}  // namespace hexdem::testing
