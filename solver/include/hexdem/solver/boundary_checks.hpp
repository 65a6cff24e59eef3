#pragma once
/// \file boundary_checks.hpp
/// Checks of a case's boundary conditions against its lattice that the solver makes before
/// it sets them up (docs/case-format.md, "Where a condition acts").

#include "hexdem/meshing/lattice.hpp"
#include "hexdem/solver/case.hpp"

namespace hexdem::solver {

/// Refuses (hexdem::InputError, one line naming the case's `[[boundary]]` entry, the body,
/// the plane and a disk) a body that crosses, or lies beyond, the mirror plane of a
/// `symmetry` condition. The plane is the line x = const (or y = const) through the set's
/// edges; the model side is the side the set's outward normals point away from. A disk whose
/// centre lies beyond the plane by more than the generator's tolerance (meshing::
/// kBoundaryTolerance, 1e-3 of the spacing 2r) is on the mirror side: a half model cannot
/// hold it (its mirror image would overlap it, or the body would be modelled twice). Sets that
/// do not exist or are not straight are left to the solver's own checks.
void check_symmetry_planes(const Case& c, const meshing::Lattice& lattice);

}  // namespace hexdem::solver
