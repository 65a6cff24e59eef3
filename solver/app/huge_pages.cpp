// Large allocations of the hexdem program on transparent huge pages.
//
// The model's arrays (8 to 24 MB each at 1,000,000 disks) are touched for the first time
// while the lattice and the model are built, and every 4 KiB page costs a fault; the steps and
// the critical-step estimate then walk them with a TLB entry per 4 KiB. Debian's kernels leave
// transparent huge pages to `madvise` (/sys/kernel/mm/transparent_hugepage/enabled), so the
// program asks for them: an allocation of at least 4 MiB is aligned to 2 MiB and advised
// MADV_HUGEPAGE (the kernel may still give small pages; nothing depends on it). Addresses
// change, values do not: every result is the same to the bit (docs/benchmarks.md, "Huge
// pages"). HEXDEM_HUGE_PAGES=0 in the environment turns it off (for comparisons).
//
// Large blocks are also staggered: each allocation of at least 1 MiB starts a different
// number of cache lines (1 to 63) past a page boundary. Without it every large array starts
// at the same offset within a page (glibc maps such blocks on their own pages, 16 bytes past
// the boundary; the huge-page blocks sit on 2 MiB boundaries), so element i of every array
// falls into the same set of the L1 and L2 caches, and a loop that walks a dozen arrays side
// by side (the velocity update: masses, velocities, their previous values, forces, moments)
// evicts its own lines and stalls on loads that alias stores 4 KiB apart. At 1,000,000 disks
// the rotation model's step ran at 1.21e7 particle-steps/s with the arrays aligned and
// 2.13e7 staggered, the local-strain model's at 6.1e6 and 7.9e6 (docs/benchmarks.md,
// "Staggered arrays"). A staggered block keeps its true start and a check word in the 16
// bytes before the address it hands out, which operator delete reads back.
// HEXDEM_STAGGER=0 in the environment turns it off (for comparisons).
//
// Only the program replaces the global allocation functions (the libraries and the tests use
// the default ones), and not in sanitizer builds, whose runtime owns them.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>

#include <malloc.h>
#include <sys/mman.h>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define HEXDEM_HUGE_PAGES 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define HEXDEM_HUGE_PAGES 0
#endif
#endif
#ifndef HEXDEM_HUGE_PAGES
#define HEXDEM_HUGE_PAGES 1
#endif

#if HEXDEM_HUGE_PAGES
namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;   // x86-64 transparent huge page
constexpr std::size_t kThreshold = std::size_t{4} << 20;  // smaller blocks: plain malloc

bool huge_pages_wanted() noexcept {
  static const bool wanted = [] {
    const char* v = std::getenv("HEXDEM_HUGE_PAGES");
    return v == nullptr || std::strcmp(v, "0") != 0;
  }();
  return wanted;
}

/// glibc serves a block of at least M_MMAP_THRESHOLD from its own mapping, which free()
/// returns to the system at once. Left to itself it raises that threshold (up to 32 MiB) after
/// the first such block is freed, and then serves the model's arrays (1 to 24 MB each) from
/// the heap, where the blocks the set-up frees (the generator's work space, the critical
/// step's band model) stay resident below the ones it keeps: 20 to 27 bytes per disk of the
/// peak at 1,000,000 disks (docs/benchmarks.md, "Memory"). A threshold set once stays fixed.
constexpr int kMmapThreshold = 1 << 20;
const bool kFixedMmapThreshold = [] { return mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1; }();

/// Blocks from their own mapping (the fixed threshold) are the ones that start page-aligned.
constexpr auto kStaggerThreshold = static_cast<std::size_t>(kMmapThreshold);
constexpr std::size_t kPage = 4096;
constexpr std::size_t kLine = 64;
constexpr std::uint64_t kStaggerMagic = 0x6865786465d3a7c5ULL;  // check word: magic ^ start

bool stagger_wanted() noexcept {
  static const bool wanted = [] {
    const char* v = std::getenv("HEXDEM_STAGGER");
    return v == nullptr || std::strcmp(v, "0") != 0;
  }();
  return wanted;
}

std::atomic<std::size_t> stagger_count{0};

/// A block of n bytes (n >= kStaggerThreshold) that starts 1 to 63 cache lines past a page
/// boundary, the number cycling with each call; the 16 bytes before it hold the check word and
/// the true start (page-aligned, or 2 MiB-aligned for huge pages).
void* allocate_staggered(std::size_t n, bool huge) noexcept {
  const std::size_t align = huge ? kHugePage : kPage;
  if (n > SIZE_MAX - kPage) return nullptr;
  // C17 aligned_alloc takes any size; free() releases it like any malloc'd block.
  void* base = std::aligned_alloc(align, n + kPage);
  if (base == nullptr) return nullptr;
  if (huge) (void)::madvise(base, n + kPage, MADV_HUGEPAGE);  // advice only: a failure changes nothing
  const std::size_t lines = 1 + stagger_count.fetch_add(1, std::memory_order_relaxed) % 63;
  auto* user = static_cast<unsigned char*>(base) + lines * kLine;
  const auto start = reinterpret_cast<std::uintptr_t>(base);
  const std::uint64_t header[2] = {kStaggerMagic ^ static_cast<std::uint64_t>(start), static_cast<std::uint64_t>(start)};
  std::memcpy(user - sizeof header, header, sizeof header);
  return user;
}

/// The true start of a staggered block, or nullptr for any other pointer. Any pointer that
/// lies 1 to 63 whole lines past a page boundary is checked: the 16 bytes before it are
/// readable in every block (a malloc'd block's own header lies there), and only a staggered
/// block holds its page-aligned start there, 64 to 4,032 bytes below it, with the check word.
void* staggered_start(void* p) noexcept {
  const auto u = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t in_page = u % kPage;
  if (p == nullptr || in_page % kLine != 0 || in_page < kLine || in_page > 63 * kLine) return nullptr;
  std::uint64_t header[2];
  std::memcpy(header, static_cast<unsigned char*>(p) - sizeof header, sizeof header);
  const std::uint64_t start = header[1];
  if (start % kPage != 0 || start >= u || u - start != in_page || header[0] != (kStaggerMagic ^ start)) return nullptr;
  return reinterpret_cast<void*>(static_cast<std::uintptr_t>(start));
}

void* allocate(std::size_t n) noexcept {
  if (n >= kStaggerThreshold && stagger_wanted()) return allocate_staggered(n, n >= kThreshold && huge_pages_wanted());
  if (n >= kThreshold && huge_pages_wanted()) {
    // C17 aligned_alloc takes any size; free() releases it like any malloc'd block.
    void* p = std::aligned_alloc(kHugePage, n);
    if (p != nullptr) (void)::madvise(p, n, MADV_HUGEPAGE);  // advice only: a failure changes nothing
    return p;
  }
  return std::malloc(n == 0 ? 1 : n);
}

void release(void* p) noexcept {
  if (void* start = staggered_start(p)) {
    std::free(start);
  } else {
    std::free(p);
  }
}

void* allocate_or_throw(std::size_t n) {
  for (;;) {
    if (void* p = allocate(n)) return p;
    std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
  }
}

}  // namespace

void* operator new(std::size_t n) { return allocate_or_throw(n); }
void* operator new[](std::size_t n) { return allocate_or_throw(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return allocate(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return allocate(n); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
#endif
