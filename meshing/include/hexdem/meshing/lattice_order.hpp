// Reordering a lattice's disks and bonds along a space-filling curve, for memory locality.
//
// The generator numbers the disks row by row within each body (and each body's bonds by their
// first disk), which is already a locality order: a bond joins a disk to the next one in its
// row or to one in the next row. A Hilbert curve (Hilbert 1891; the iterative index of Warren,
// "Hacker's Delight", 2nd ed., section 16-2) instead keeps square patches of disks together,
// so that a disk's neighbours in the rows above and below are near it in memory also when the
// rows are long. docs/benchmarks.md measures both orders ("Disk order").
#pragma once

#include <cstdint>
#include <vector>

#include "hexdem/meshing/lattice.hpp"

namespace hexdem::meshing {

/// The order of the disks in memory.
enum class DiskOrder {
  Rows,     ///< the generator's: row by row within each body
  Hilbert,  ///< a Hilbert curve over the lattice's bounding box, within each body
};

/// Hilbert index of the cell (ix, iy) of a 2^16 x 2^16 grid (0 <= ix, iy < 65536).
[[nodiscard]] std::uint64_t hilbert_index(std::uint32_t ix, std::uint32_t iy);

/// The new index of every disk (`new_of_old[old] = new`) that orders each body's disks along
/// a Hilbert curve through the disk centres. The bodies keep their order and stay contiguous.
[[nodiscard]] std::vector<std::int32_t> hilbert_permutation(const Lattice& lattice);

/// Renumbers the disks (`new_of_old` must be a permutation of 0 .. num_disks - 1): every per-disk
/// array is permuted, each bond joins the renumbered disks with i < j, the bonds are sorted by
/// (i, j), and each boundary set's entries stay ascending by disk. The geometry, the bond
/// classes and the sets' contents are unchanged.
void renumber_disks(Lattice& lattice, const std::vector<std::int32_t>& new_of_old);

/// Puts the lattice in the given order (Rows leaves it as generated).
void apply_disk_order(Lattice& lattice, DiskOrder order);

}  // namespace hexdem::meshing
