#pragma once
/// \file expanding_ring.hpp
/// The hoop-cracking test ring (tests/solver/test_softening.cpp, HoopCracking, and
/// tests/solver/test_random_stiffness.cpp): a softening concrete ring, axisymmetric, r 20 to
/// 30 mm, 10 mm tall, r = 0.5 mm disks, thrown outwards at 5 m/s for 60 us, so that its hoop
/// strain passes the tensile strength everywhere. Lengths in mm in the text.
#include <string>

namespace hexdem::testing {

/// The ring's case text; `random` is the body of a [random] table ("" for none).
inline std::string expanding_ring_case(const std::string& random = "") {
  return std::string(R"(units = "mm"
[case]
name = "ring"
geometry = "axisymmetric"
[mesh]
radius = 0.5e-3
[[body]]
name = "ring"
material = 1
  [[body.shape]]
  type = "rectangle"
  min = [20.0, 0.0]
  max = [30.0, 10.0]
[[material]]
id = 1
name = "concrete"
density = 2400.0
E = 30e9
nu = 0.2
tensile_strength = 3e6
compressive_strength = 30e6
cohesion = 8.66e6
friction_angle = 30.0
fracture_energy = 100.0
rate_dependent = false
[[initial_velocity]]
body = "ring"
velocity = [5.0, 0.0]
[time]
end = 60e-6
)") + (random.empty() ? "" : "[random]\n" + random);
}

}  // namespace hexdem::testing
