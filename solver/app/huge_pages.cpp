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
// Only the program replaces the global allocation functions (the libraries and the tests use
// the default ones), and not in sanitizer builds, whose runtime owns them.
#include <cstddef>
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
const bool kFixedMmapThreshold = [] { return mallopt(M_MMAP_THRESHOLD, 1 << 20) == 1; }();

void* allocate(std::size_t n) noexcept {
  if (n >= kThreshold && huge_pages_wanted()) {
    // C17 aligned_alloc takes any size; free() releases it like any malloc'd block.
    void* p = std::aligned_alloc(kHugePage, n);
    if (p != nullptr) (void)::madvise(p, n, MADV_HUGEPAGE);  // advice only: a failure changes nothing
    return p;
  }
  return std::malloc(n == 0 ? 1 : n);
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
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
#endif
