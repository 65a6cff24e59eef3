#pragma once
/// \file lattice_vtu.hpp
/// Writes a Lattice as a .vtu: points = disk centres, one line cell per bond; point data
/// `radius`, `kind`, `cell_area`, `body`, `material`, one 0/1 UInt8 array per boundary set
/// (named after the set), and in axisymmetric mode `ring_radius` (cell centroid distance from
/// the axis, m); cell data `bond_class`; field data `geometry` ("plane" or "axisymmetric"),
/// `body_names` (one string per body; omitted when there is no body) and `lattice_radius`
/// (disk radius of body 0, m; omitted when body 0 has no disk). docs/file-format.md has the
/// full list with types and units. Throws std::invalid_argument for inconsistent array sizes
/// and std::runtime_error naming the path on an I/O failure.

#include <string>

#include "hexdem/io/vtu_writer.hpp"
#include "hexdem/meshing/lattice.hpp"

namespace hexdem::meshing {

void write_lattice_vtu(const std::string& path, const Lattice& lattice,
                       const io::WriteOptions& options = {});

}  // namespace hexdem::meshing
