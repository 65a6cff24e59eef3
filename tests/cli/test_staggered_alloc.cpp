// The hexdem program's allocation functions (solver/app/huge_pages.cpp, compiled into this
// test as into the program): large blocks start at different cache-line offsets within a
// page, huge-page blocks keep their 2 MiB-aligned start, and operator delete gives every block
// back, large or small, whatever its address.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <set>
#include <vector>

namespace {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kReplaced = false;  // the sanitizer's runtime owns the allocation functions
#else
constexpr bool kReplaced = true;
#endif

bool env_off(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr && std::strcmp(v, "0") == 0;
}

std::uintptr_t in_page(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % 4096; }

TEST(StaggeredAlloc, LargeArraysStartAtDifferentLinesOfAPage) {
  if (!kReplaced || env_off("HEXDEM_STAGGER")) GTEST_SKIP() << "the program's allocation functions are not in use";
  // 32 arrays of 1.6 MB (the staggered range from 1 MiB) and 8 of 8 MB (huge pages too).
  std::vector<std::vector<double>> small(32), large(8);
  std::set<std::uintptr_t> offsets;
  for (auto& v : small) {
    v.assign(200000, 1.0);
    const std::uintptr_t o = in_page(v.data());
    EXPECT_EQ(o % 64, 0U);
    EXPECT_GE(o, 64U);
    EXPECT_LE(o, 63U * 64U);
    offsets.insert(o);
  }
  for (auto& v : large) {
    v.assign(1000000, 2.0);
    const std::uintptr_t o = in_page(v.data());
    EXPECT_EQ(o % 64, 0U);
    EXPECT_GE(o, 64U);
    offsets.insert(o);
    if (!env_off("HEXDEM_HUGE_PAGES")) {
      // The block's true start, o bytes below, lies on a 2 MiB boundary.
      EXPECT_EQ((reinterpret_cast<std::uintptr_t>(v.data()) - o) % (std::uintptr_t{2} << 20), 0U);
    }
  }
  // Consecutive blocks take consecutive offsets (1 to 63 lines, cycling): 40 blocks, 40 offsets.
  EXPECT_EQ(offsets.size(), 40U);
  // Every byte is usable, and the values stay (nothing of the block's own header overlaps it).
  for (auto& v : small) {
    v.front() = -1.0;
    v.back() = -2.0;
  }
  for (const auto& v : small) {
    EXPECT_EQ(v.front(), -1.0);
    EXPECT_EQ(v[1], 1.0);
    EXPECT_EQ(v.back(), -2.0);
  }
}

TEST(StaggeredAlloc, EveryBlockIsGivenBack) {
  if (!kReplaced) GTEST_SKIP() << "the program's allocation functions are not in use";
  // Small blocks of every size around the cache line (many start 64-aligned inside a page:
  // operator delete must tell them from the staggered ones) and large ones, written through,
  // in rounds: a block freed at a wrong address makes glibc abort, and blocks never freed
  // would leave 3.2 GB resident.
  for (int round = 0; round < 100; ++round) {
    std::vector<std::unique_ptr<char[]>> blocks;
    for (std::size_t n = 1; n <= 512; ++n) blocks.emplace_back(new char[n]);
    for (std::size_t k = 0; k < 4; ++k) {
      const std::size_t n = (std::size_t{8} << 20) + k * 4096;
      blocks.emplace_back(new char[n]);
      std::memset(blocks.back().get(), static_cast<int>(round), n);
    }
  }
  rusage usage{};
  ASSERT_EQ(getrusage(RUSAGE_SELF, &usage), 0);
  EXPECT_LT(usage.ru_maxrss, 512L * 1024) << "peak resident set [KiB]: the large blocks were not given back";
}

}  // namespace
