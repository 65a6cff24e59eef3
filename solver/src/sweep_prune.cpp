// Incremental sweep and prune over inflated disk boxes (docs/contact-detection.md).
//
// State: per axis, the 2n box end points sorted by (value, tag) with the index of every end
// point (`pos`), and the sorted list of overlapping pairs. The pair list is a function of
// the two orders only: i and j overlap iff min(i) precedes max(j) and min(j) precedes max(i)
// on both axes. Moving one end point past another changes exactly one of these four
// "precedes" relations for one pair, so the pair's status toggles iff the other three hold,
// which the `pos` arrays answer in O(1). This is the swap rule of Cohen et al. without
// per-pair, per-axis overlap records: those would have to be kept for every pair overlapping
// on one axis only, about N^1.5 pairs for a 2D packing.

#include "hexdem/solver/sweep_prune.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "hexdem/error.hpp"

namespace hexdem::solver {
namespace {

constexpr std::uint32_t kMaxBit = 0x80000000u;
constexpr std::uint32_t kDiskMask = 0x7fffffffu;

/// Index of an end point in `pos`: 2 disk + is_max.
inline std::uint32_t slot_of(std::uint32_t tag) {
  return 2 * (tag & kDiskMask) + (tag >> 31);
}

inline SweepPrune::Pair ordered(std::uint32_t a, std::uint32_t b) {
  const auto i = static_cast<std::int32_t>(a), j = static_cast<std::int32_t>(b);
  return i < j ? SweepPrune::Pair{i, j} : SweepPrune::Pair{j, i};
}

/// Number of pairs in exactly one of two sorted lists.
std::size_t count_changes(const std::vector<SweepPrune::Pair>& a,
                          const std::vector<SweepPrune::Pair>& b) {
  std::size_t i = 0, j = 0, common = 0;
  while (i < a.size() && j < b.size()) {
    if (a[i] < b[j]) {
      ++i;
    } else if (b[j] < a[i]) {
      ++j;
    } else {
      ++common;
      ++i;
      ++j;
    }
  }
  return a.size() + b.size() - 2 * common;
}

}  // namespace

void SweepPrune::start_exclusions(std::size_t n) {
  HEXDEM_VERIFY(!built_ || n == n_,
                "exclusions for " + std::to_string(n) + " disks, built with " + std::to_string(n_));
  HEXDEM_VERIFY(n < kMaxBit, "too many disks: " + std::to_string(n));
  excl_n_ = n;
  excl_off_.assign(n + 1, 0);
  excl_len_.assign(n, 0);
}

// Rows are counted into excl_off_[i + 1] and filled through excl_len_; this sorts and
// deduplicates them and, if built, recomputes the pair list.
void SweepPrune::finish_exclusions() {
  const std::size_t n = excl_n_;
  for (std::size_t i = 0; i < n; ++i) {
    auto* first = excl_nbr_.data() + excl_off_[i];
    auto* last = first + excl_len_[i];
    std::sort(first, last);
    excl_len_[i] = static_cast<std::uint32_t>(std::unique(first, last) - first);
  }
  if (built_) {
    pending_.clear();
    find_all_pairs();
  }
}

void SweepPrune::set_exclusions(const std::int32_t* offsets, const std::int32_t* neighbours,
                                std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    HEXDEM_VERIFY(offsets[i] >= 0 && offsets[i] <= offsets[i + 1],
                  "exclusion offsets decrease at disk " + std::to_string(i));
  }
  for (std::int32_t k = offsets[0]; k < offsets[n]; ++k) {
    HEXDEM_VERIFY(neighbours[k] >= 0 && static_cast<std::size_t>(neighbours[k]) < n,
                  "excluded neighbour out of range: " + std::to_string(neighbours[k]));
  }
  start_exclusions(n);
  // Each pair once, in the row of its lower disk: count, prefix sums, scatter.
  for (std::size_t i = 0; i < n; ++i) {
    for (std::int32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const auto j = static_cast<std::size_t>(neighbours[k]);
      if (j == i) continue;
      ++excl_off_[std::min(i, j) + 1];
    }
  }
  for (std::size_t i = 0; i < n; ++i) excl_off_[i + 1] += excl_off_[i];
  excl_nbr_.assign(excl_off_[n], 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::int32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const auto j = static_cast<std::size_t>(neighbours[k]);
      if (j == i) continue;
      const std::size_t lo = std::min(i, j);
      excl_nbr_[excl_off_[lo] + excl_len_[lo]++] = static_cast<std::int32_t>(std::max(i, j));
    }
  }
  finish_exclusions();
}

void SweepPrune::set_exclusion_pairs(const std::int32_t* i, const std::int32_t* j,
                                     std::size_t count, std::size_t n) {
  HEXDEM_VERIFY(count < (std::size_t{1} << 32), "too many excluded pairs: " + std::to_string(count));
  for (std::size_t k = 0; k < count; ++k) {
    HEXDEM_VERIFY(i[k] >= 0 && j[k] >= 0 && static_cast<std::size_t>(i[k]) < n &&
                      static_cast<std::size_t>(j[k]) < n,
                  "excluded pair " + std::to_string(k) + " out of range");
  }
  start_exclusions(n);
  for (std::size_t k = 0; k < count; ++k) {
    if (i[k] == j[k]) continue;
    ++excl_off_[static_cast<std::size_t>(std::min(i[k], j[k])) + 1];
  }
  for (std::size_t d = 0; d < n; ++d) excl_off_[d + 1] += excl_off_[d];
  excl_nbr_.assign(excl_off_[n], 0);
  for (std::size_t k = 0; k < count; ++k) {
    if (i[k] == j[k]) continue;
    const auto lo = static_cast<std::size_t>(std::min(i[k], j[k]));
    excl_nbr_[excl_off_[lo] + excl_len_[lo]++] = std::max(i[k], j[k]);
  }
  finish_exclusions();
}

void SweepPrune::clear_exclusions() {
  excl_n_ = 0;
  excl_off_.clear();
  excl_len_.clear();
  excl_nbr_.clear();
  if (built_) {
    pending_.clear();
    find_all_pairs();
  }
}

bool SweepPrune::is_excluded(std::int32_t i, std::int32_t j) const {
  if (excl_off_.empty()) return false;
  HEXDEM_ASSERT(i >= 0 && j >= 0 && static_cast<std::size_t>(i) < excl_n_ &&
                    static_cast<std::size_t>(j) < excl_n_,
                "disk index out of range");
  if (i > j) std::swap(i, j);  // the pair is in its lower disk's row
  const auto* first = excl_nbr_.data() + excl_off_[i];
  const auto* last = first + excl_len_[i];
  if (last - first <= 16) return std::find(first, last, j) != last;
  return std::binary_search(first, last, j);
}

bool SweepPrune::remove_exclusion(std::int32_t i, std::int32_t j) {
  if (excl_off_.empty() || i == j) return false;
  const auto erase = [this](std::int32_t row, std::int32_t col) {
    auto* first = excl_nbr_.data() + excl_off_[row];
    auto* last = first + excl_len_[row];
    auto* it = std::lower_bound(first, last, col);
    if (it == last || *it != col) return false;
    std::copy(it + 1, last, it);
    --excl_len_[row];
    return true;
  };
  if (!erase(std::min(i, j), std::max(i, j))) return false;  // the lower disk's row holds the pair
  // At rest the stored boxes and the end-point orders agree, so the values decide.
  if (built_ && overlap(i, j)) {
    pending_.push_back(ordered(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)));
  }
  return true;
}

std::size_t SweepPrune::memory_bytes() const noexcept {
  const auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  std::size_t total = sizeof(*this);
  total += bytes(ref_x_) + bytes(ref_y_) + bytes(ref_r_);
  for (int a = 0; a < 2; ++a) {
    total += bytes(axis_[a].ends) + bytes(axis_[a].pos);
  }
  total += bytes(pairs_) + bytes(next_) + bytes(flips_) + bytes(pending_) + bytes(refresh_);
  total += bytes(excl_off_) + bytes(excl_len_) + bytes(excl_nbr_);
  total += bytes(work_) + bytes(band_start_) + bytes(band_fill_) + bytes(band_boxes_);
  total += bytes(row_start_) + bytes(row_nbr_);
  return total;
}

bool SweepPrune::overlap(std::int32_t i, std::int32_t j) const noexcept {
  const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(j);
  return lo(0, a) <= hi(0, b) && lo(0, b) <= hi(0, a) && lo(1, a) <= hi(1, b) && lo(1, b) <= hi(1, a);
}

void SweepPrune::set_box(std::size_t i, double x, double y, double r) {
  ref_x_[i] = x;
  ref_y_[i] = y;
  ref_r_[i] = r;
  const double w = r + half_margin_;  // the header's box rule, operation for operation
  // Written into the end points in place: the order is restored by the caller (sift or
  // sort_all).
  axis_[0].ends[axis_[0].pos[2 * i]].value = x - w;
  axis_[0].ends[axis_[0].pos[2 * i + 1]].value = x + w;
  axis_[1].ends[axis_[1].pos[2 * i]].value = y - w;
  axis_[1].ends[axis_[1].pos[2 * i + 1]].value = y + w;
}

void SweepPrune::build(const double* x, const double* y, const double* r, std::size_t n,
                       double margin) {
  HEXDEM_VERIFY(std::isfinite(margin) && margin >= 0,
                "sweep and prune margin must be finite and >= 0, got " + std::to_string(margin));
  HEXDEM_VERIFY(n < kMaxBit, "too many disks: " + std::to_string(n));
  HEXDEM_VERIFY(excl_off_.empty() || excl_n_ == n, "exclusions set for " + std::to_string(excl_n_) +
                                                       " disks, building " + std::to_string(n));
  for (std::size_t i = 0; i < n; ++i) {
    HEXDEM_VERIFY(std::isfinite(x[i]) && std::isfinite(y[i]) && std::isfinite(r[i]) && r[i] >= 0,
                  "disk " + std::to_string(i) + ": non-finite centre or bad radius");
  }
  n_ = n;
  margin_ = margin;
  half_margin_ = 0.5 * margin;
  ref_x_.resize(n);
  ref_y_.resize(n);
  ref_r_.resize(n);
  init_ends();
  for (std::size_t i = 0; i < n; ++i) set_box(i, x[i], y[i], r[i]);
  sort_all(true);
  pending_.clear();
  find_all_pairs();
  built_ = true;

  // Size the buffers of the steady state.
  const std::size_t slack = pairs_.size() / 4 + 1024;
  pairs_.reserve(pairs_.size() + slack);
  next_.reserve(pairs_.capacity());
  flips_.reserve(std::max(flips_.capacity(), n / 4 + 1024));
  pending_.reserve(1024);
  refresh_.reserve(n);

  stats_ = {};
  stats_.refreshed = n;
  stats_.rebuilt = true;
}

// Every disk's two end points per axis, unsorted (minimum, maximum of disk i at 2i, 2i + 1),
// for set_box to fill in before sort_all.
void SweepPrune::init_ends() {
  const auto n = static_cast<std::uint32_t>(n_);
  for (int a = 0; a < 2; ++a) {
    Axis& ax = axis_[a];
    ax.ends.assign(2 * std::size_t{n}, {});
    ax.pos.resize(2 * std::size_t{n});
    for (std::uint32_t i = 0; i < n; ++i) {
      ax.ends[2 * i].tag = i;
      ax.ends[2 * i + 1].tag = kMaxBit | i;
      ax.pos[2 * i] = 2 * i;
      ax.pos[2 * i + 1] = 2 * i + 1;
    }
  }
}

// Sorts one axis's end points by (value, tag) with a stable LSD radix sort on 16-bit digits of
// the values' order-preserving bit patterns, started from the tag order (minima of disks 0 to
// n - 1, then their maxima): the order of the comparison sort, (value, tag), in O(n) instead
// of O(n log n) (0.2 s of the set-up at 1,000,000 disks; docs/benchmarks.md, "Set-up").
// Digits that all end points share are skipped. The work space, one more copy of the end
// points, lives during the call only (the first build; update() sorts in place).
void SweepPrune::radix_sort_ends(std::vector<EndPoint>& ends) const {
  const std::size_t n = n_;
  std::vector<EndPoint> other(ends.size());
  for (const EndPoint& e : ends) other[(e.tag & kDiskMask) + (e.tag >> 31) * n] = e;  // tag order
  // -0 as +0 (they compare equal, so the tag decides); negative values reversed below positive.
  const auto key = [](double v) {
    const auto u = std::bit_cast<std::uint64_t>(v == 0.0 ? 0.0 : v);
    return (u >> 63) != 0 ? ~u : u | (std::uint64_t{1} << 63);
  };
  constexpr std::size_t kBuckets = 1 << 16;
  std::vector<std::size_t> count(4 * kBuckets, 0);
  for (const EndPoint& e : other) {
    const std::uint64_t k = key(e.value);
    for (std::size_t d = 0; d < 4; ++d) ++count[d * kBuckets + ((k >> (16 * d)) & 0xffff)];
  }
  std::vector<EndPoint>* from = &other;
  std::vector<EndPoint>* to = &ends;
  for (std::size_t d = 0; d < 4; ++d) {
    std::size_t* c = count.data() + d * kBuckets;
    if (std::any_of(c, c + kBuckets, [&](std::size_t v) { return v == from->size(); })) continue;  // one digit
    std::size_t sum = 0;
    for (std::size_t b = 0; b < kBuckets; ++b) sum += std::exchange(c[b], sum);
    for (const EndPoint& e : *from) (*to)[c[(key(e.value) >> (16 * d)) & 0xffff]++] = e;
    std::swap(from, to);
  }
  if (from != &ends) ends.swap(other);
}

// Sorts each axis's end points (their values set by set_box) and indexes their positions:
// from scratch by radix sort (build), or in place by comparison (update()'s re-sort, which
// allocates nothing; its order is almost right already).
void SweepPrune::sort_all(bool fresh) {
  const auto n = static_cast<std::uint32_t>(n_);
  for (int a = 0; a < 2; ++a) {
    Axis& ax = axis_[a];
    if (fresh) {
      radix_sort_ends(ax.ends);
    } else {
      std::sort(ax.ends.begin(), ax.ends.end(), [](const EndPoint& p, const EndPoint& q) {
        return p.value < q.value || (p.value == q.value && p.tag < q.tag);
      });
    }
    for (std::uint32_t k = 0; k < 2 * n; ++k) ax.pos[slot_of(ax.ends[k].tag)] = k;
  }
}

// All overlapping pairs from scratch. A plain sweep along x tests every pair that overlaps
// in x, about N^1.5 for a 2D packing, so the sweep runs in horizontal bands instead: a box
// is listed in every band its y range meets (in x order), each band is swept along x, and
// a pair is reported only in the band that holds the bottom of the two boxes' common y
// range, so exactly once. Band height: the median box height, doubled while the band
// entries exceed 6 per disk (a few giant disks). Cost O(N log N + pairs + entries).
void SweepPrune::find_all_pairs() {
  std::swap(pairs_, next_);  // the previous list stays in next_ for the caller to compare
  pairs_.clear();
  const std::size_t n = n_;
  if (n < 2) return;

  const double ymin = axis_[1].ends.front().value;
  const double span = axis_[1].ends.back().value - ymin;
  // The bands' height: the median box height of at most 4,096 boxes (every k-th): it sets how
  // fast the search is, not what it finds.
  const std::size_t stride = std::max<std::size_t>(1, n / 4096);
  work_.clear();
  for (std::size_t i = 0; i < n; i += stride) work_.push_back(hi(1, i) - lo(1, i));
  std::nth_element(work_.begin(), work_.begin() + static_cast<std::ptrdiff_t>(work_.size() / 2), work_.end());
  double height = work_[work_.size() / 2];
  if (!(height > 0)) height = span / std::sqrt(static_cast<double>(n));

  std::size_t nb = 1;
  double inv = 0;
  const auto band_of = [&](double v) {
    const double t = (v - ymin) * inv;  // monotone in v, so bands of a box are contiguous
    return t >= static_cast<double>(nb - 1) ? nb - 1 : static_cast<std::size_t>(t);
  };
  for (;;) {
    nb = 1;
    inv = 0;
    if (height > 0 && span > 0) {
      const double q = span / height;
      if (q >= static_cast<double>(n)) {
        nb = n;
        inv = static_cast<double>(n) / span;
      } else {
        nb = static_cast<std::size_t>(q) + 1;
        inv = 1 / height;
      }
    }
    band_start_.assign(nb + 1, 0);
    std::size_t entries = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t b0 = band_of(lo(1, i)), b1 = band_of(hi(1, i));
      entries += b1 - b0 + 1;
      for (std::size_t b = b0; b <= b1; ++b) ++band_start_[b + 1];
      if (entries > 6 * n) break;
    }
    if (entries <= 6 * n || nb == 1) break;
    height *= 2;
  }
  for (std::size_t b = 0; b < nb; ++b) band_start_[b + 1] += band_start_[b];
  band_fill_.assign(band_start_.begin(), band_start_.end() - 1);
  band_boxes_.resize(band_start_[nb]);
  for (const EndPoint& e : axis_[0].ends) {  // minima in x order: each band comes out sorted
    if (e.tag & kMaxBit) continue;
    const std::uint32_t i = e.tag;
    const BandBox bb{e.value, i};
    const std::size_t b0 = band_of(lo(1, i)), b1 = band_of(hi(1, i));
    for (std::size_t b = b0; b <= b1; ++b) band_boxes_[band_fill_[b]++] = bb;
  }

  // Found pairs go to flips_ (unused between updates), then are bucketed by i.
  flips_.clear();
  for (std::size_t b = 0; b < nb; ++b) {
    const BandBox* bb = band_boxes_.data();
    const std::size_t end = band_start_[b + 1];
    for (std::size_t k = band_start_[b]; k < end; ++k) {
      // Only x's minimum is kept per entry (the sweep's test); the rest from the end points.
      const std::uint32_t pi = bb[k].disk;
      const double p_hi_x = hi(0, pi), p_lo_y = lo(1, pi), p_hi_y = hi(1, pi);
      for (std::size_t m = k + 1; m < end && bb[m].lo_x <= p_hi_x; ++m) {
        const std::uint32_t qi = bb[m].disk;
        const double q_lo_y = lo(1, qi), q_hi_y = hi(1, qi);
        if (q_lo_y <= p_hi_y && p_lo_y <= q_hi_y && band_of(std::max(p_lo_y, q_lo_y)) == b) {
          const Pair pr = ordered(pi, qi);
          if (!is_excluded(pr.first, pr.second)) flips_.push_back(pr);
        }
      }
    }
  }
  row_start_.assign(n + 1, 0);
  for (const Pair& p : flips_) ++row_start_[p.first + 1];
  for (std::size_t i = 0; i < n; ++i) row_start_[i + 1] += row_start_[i];
  row_nbr_.resize(flips_.size());
  for (const Pair& p : flips_) row_nbr_[row_start_[p.first]++] = p.second;  // row ends
  pairs_.resize(flips_.size());
  std::size_t out = 0;
  for (std::size_t i = 0, begin = 0; i < n; ++i) {
    const std::size_t end = row_start_[i];
    std::sort(row_nbr_.begin() + static_cast<std::ptrdiff_t>(begin),
              row_nbr_.begin() + static_cast<std::ptrdiff_t>(end));
    for (std::size_t k = begin; k < end; ++k) {
      pairs_[out++] = {static_cast<std::int32_t>(i), row_nbr_[k]};
    }
    begin = end;
  }
  flips_.clear();
}

// Moves one end point to its place in the order of its axis. Every time it passes an end
// point of the other kind (a minimum passing a maximum or the reverse) of another disk, one
// "precedes" relation of that pair flips; the pair toggles iff the other three hold now.
void SweepPrune::sift(int a, std::uint32_t slot) {
  Axis& ax = axis_[a];
  EndPoint* e = ax.ends.data();
  std::uint32_t* pos = ax.pos.data();
  const std::uint32_t* opos = axis_[1 - a].pos.data();
  const auto size = static_cast<std::uint32_t>(ax.ends.size());

  std::uint32_t k = pos[slot];
  const EndPoint m = e[k];
  const std::uint32_t mdisk = m.tag & kDiskMask;
  const bool m_is_max = (m.tag & kMaxBit) != 0;
  std::size_t swaps = 0;

  const auto cross = [&](std::uint32_t otag) {
    if (((otag ^ m.tag) & kMaxBit) == 0) return;  // min past min, max past max: no change
    const std::uint32_t odisk = otag & kDiskMask;
    HEXDEM_ASSERT(odisk != mdisk, "end points of one box crossed");
    // The flipped relation: min(da) precedes max(db) on this axis. The other one on this
    // axis, min(db) precedes max(da), holds whenever these two end points are adjacent,
    // because every box's minimum precedes its maximum. The end point that moves takes part
    // in neither relation on the other axis, so the stored positions answer them.
    const std::uint32_t da = m_is_max ? odisk : mdisk;
    const std::uint32_t db = m_is_max ? mdisk : odisk;
    HEXDEM_ASSERT(pos[2 * db] < pos[2 * da + 1], "box end points out of order");
    if (opos[2 * da] < opos[2 * db + 1] && opos[2 * db] < opos[2 * da + 1]) {
      flips_.push_back(ordered(da, db));
    }
  };

  while (k > 0 &&
         (m.value < e[k - 1].value || (m.value == e[k - 1].value && m.tag < e[k - 1].tag))) {
    const EndPoint o = e[k - 1];
    cross(o.tag);
    e[k] = o;
    pos[slot_of(o.tag)] = k;
    --k;
    ++swaps;
  }
  while (k + 1 < size &&
         (e[k + 1].value < m.value || (e[k + 1].value == m.value && e[k + 1].tag < m.tag))) {
    const EndPoint o = e[k + 1];
    cross(o.tag);
    e[k] = o;
    pos[slot_of(o.tag)] = k;
    ++k;
    ++swaps;
  }
  e[k] = m;
  pos[slot] = k;
  stats_.swaps += swaps;
}

bool SweepPrune::update(const double* x, const double* y, const double* r) {
  stats_ = {};
  if (!built_) return false;
  const std::size_t n = n_;
  const double* rx = ref_x_.data();
  const double* ry = ref_y_.data();
  const double* rr = ref_r_.data();
  const double h2 = half_margin_ * half_margin_;

  refresh_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = x[i] - rx[i], dy = y[i] - ry[i];
    // Written so that NaN takes the refresh branch, where it is caught below.
    if (!(dx * dx + dy * dy <= h2) || r[i] != rr[i]) {
      refresh_.push_back(static_cast<std::uint32_t>(i));
    }
  }
  std::size_t kept = 0;
  for (const std::uint32_t i : refresh_) {
    if (std::isfinite(x[i]) && std::isfinite(y[i]) && std::isfinite(r[i]) && r[i] >= 0) {
      refresh_[kept++] = i;
    }
  }
  stats_.non_finite = refresh_.size() - kept;
  refresh_.resize(kept);
  stats_.refreshed = kept;

  if (static_cast<double>(kept) > rebuild_fraction_ * static_cast<double>(n)) {
    for (const std::uint32_t i : refresh_) set_box(i, x[i], y[i], r[i]);
    sort_all(false);
    pending_.clear();
    find_all_pairs();  // the previous list is left in next_
    stats_.rebuilt = true;
    stats_.flips = count_changes(next_, pairs_);
    return stats_.flips > 0;
  }

  for (const std::uint32_t i : refresh_) {
    const double old_hi[2] = {hi(0, i), hi(1, i)};
    set_box(i, x[i], y[i], r[i]);  // both axes' values; the order is restored below
    for (int a = 0; a < 2; ++a) {
      // Move the leading end first so that the box's own end points never block each other.
      if (hi(a, i) > old_hi[a]) {
        sift(a, 2 * i + 1);
        sift(a, 2 * i);
      } else {
        sift(a, 2 * i);
        sift(a, 2 * i + 1);
      }
    }
  }
  flips_.insert(flips_.end(), pending_.begin(), pending_.end());
  pending_.clear();
  return apply_flips();
}

// Toggles the pairs listed an odd number of times in flips_ (excluded pairs are dropped;
// remove_exclusion() appended its pairs) by one merge pass over the sorted pair list.
bool SweepPrune::apply_flips() {
  std::sort(flips_.begin(), flips_.end());
  std::size_t kept = 0;
  for (std::size_t k = 0; k < flips_.size();) {
    std::size_t end = k + 1;
    while (end < flips_.size() && flips_[end] == flips_[k]) ++end;
    if ((end - k) % 2 == 1 && !is_excluded(flips_[k].first, flips_[k].second)) {
      flips_[kept++] = flips_[k];
    }
    k = end;
  }
  flips_.resize(kept);
  stats_.flips = kept;
  if (kept == 0) return false;

  next_.clear();
  auto it = pairs_.cbegin();
  for (const Pair& f : flips_) {
    const auto at = std::lower_bound(it, pairs_.cend(), f);
    next_.insert(next_.end(), it, at);
    if (at != pairs_.cend() && *at == f) {
      it = at + 1;  // it was in the list: leaves
    } else {
      next_.push_back(f);  // enters
      it = at;
    }
  }
  next_.insert(next_.end(), it, pairs_.cend());
  std::swap(pairs_, next_);
  flips_.clear();
  return true;
}

}  // namespace hexdem::solver
