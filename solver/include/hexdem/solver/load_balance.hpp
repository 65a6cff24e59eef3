#pragma once
/// \file load_balance.hpp
/// A parallel loop's index range split over the OpenMP threads in contiguous parts, as
/// `schedule(static)` splits it, but with parts sized by the threads' speed in the loop's
/// previous calls.
///
/// Why: on a machine whose cores differ in speed from time to time (virtual CPUs that share
/// their host with other guests, or big and little cores), equal parts make the faster thread
/// wait at the loop's end. A two-thread profile of the warhead case (8,053 disks) had the
/// second thread waiting at the barriers for 45 % of its samples while the first was 1.5 to
/// 1.8 times slower on the same kernels. Dynamic scheduling balances, but it gives each
/// thread other data every step and ran 30-50 % slower (docs/benchmarks.md); here each thread
/// keeps a contiguous part, which moves by a few items per call.
///
/// Every kernel run through it computes each index on its own (a disk's or a bond's values,
/// in a fixed order within the index), so the results do not depend on the parts: the same
/// bits for any thread count and any split. Nothing is allocated per call once the thread
/// count is known.

#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace hexdem::solver {

class LoadBalance {
 public:
  /// Calls body(lo, hi) on every thread of a parallel region, on contiguous parts that cover
  /// [0, n) in thread order, and moves the parts toward equal times for the next call.
  template <class Body>
  void run(std::size_t n, Body&& body) {
    const int threads = omp_get_max_threads();
    if (threads <= 1 || n < 2 * static_cast<std::size_t>(threads)) {
      body(std::size_t{0}, n);
      return;
    }
    const auto t_count = static_cast<std::size_t>(threads);
    if (share_.size() != t_count) {
      share_.assign(t_count, 1.0 / static_cast<double>(threads));
      seconds_.assign(t_count, 0.0);
      bound_.assign(t_count + 1, 0);
    }
    double sum = 0.0;
    bound_[0] = 0;
    for (std::size_t t = 0; t < t_count; ++t) {
      sum += share_[t];
      bound_[t + 1] = t + 1 == t_count ? n : std::min(n, static_cast<std::size_t>(sum * static_cast<double>(n) + 0.5));
    }
    bool full_team = true;
#pragma omp parallel num_threads(threads)
    {
      const int team = omp_get_num_threads();
      const auto t = static_cast<std::size_t>(omp_get_thread_num());
      if (team == threads) {
        const double start = omp_get_wtime();
        body(bound_[t], bound_[t + 1]);
        seconds_[t] = omp_get_wtime() - start;
      } else {
        // A smaller team than asked for (nested or limited): equal parts, nothing learned.
        const std::size_t lo = n * t / static_cast<std::size_t>(team), hi = n * (t + 1) / static_cast<std::size_t>(team);
        body(lo, hi);
#pragma omp single nowait
        full_team = false;
      }
    }
    if (full_team) rebalance();
  }

 private:
  /// Each thread's speed in the last call (items per second), and the parts that would have
  /// taken equal times at those speeds; half way there, to damp a single slow call. Each part
  /// keeps at least a tenth of an equal share.
  void rebalance() {
    const std::size_t t_count = share_.size();
    double total_speed = 0.0;
    for (std::size_t t = 0; t < t_count; ++t) total_speed += share_[t] / std::max(seconds_[t], 1e-9);
    if (!(total_speed > 0)) return;
    const double floor = 0.1 / static_cast<double>(t_count);
    double sum = 0.0;
    for (std::size_t t = 0; t < t_count; ++t) {
      const double target = share_[t] / std::max(seconds_[t], 1e-9) / total_speed;
      share_[t] = std::max(floor, 0.5 * (share_[t] + target));
      sum += share_[t];
    }
    for (double& s : share_) s /= sum;
  }

  std::vector<double> share_;        ///< each thread's fraction of the range [-], summing to 1
  std::vector<double> seconds_;      ///< each thread's time in the last call [s]
  std::vector<std::size_t> bound_;   ///< the parts' bounds, threads + 1
};

}  // namespace hexdem::solver
