// LoadBalance: the threads' contiguous parts of a parallel loop cover its range exactly
// once, in thread order, and move toward the faster thread when one thread is slower.

#include <gtest/gtest.h>

#include <omp.h>

#include <chrono>
#include <cstddef>
#include <thread>
#include <vector>

#include "hexdem/solver/load_balance.hpp"

namespace {

using hexdem::solver::LoadBalance;

/// Sets the OpenMP thread count for a scope.
class Threads {
 public:
  explicit Threads(int n) : before_(omp_get_max_threads()) { omp_set_num_threads(n); }
  ~Threads() { omp_set_num_threads(before_); }
  Threads(const Threads&) = delete;
  Threads& operator=(const Threads&) = delete;

 private:
  int before_;
};

/// One call: each index's visits, and each thread's part [lo, hi).
struct Call {
  std::vector<int> visits;
  std::vector<std::size_t> lo, hi;
};

/// Runs one call of `lb` over n items; thread 1 sleeps `slow_us` microseconds per item.
Call run(LoadBalance& lb, std::size_t n, int threads, double slow_us) {
  Call c;
  c.visits.assign(n, 0);
  c.lo.assign(static_cast<std::size_t>(threads), 0);
  c.hi.assign(static_cast<std::size_t>(threads), 0);
  lb.run(n, [&](std::size_t lo, std::size_t hi) {
    const auto t = static_cast<std::size_t>(omp_get_thread_num());
    c.lo[t] = lo;
    c.hi[t] = hi;
    for (std::size_t i = lo; i < hi; ++i) ++c.visits[i];  // parts are disjoint: no race
    if (t == 1 && slow_us > 0)
      std::this_thread::sleep_for(std::chrono::duration<double, std::micro>(slow_us * static_cast<double>(hi - lo)));
  });
  return c;
}

TEST(LoadBalance, PartsCoverTheRangeOnceInThreadOrder) {
  for (const int threads : {1, 2, 3}) {
    const Threads scope(threads);
    for (const std::size_t n : {0u, 1u, 5u, 1000u, 12345u}) {
      LoadBalance lb;
      for (int call = 0; call < 4; ++call) {
        const Call c = run(lb, n, threads, threads > 1 ? 1.0 : 0.0);
        for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(c.visits[i], 1) << "index " << i << ", n " << n << ", threads " << threads;
        if (threads > 1 && n >= 2 * static_cast<std::size_t>(threads)) {
          EXPECT_EQ(c.lo[0], 0u);
          EXPECT_EQ(c.hi.back(), n);
          for (std::size_t t = 1; t < c.lo.size(); ++t) EXPECT_EQ(c.lo[t], c.hi[t - 1]) << "thread " << t;
        }
      }
    }
  }
}

TEST(LoadBalance, TheSlowThreadGetsASmallerPart) {
  // Thread 1 takes 20 us per item more: after a few calls its part is well under half, but
  // never below a tenth of an equal share.
  const Threads scope(2);
  if (omp_get_max_threads() < 2) GTEST_SKIP() << "no second thread";
  LoadBalance lb;
  const std::size_t n = 400;
  Call c = run(lb, n, 2, 0.0);
  for (int call = 0; call < 8; ++call) c = run(lb, n, 2, 20.0);
  const std::size_t slow_part = c.hi[1] - c.lo[1];
  EXPECT_LT(slow_part, n / 4) << "thread 1's part " << slow_part << " of " << n;
  EXPECT_GE(slow_part, n / 25) << "each part keeps about a tenth of an equal share";
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(c.visits[i], 1);
}

}  // namespace
