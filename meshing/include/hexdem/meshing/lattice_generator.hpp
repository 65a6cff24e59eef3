#pragma once
/// \file lattice_generator.hpp
/// Fills the bodies of an Outline with disks and semi-disks on a hexagonal lattice
/// (physics.md section 1; the paper's Section 2 and Eq. 9).
///
/// Method. Each body is filled independently in its own lattice frame (angle, origin).
/// Lattice rows are classified by a scanline over the outline's edges (O(rows x crossings)),
/// so the cost is linear in the number of disks, not in disks x edges. Only lattice points
/// whose hexagonal cell meets an outline edge are treated specially: their cell is the
/// hexagon clipped by the outline (exact Green's-theorem area and centroid); the pieces of
/// the region that fall in the hexagons of lattice points outside the region are added to the
/// nearest inside neighbour, so that the cell areas of a body sum to its region's area.
/// Lattice points on a straight outline edge that runs along a lattice line (the paper's
/// "neat boundary") are semi-disks; their cell is half a hexagon.

#include <cstdint>
#include <string>

#include "hexdem/meshing/lattice.hpp"
#include "hexdem/meshing/outline.hpp"

namespace hexdem::meshing {

/// Default limit on the number of disks of one generation (GeneratorOptions::max_disks).
inline constexpr std::int64_t kDefaultMaxDisks = 100'000'000;

/// The generator's geometric tolerance, in units of the lattice spacing d = 2r: a lattice
/// point this close to an outline edge is on the edge (it becomes a disk even when it lies
/// just outside), and an edge whose end points are this close to one lattice line runs along
/// it. Checks of disks against an outline's lines (boundary_checks.cpp) use the same.
inline constexpr double kBoundaryTolerance = 1e-3;

/// Memory `hexdem mesh` needs per disk, for messages [bytes]: the disk arrays (x, y, radius,
/// cell area and centroid, kind, body, material: 57 bytes), three bonds (10 bytes each) and
/// the generator's and writer's working arrays. Measured: 143 MB peak resident for a
/// 1,155,578-disk rectangle (docs/outline-format.md, "Size limit").
inline constexpr double kLatticeBytesPerDisk = 125.0;

struct GeneratorOptions {
  LatticeOptions lattice;                       ///< defaults for bodies that set none
  GeometryMode mode = GeometryMode::Plane;
  /// Refuse (InputError, before allocating) an outline whose estimated disk count
  /// (region area / hexagon area, summed over the bodies) exceeds this.
  std::int64_t max_disks = kDefaultMaxDisks;
  /// Appended to the too-many-disks message: how to raise the limit where the options
  /// came from (e.g. "--max-disks N").
  std::string max_disks_hint = "--max-disks N";
};

/// Ceiling the outline readers apply (check_lattice_size before validating the loops, so that
/// absurd outlines are refused before CGAL works on millions of arc chords); the generator
/// then applies GeneratorOptions::max_disks.
inline constexpr std::int64_t kMaxDisksCeiling = 1'000'000'000'000;

/// The size limit the outline readers check before validating the loops: the caller's limit
/// (ReadOptions::max_disks, if > 0; with its hint) or else the ceiling, whichever is smaller.
[[nodiscard]] GeneratorOptions reader_size_limit(std::int64_t max_disks, const std::string& hint);

/// Throws InputError, before anything is allocated, when a lattice index of a body would pass
/// 2^30 or the estimated disk count (region area / hexagon area 2 sqrt(3) r^2, at least one
/// per lattice row, summed over the bodies) exceeds options.max_disks. Bodies need a radius
/// (from the body or options.lattice).
void check_lattice_size(const Outline& outline, const GeneratorOptions& options);

/// Point array names of mesh and result frames that a boundary set may not take (a set is
/// written as a point array of its name).
bool is_reserved_array_name(const std::string& name);

/// Figures of a generation, for the summary line and tests.
struct GeneratorReport {
  std::int64_t disks = 0;
  std::int64_t semi_disks = 0;
  std::int64_t bonds = 0;
  double region_area = 0.0;        ///< sum of the bodies' region areas [m^2]
  double cell_area_sum = 0.0;      ///< sum of the cell areas [m^2]
  double lost_area = 0.0;          ///< region area that no disk could take [m^2]
  double min_cell_fraction = 0.0;  ///< smallest cell area / full hexagon area
  double seconds = 0.0;            ///< wall time of the generation
  [[nodiscard]] double area_error() const {
    return region_area > 0 ? (cell_area_sum - region_area) / region_area : 0.0;
  }
};

/// Generates the lattice. The outline must have been through validate_and_orient().
/// Throws InputError for a radius <= 0, a body that receives no disk (radius too large for the
/// region), an outline that would need more than options.max_disks disks or a lattice index
/// beyond 2^30 (both checked before anything is allocated), a boundary set named like a
/// point array (is_reserved_array_name), or, in axisymmetric mode, a region reaching r < 0
/// or a disk with zero weight.
Lattice generate_lattice(const Outline& outline, const GeneratorOptions& options,
                         GeneratorReport* report = nullptr);

}  // namespace hexdem::meshing
