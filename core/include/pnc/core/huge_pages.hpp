#pragma once
// pnc/core/huge_pages.hpp: large arrays backed by transparent huge pages (2 MiB on x86-64,
// decision D430). A solver whose step streams arrays larger than the caches (the GIMP
// particles beyond ~10^5) pays for a TLB walk every 4 KiB page; with huge pages, one every
// 2 MiB. Debian's kernels give huge pages only to memory that asks for them (THP "madvise"),
// so the arrays ask: MADV_HUGEPAGE for the pages they will touch, and MADV_COLLAPSE (Linux
// >= 6.1) to turn the pages already touched into huge pages now. Advice only: the data and
// every result are unchanged, and where the kernel refuses (older kernels, THP "never",
// non-Linux) nothing happens. The environment variable PNC_HUGE_PAGES=0 switches it off (for
// an A/B measurement); unset or any other value: on. No units other than bytes.
#include <cstddef>
#include <vector>

namespace pnc {

/// Whether PNC_HUGE_PAGES allows the advice (read once per process; "0" = off).
bool huge_pages_enabled();

/// Advises the kernel to back the 2 MiB-aligned pages that overlap [data, data + bytes) with
/// huge pages, and collapses those already populated (filling their unpopulated parts, so the
/// memory in use may grow by up to 2 MiB at each end of the range). Ranges under 64 KiB are
/// left alone. A caller advises only arrays that are streamed and, together, much larger than
/// the caches: elsewhere there is no page walk to save. Returns true when the advice was given and
/// accepted for the whole range (false: too small, switched off, or refused in part; never fails).
/// The rounding outwards to 2 MiB may cover a neighbour's bytes in the same mapping: their
/// contents are untouched, only how the kernel backs them.
bool prefer_huge_pages(const void* data, std::size_t bytes);

/// prefer_huge_pages over a vector's elements.
template <class T, class A> bool prefer_huge_pages(const std::vector<T, A>& v) {
  return prefer_huge_pages(v.data(), v.size() * sizeof(T));
}

} // namespace pnc
