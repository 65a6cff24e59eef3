// Moving the interior disks of a lattice off their hexagonal sites: an irregular lattice.
//
// A regular hexagonal lattice has three close-packed directions along which its bonds line up
// and its broken disks slide; its cracks and its damaged zones follow them (docs/model.md,
// "Irregular lattice"). Random lattices of the rigid-body-spring and lattice models of
// concrete (Bolander and Saito 1998; Jirasek and Bazant 1995, who perturb a regular lattice's
// nodes; Grassl and Jirasek 2010) have no such directions. This keeps the hexagonal topology
// (six bonds per interior disk, the cells, the sets and the boundary disks) and moves every
// interior disk by a random vector of length at most `fraction` r, uniform over the disk of
// that radius; a bond's rest length and direction are then its own (the model's per-bond
// reference geometry).
#pragma once

#include <cstdint>
#include <vector>

#include "hexdem/meshing/lattice.hpp"

namespace hexdem::meshing {

/// Largest jitter fraction: at 0.3 r no two bonded disks come closer than 1.4 r and no two
/// unbonded ones closer than 2.26 r (the second neighbours, 2 sqrt(3) r apart on the sites),
/// so no disk overlaps another that it is not bonded to.
inline constexpr double kMaxJitter = 0.3;

/// Moves each interior disk of `lattice` (a full disk whose cell is the whole hexagon
/// 2 sqrt(3) r^2, with six bonds, in no boundary set) by a random vector of length at most
/// `fraction` times its radius, its cell's centroid with it; axisymmetric lattices get their
/// bonds' ring radii (bond_b) again. The vector of a disk depends only on `seed` and the
/// disk's position on its site (not on the disk's index or the thread count), so the same case
/// gives the same lattice in any disk order. `fraction` must lie in [0, kMaxJitter]; 0 leaves
/// the lattice unchanged. Returns the number of disks moved.
std::int64_t jitter_lattice(Lattice& lattice, double fraction, std::uint64_t seed);

/// Interior disks of `lattice`, 1 per disk: a full disk with six bonds whose cell is the whole
/// hexagon 2 sqrt(3) r^2, in no boundary set. The disks that jitter_lattice moves and that
/// contact_radii spreads; the rest (the outline's edges, semi-disks, sets) stay as generated.
std::vector<std::uint8_t> interior_disks(const Lattice& lattice);

/// Largest spread of the contact radii: an interior disk's unbonded neighbours are at least
/// 2 sqrt(3) r - 2 kMaxJitter r = 2.26 r away (second neighbours, both moved towards each
/// other), so contact radii up to 1.13 r never overlap a disk they are not bonded to.
inline constexpr double kMaxRadiusSpread = 0.13;

/// Contact radii of a polydisperse broken packing ([contact] radius_spread, docs/model.md,
/// "Contact radii"): an interior disk's contact radius is r (1 + s (2u - 1)) [m], u uniform in
/// [0, 1) from `seed` and the disk's position (not its index: the same in any disk order);
/// every other disk keeps r. Mass, cell and bonds keep r. Empty when s = 0; s must lie in
/// [0, kMaxRadiusSpread].
std::vector<double> contact_radii(const Lattice& lattice, double spread, std::uint64_t seed);

}  // namespace hexdem::meshing
