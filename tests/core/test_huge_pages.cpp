// Huge-page advice for large arrays (pnc/core/huge_pages.hpp, D430): the data are unchanged,
// the advice is taken where the kernel can (transparent huge pages not "never", Linux >= 6.1
// for MADV_COLLAPSE), and then the array's 2 MiB-aligned interior is backed by huge pages
// (read back from /proc/self/smaps); PNC_HUGE_PAGES=0 (ctest CoreHugePages.under_PNC_HUGE_PAGES_0)
// switches it off.
#include "pnc/core/huge_pages.hpp"

#include "common/huge_pages_probe.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

TEST(CoreHugePages, AnAdvisedArrayKeepsItsDataAndIsBackedByHugePagesWhereTheKernelCan) {
  std::vector<double> a(std::size_t{3} << 20); // 24 MiB, touched in 4 KiB pages by its fill
  for (std::size_t k = 0; k < a.size(); ++k)
    a[k] = 0.5 * static_cast<double>(k) + 1e-3;
  const bool taken = pnc::prefer_huge_pages(a);
  for (std::size_t k = 0; k < a.size(); ++k)
    ASSERT_EQ(a[k], 0.5 * static_cast<double>(k) + 1e-3) << "element " << k;
  EXPECT_EQ(pnc::huge_pages_enabled(), !pnc::test::huge_pages_switched_off());
  const auto lo = reinterpret_cast<std::uintptr_t>(a.data());
  const auto hi = lo + a.size() * sizeof(double);
  const long kb = pnc::test::huge_kb_in(lo, hi);
  if (pnc::test::huge_pages_switched_off()) {
    EXPECT_FALSE(taken);
    if (pnc::test::thp_mode() == "madvise") // (with "always" the kernel gives them unasked)
      EXPECT_EQ(kb, 0) << "switched off, yet huge pages in the array's mappings";
    return;
  }
  EXPECT_EQ(taken, pnc::test::kernel_can_collapse());
  // taken: the aligned interior (all of the 24 MiB but at most 2 MiB at each end) is huge
  if (taken) EXPECT_GE(kb, 20L * 1024) << "kB of huge pages in the array's mappings";
}

TEST(CoreHugePages, SmallRangesAreLeftAlone) {
  std::vector<double> a(4096); // 32 KiB
  EXPECT_FALSE(pnc::prefer_huge_pages(a));
  EXPECT_FALSE(pnc::prefer_huge_pages(nullptr, std::size_t{1} << 30));
}
