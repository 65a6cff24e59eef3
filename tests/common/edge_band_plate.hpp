#pragma once
/// \file edge_band_plate.hpp
/// The test plate of the critical step's edge band (tests/solver/test_critical_step.cpp and
/// `hexdem check` in tests/cli/test_workflow_cli.cpp): a 40 x 40 mm plate of r = 0.1 mm
/// (44,739 disks) with a hole of radius 4 mm, fixed at its base, a symmetry plane on its left
/// edge (rollers with mirror springs), the lattice turned by 7 degrees, concrete. Lengths in m.
#include <string>

namespace hexdem::testing {

/// The plate's case text; `end` [s] is the run's end time (1e-3: about 24,000 steps, so the
/// step count sees a change of omega^2 of 1e-4).
inline std::string edge_band_plate_case(const std::string& geometry, const std::string& shear_model) {
  return "[case]\ngeometry = \"" + geometry + "\"\nthickness = 0.01\nshear_model = \"" + shear_model +
         "\"\n[lattice]\nradius = 0.1e-3\nangle = 7.0\n[[body]]\nname = \"plate\"\n"
         "[[body.shape]]\ntype = \"rectangle\"\nmin = [0, 0]\nmax = [0.04, 0.04]\n"
         "boundary = { bottom = \"base\", top = \"top\", left = \"mirror\", right = \"side\" }\n"
         "[[body.shape]]\ntype = \"circle\"\nrole = \"hole\"\ncenter = [0.025, 0.02]\nradius = 0.004\n"
         "[[material]]\nid = 1\nname = \"concrete\"\ndensity = 2400.0\nE = 30e9\nnu = 0.2\n"
         "[[boundary]]\nset = \"base\"\ntype = \"fixed\"\n"
         "[[boundary]]\nset = \"mirror\"\ntype = \"symmetry\"\ncomponent = \"x\"\n"
         "[time]\nend = 1e-3\n";
}

}  // namespace hexdem::testing
