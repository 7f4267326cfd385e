// Transparent huge pages for large arrays (huge_pages.hpp, D430).
#include "pnc/core/huge_pages.hpp"

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#if defined(__linux__)
#include <sys/mman.h>
#ifndef MADV_COLLAPSE
#define MADV_COLLAPSE 25 // Linux >= 6.1 (asm-generic/mman-common.h); older kernels: EINVAL
#endif
#endif

namespace pnc {

bool huge_pages_enabled() {
  static const bool on = [] {
    const char* v = std::getenv("PNC_HUGE_PAGES");
    return !(v && std::strcmp(v, "0") == 0);
  }();
  return on;
}

bool prefer_huge_pages(const void* data, std::size_t bytes) {
#if defined(__linux__)
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21; // 2 MiB, x86-64's PMD page
  if (!data || bytes < kHuge / 32 || !huge_pages_enabled()) return false;
  const auto begin = reinterpret_cast<std::uintptr_t>(data), end = begin + bytes;
  // outwards to 2 MiB first (a neighbour's bytes in the same mapping are only backed
  // differently); where that reaches unmapped addresses (ENOMEM), the aligned interior only
  const auto advise = [](std::uintptr_t lo, std::uintptr_t hi) {
    if (hi <= lo) return false;
    void* p = reinterpret_cast<void*>(lo);
    if (::madvise(p, hi - lo, MADV_HUGEPAGE) != 0) return false;
    return ::madvise(p, hi - lo, MADV_COLLAPSE) == 0;
  };
  if (advise(begin & ~(kHuge - 1), (end + kHuge - 1) & ~(kHuge - 1))) return true;
  if (errno != ENOMEM) return false;
  return advise((begin + kHuge - 1) & ~(kHuge - 1), end & ~(kHuge - 1));
#else
  (void)data;
  (void)bytes;
  return false;
#endif
}

} // namespace pnc
