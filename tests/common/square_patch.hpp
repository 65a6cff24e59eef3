#pragma once
/// \file square_patch.hpp
/// A square patch of the regular lattice, for the patch tests of tests/solver/test_patch.cpp
/// and the irregular lattice of tests/solver/test_irregular_lattice.cpp: `cells` x 2r on a
/// side from the origin, no boundary sets, the lattice turned by `angle_deg`. Lengths in m.
#include "hexdem/meshing/lattice_generator.hpp"

namespace hexdem::testing {

inline meshing::Lattice square_patch(double r, int cells, double angle_deg = 0.0) {
  meshing::Outline o;
  meshing::BodyOutline b;
  b.name = "patch";
  b.where = "patch";
  b.angle_deg = angle_deg;
  const double L = cells * 2 * r;
  meshing::Loop loop;
  loop.points = {{0, 0}, {L, 0}, {L, L}, {0, L}};
  loop.edge_set.assign(4, -1);
  loop.edge_straight.assign(4, 1);
  b.outers.push_back(loop);
  o.bodies.push_back(b);
  meshing::GeneratorOptions go;
  go.lattice.radius = r;
  return meshing::generate_lattice(o, go);
}

}  // namespace hexdem::testing
