#pragma once
/// \file lattice.hpp
/// The disk lattice as structure-of-arrays, ready for the solver (physics.md section 1).
/// Per-disk arrays have num_disks() entries, per-bond arrays num_bonds(). All lengths are
/// metres, areas m^2. The Lattice owns all its data.

#include <cstdint>
#include <string>
#include <vector>

namespace hexdem::meshing {

/// Geometry mode: plane (x, y) or axisymmetric meridian half-plane (r, z), r = x >= 0.
enum class GeometryMode : std::uint8_t { Plane = 0, Axisymmetric = 1 };

/// Disk kind, as written to the `kind` point array.
enum class DiskKind : std::uint8_t { Disk = 0, SemiDisk = 1 };

struct Lattice {
  GeometryMode mode = GeometryMode::Plane;

  // Per disk.
  std::vector<double> x, y;              ///< centre [m] (axisymmetric: r, z)
  std::vector<double> radius;            ///< disk radius r [m]
  std::vector<double> cell_area;         ///< area of the disk's cell [m^2] (Eq. 9 inside,
                                         ///< the hexagon clipped by the outline at the boundary)
  std::vector<double> cell_cx, cell_cy;  ///< centroid of the cell [m]; in axisymmetric mode
                                         ///< cell_cx is the ring radius b used for the weight
  std::vector<std::uint8_t> kind;        ///< DiskKind
  std::vector<std::int32_t> body;        ///< index into body_names
  std::vector<std::int32_t> material;    ///< material id of the body

  // Per bond (pairs of disks of the same body at distance 2r, i < j).
  std::vector<std::int32_t> bond_i, bond_j;
  std::vector<std::uint8_t> bond_class;  ///< 1 along the lattice axis, 2 the other directions
  std::vector<std::uint8_t> bond_on_edge;  ///< 1 if the bond lies along a neat outline edge
                                           ///< (between two semi-disks): half its cell is
                                           ///< outside, so its springs are halved
  std::vector<double> bond_b;            ///< axisymmetric only: bond midpoint distance from
                                         ///< the axis [m]; empty in plane mode

  // Boundary sets, compressed rows: set s owns entries set_offset[s] .. set_offset[s+1]-1.
  // A disk belongs to a set when part of the named outline edges lies on its cell's boundary;
  // each entry carries that length and its mean outward unit normal (for pressure loads).
  std::vector<std::string> set_names;
  std::vector<std::int64_t> set_offset;  ///< size set_names.size() + 1
  std::vector<std::int32_t> set_disk;    ///< disk index, ascending within a set
  std::vector<double> set_length;        ///< length of the named edges on the disk's cell [m]
  std::vector<double> set_nx, set_ny;    ///< mean outward unit normal of those edges
  std::vector<double> set_cx, set_cy;    ///< length-weighted mean position of those edges [m]
                                         ///< (axisymmetric loads act at its radius)
  std::vector<double> set_distance;      ///< distance of the disk centre from those edges [m];
                                         ///< boundary conditions hold the members closer than r

  std::vector<std::string> body_names;   ///< body index -> name
  std::vector<double> body_region_area;  ///< area of each body's region [m^2] (exact polygon)

  [[nodiscard]] std::size_t num_disks() const { return x.size(); }
  [[nodiscard]] std::size_t num_bonds() const { return bond_i.size(); }
  [[nodiscard]] std::size_t num_sets() const { return set_names.size(); }

  /// Index of a set by name, or -1.
  [[nodiscard]] int find_set(const std::string& name) const;

  /// 0/1 membership of set s for every disk (for output).
  [[nodiscard]] std::vector<std::uint8_t> set_membership(std::size_t s) const;

  /// Bytes held by the arrays (capacity), for memory reports.
  [[nodiscard]] std::size_t memory_bytes() const;
};

}  // namespace hexdem::meshing
