#pragma once
/// \file sweep_prune.hpp
/// Contact broad phase for disks: incremental sort-and-update (sweep and prune) over inflated
/// axis-aligned boxes, after Cohen, Lin, Manocha and Ponamgi, "I-COLLIDE", 1995 (the paper's
/// ref. 18; physics.md section 8). The algorithm, its cost and measured figures are in
/// docs/contact-detection.md. Lengths in m.
///
/// Box and margin rule. With h = margin / 2, disk i gets the box
///
///     [xr - (rr + h), xr + (rr + h)] x [yr - (rr + h), yr + (rr + h)]
///
/// computed with exactly these floating-point operations, where (xr, yr, rr) is the disk's
/// reference state: its centre and radius when the box was last set. A box is set at build()
/// and again by update() when the centre has moved more than h from (xr, yr), tested as
/// (x - xr)^2 + (y - yr)^2 > h^2, or when r != rr. So after every update() each disk's
/// current tight box [x - r, x + r] x [y - r, y + r] lies inside its stored box (up to
/// rounding), and every pair of disks whose tight boxes overlap, in particular every pair of
/// touching disks, is a candidate.
///
/// Overlap rule. Boxes are closed: i and j overlap when lo_x(i) <= hi_x(j), lo_x(j) <= hi_x(i),
/// lo_y(i) <= hi_y(j) and lo_y(j) <= hi_y(i). Boxes that touch exactly overlap, equal
/// coordinates are allowed anywhere (lattices, duplicated centres), and the candidate list is
/// exactly the set a brute-force test of all pairs with this rule gives, minus the excluded
/// pairs.

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace hexdem::solver {

/// Stored (inflated) box of one disk [m].
struct SweepBox {
  double lo_x, hi_x, lo_y, hi_y;
};

/// What the last build() or update() did (for tests, benchmarks and diagnostics).
struct SweepStats {
  std::size_t refreshed = 0;   ///< disks whose boxes were set
  std::size_t swaps = 0;       ///< end-point swaps of the incremental sort (0 if rebuilt)
  std::size_t flips = 0;       ///< pairs that entered or left the list
  std::size_t non_finite = 0;  ///< disks skipped: x, y or r not finite, or r < 0
  bool rebuilt = false;        ///< true: full sort and pair search instead of the swaps
};

/// Candidate contact pairs of disks (i < j) whose inflated boxes overlap, kept up to date
/// step by step in O(N + swaps) (docs/contact-detection.md).
///
/// Typical use: set_exclusions() with the intact bonds, build() once, then every step
/// update() with the current centres and radii and read pairs(); call remove_exclusion()
/// when a bond breaks. Not thread-safe; the results do not depend on the thread count or on
/// the order of the calls that led to the current boxes.
///
/// Memory (memory_bytes()): about 220 bytes per disk plus 30 per candidate pair and 4 per
/// excluded pair, including the work space of the full search, which is kept so that
/// update() does not allocate once the pair list has reached its largest size.
class SweepPrune {
 public:
  using Pair = std::pair<std::int32_t, std::int32_t>;

  /// Default fraction of refreshed disks above which update() re-sorts from scratch.
  static constexpr double kDefaultRebuildFraction = 0.25;

  /// Excluded pairs (e.g. the disks joined by intact bonds; the bonds handle them), as a
  /// CSR list over n disks (offsets has n + 1 entries): the neighbours of disk i are
  /// neighbours[offsets[i] .. offsets[i + 1]). The relation is made symmetric (j in the row of i
  /// excludes (i, j) and (j, i)); rows need not be sorted, and duplicates and self-entries are
  /// ignored. The data are copied. May be called before build() (then n must equal build's n) or
  /// after it (the pair list is then recomputed at once). Throws std::logic_error on an index out
  /// of range or decreasing offsets.
  void set_exclusions(const std::int32_t* offsets, const std::int32_t* neighbours, std::size_t n);

  /// Excluded pairs as a list of count pairs (i[k], j[k]) over n disks, e.g. the intact
  /// bonds (bi, bj) of the model; otherwise as set_exclusions().
  void set_exclusion_pairs(const std::int32_t* i, const std::int32_t* j, std::size_t count,
                           std::size_t n);

  /// Drops all exclusions (the pair list is recomputed at once if built).
  void clear_exclusions();

  /// Removes the exclusion of (i, j) in either order, e.g. when their bond breaks; O(row
  /// length), no allocation. The pair enters the list at the next update() if its boxes
  /// overlap then. Returns false if (i, j) was not excluded.
  bool remove_exclusion(std::int32_t i, std::int32_t j);

  /// True if (i, j) is currently excluded.
  [[nodiscard]] bool is_excluded(std::int32_t i, std::int32_t j) const;

  /// Sets every box from the centres x, y [m] and radii r [m] of n disks, sorts the end
  /// points and finds all candidate pairs: O(N log N + pairs). margin >= 0 [m] is the
  /// Verlet skin: each box is inflated by margin / 2 on every side. The arrays are read
  /// during the call only. Throws std::logic_error on a negative or non-finite margin,
  /// non-finite x, y or r, negative r, n >= 2^31, or exclusions set for another n.
  void build(const double* x, const double* y, const double* r, std::size_t n, double margin);

  /// Re-sets the boxes of the disks that moved more than margin / 2 or changed radius (see
  /// the file comment), restores the order of their end points by swaps and updates the
  /// pair list from the swaps: O(N + swaps). If more than rebuild_fraction() of the disks
  /// were refreshed, sorts and searches from scratch instead (same result). The arrays
  /// hold the current centres and radii of the n disks given to build() [m] and are read
  /// during the call only; a disk with a non-finite value or a negative radius keeps its box
  /// (counted in stats().non_finite). Returns true if pairs() changed. Reports no errors;
  /// allocates only while a buffer grows beyond its largest size so far.
  bool update(const double* x, const double* y, const double* r);

  /// Candidate pairs (i < j), sorted by (i, j), excluded pairs left out. Valid until the
  /// next non-const call.
  [[nodiscard]] const std::vector<Pair>& pairs() const noexcept { return pairs_; }

  /// Number of disks given to build().
  [[nodiscard]] std::size_t size() const noexcept { return n_; }

  /// The margin given to build() [m].
  [[nodiscard]] double margin() const noexcept { return margin_; }

  /// Stored box of disk i [m].
  [[nodiscard]] SweepBox box(std::int32_t i) const noexcept {
    const auto k = static_cast<std::size_t>(i);
    return {lo(0, k), hi(0, k), lo(1, k), hi(1, k)};
  }

  /// Bytes held by this object, work space included.
  [[nodiscard]] std::size_t memory_bytes() const noexcept;

  /// Statistics of the last build() or update().
  [[nodiscard]] const SweepStats& stats() const noexcept { return stats_; }

  /// Fraction f of refreshed disks above which update() re-sorts from scratch (f >= 1:
  /// never; f <= 0: whenever a box changes). Only the cost depends on it.
  void set_rebuild_fraction(double f) noexcept { rebuild_fraction_ = f; }
  [[nodiscard]] double rebuild_fraction() const noexcept { return rebuild_fraction_; }

 private:
  /// Box end point on one axis: the coordinate and tag = is_max << 31 | disk. Sorted by
  /// (value, tag), so at equal coordinates every minimum precedes every maximum (closed
  /// boxes) and the order is total.
  struct EndPoint {
    double value;
    std::uint32_t tag;
  };
  struct Axis {
    std::vector<EndPoint> ends;      ///< 2n end points in (value, tag) order
    std::vector<std::uint32_t> pos;  ///< pos[2 disk + is_max]: index in `ends`
  };
  /// One entry of a y band in the full pair search: the box's x minimum (the sweep's test)
  /// and its disk; the other bounds are read from the end points (16 bytes an entry, not 40:
  /// the entries, about two per disk, were a third of the broad phase's memory).
  struct BandBox {
    double lo_x;
    std::uint32_t disk;
  };

  /// The stored box of disk i on axis a, read from its end points (the boxes are not kept
  /// twice).
  [[nodiscard]] double lo(int a, std::size_t i) const noexcept { return axis_[a].ends[axis_[a].pos[2 * i]].value; }
  [[nodiscard]] double hi(int a, std::size_t i) const noexcept {
    return axis_[a].ends[axis_[a].pos[2 * i + 1]].value;
  }

  void start_exclusions(std::size_t n);
  void init_ends();
  void finish_exclusions();
  void set_box(std::size_t i, double x, double y, double r);
  void sort_all(bool fresh);
  void radix_sort_ends(std::vector<EndPoint>& ends) const;
  void find_all_pairs();
  void sift(int axis, std::uint32_t slot);
  bool apply_flips();
  [[nodiscard]] bool overlap(std::int32_t i, std::int32_t j) const noexcept;

  std::size_t n_ = 0;
  bool built_ = false;
  double margin_ = 0;
  double half_margin_ = 0;
  double rebuild_fraction_ = kDefaultRebuildFraction;

  std::vector<double> ref_x_, ref_y_, ref_r_;  ///< reference state of each box [m]
  Axis axis_[2];  ///< per axis: the stored boxes' end points [m] (lo(), hi())

  std::vector<Pair> pairs_, next_;  ///< current list and merge buffer
  std::vector<Pair> flips_;         ///< pairs whose overlap toggled (with repeats)
  std::vector<Pair> pending_;       ///< pairs released by remove_exclusion()
  std::vector<std::uint32_t> refresh_;

  // Exclusions: CSR with each pair once, in the row of its lower disk; each row sorted,
  // excl_len_[i] entries in use.
  std::size_t excl_n_ = 0;
  std::vector<std::uint32_t> excl_off_;  // fewer than 2^31 pairs: the model holds at most 2^30 bonds
  std::vector<std::uint32_t> excl_len_;
  std::vector<std::int32_t> excl_nbr_;

  // Work space of the full pair search.
  std::vector<double> work_;
  std::vector<std::size_t> band_start_, band_fill_;
  std::vector<BandBox> band_boxes_;
  std::vector<std::size_t> row_start_;
  std::vector<std::int32_t> row_nbr_;

  SweepStats stats_;
};

}  // namespace hexdem::solver
