// Checks of a case's boundary conditions against its lattice (boundary_checks.hpp).
#include "hexdem/solver/boundary_checks.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_generator.hpp"

namespace hexdem::solver {
namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

void check_symmetry_planes(const Case& c, const meshing::Lattice& lattice) {
  for (const BoundaryCondition& bc : c.boundaries) {
    if (bc.kind != BoundaryCondition::Kind::Symmetry) continue;
    const int s = lattice.find_set(bc.set);
    if (s < 0) continue;  // unknown set: reported by the solver's set-up
    const auto first = lattice.set_offset[s], last = lattice.set_offset[s + 1];
    if (first == last) continue;
    // The plane: the length-weighted mean position of the set's edges along the normal
    // component; the mirror side: where the outward normals point.
    const int k = bc.component;
    double length = 0, position = 0, normal = 0;
    for (auto e = first; e < last; ++e) {
      const double w = lattice.set_length[e];
      length += w;
      position += w * (k == 0 ? lattice.set_cx[e] : lattice.set_cy[e]);
      normal += w * (k == 0 ? lattice.set_nx[e] : lattice.set_ny[e]);
    }
    if (!(length > 0) || std::abs(normal) < 0.5 * length) continue;  // not straight: solver's check
    double plane = position / length;
    // Round-off of the mean (a plane through the origin comes out as 1e-11 m): below
    // 1e-6 r it is the origin.
    if (std::abs(plane) < 1e-6 * lattice.radius[static_cast<std::size_t>(lattice.set_disk[first])]) plane = 0.0;
    const double outward = normal > 0 ? 1.0 : -1.0;
    // Per body: the disk farthest beyond the plane, and whether the body has disks on the
    // model side too.
    const std::size_t bodies = lattice.body_names.size();
    std::vector<double> worst(bodies, 0.0);
    std::vector<std::int64_t> worst_disk(bodies, -1);
    std::vector<char> inside(bodies, 0);
    // A disk within the generator's tolerance of the plane is on it: the generator puts a
    // lattice point that close to an edge on the edge, on either side of it (a rotated
    // lattice's points near the axis of an axisymmetric model: the warhead case's at 5 degrees
    // come 6.5e-4 r beyond it).
    for (std::size_t i = 0; i < lattice.num_disks(); ++i) {
      const auto b = static_cast<std::size_t>(lattice.body[i]);
      if (b >= bodies) continue;
      const double beyond = ((k == 0 ? lattice.x[i] : lattice.y[i]) - plane) * outward;
      if (beyond > meshing::kBoundaryTolerance * 2.0 * lattice.radius[i]) {
        if (beyond > worst[b]) {
          worst[b] = beyond;
          worst_disk[b] = static_cast<std::int64_t>(i);
        }
      } else {
        inside[b] = 1;
      }
    }
    for (std::size_t b = 0; b < bodies; ++b) {
      if (worst_disk[b] < 0) continue;
      const auto i = static_cast<std::size_t>(worst_disk[b]);
      const char* axis = c.geometry == Geometry::Axisymmetric ? (k == 0 ? "r" : "z") : (k == 0 ? "x" : "y");
      throw InputError(bc.where + ": body '" + lattice.body_names[b] + "' " +
                       (inside[b] ? "crosses" : "lies beyond") + " the symmetry plane " + axis + " = " +
                       number(plane) + " m of set '" + bc.set + "' (its disk at (" + number(lattice.x[i]) +
                       ", " + number(lattice.y[i]) + ") m is " + number(worst[b]) +
                       " m on the mirror side); a symmetric model holds only what lies on the set's side "
                       "of the plane: cut the body at the plane");
    }
  }
}

}  // namespace hexdem::solver
