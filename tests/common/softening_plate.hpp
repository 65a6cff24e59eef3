#pragma once
/// \file softening_plate.hpp
/// A 20 mm square plate of softening concrete (plane stress, 10 mm thick, r = 1 mm disks, no
/// rate dependence) at a lattice angle, for the closing crack of tests/solver/test_softening.cpp
/// and the uniform stress of tests/solver/test_smeared_damage.cpp. Lengths in mm in the text.
#include <sstream>
#include <string>

namespace hexdem::testing {

/// The plate's case text: `strengths` are the material's four strength lines, `extra` further
/// material lines, `end` the end time [s].
inline std::string softening_plate_case(double angle, const std::string& strengths, const std::string& extra,
                                        double end) {
  std::ostringstream s;
  s << "units = \"mm\"\n[case]\nname = \"plate\"\ngeometry = \"plane-stress\"\nthickness = 0.01\n"
    << "[mesh]\nradius = 1.0e-3\nangle = " << angle << "\n"
    << "[[body]]\nname = \"plate\"\nmaterial = 1\n  [[body.shape]]\n  type = \"rectangle\"\n"
    << "  min = [0.0, 0.0]\n  max = [20.0, 20.0]\n"
    << "[[material]]\nid = 1\nname = \"concrete\"\ndensity = 2400.0\nE = 30e9\nnu = 0.2\n" << strengths
    << "fracture_energy = 100.0\nrate_dependent = false\n" << extra << "[time]\nend = " << end << "\n";
  return s.str();
}

}  // namespace hexdem::testing
