// The run-time CPU queries of the AVX2 and AVX-512 kernel copies (pnc/core/cpu.hpp) against the
// configure check of the test build (tests/CMakeLists.txt, which runs __builtin_cpu_supports on
// the build machine: CI builds and runs on the same machine), under the cap of the environment
// variable PNC_SIMD (D415; tests/core/CMakeLists.txt runs these tests with it unset and set).
#include "pnc/core/cpu.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

namespace {

// The cap this process runs under, worked out here from PNC_SIMD independently of the library.
int expected_cap() {
  const char* v = std::getenv("PNC_SIMD");
  if (v == nullptr) return 2;
  if (std::strcmp(v, "baseline") == 0) return 0;
  if (std::strcmp(v, "avx2") == 0) return 1;
  return 2; // unset, empty or unknown: no cap
}

} // namespace

TEST(CoreCpu, TheLibraryAndTheConfigureCheckAgreeOnAvx2) {
  const bool configure_found = PNC_TEST_CPU_HAS_AVX2 != 0;
  EXPECT_EQ(pnc::cpu_has_avx2(), configure_found && PNC_HAVE_AVX2_COPY == 1 && expected_cap() >= 1);
  EXPECT_EQ(pnc::cpu_has_avx2(), pnc::cpu_has_avx2()); // cached, the same answer
}

TEST(CoreCpu, TheLibraryAndTheConfigureCheckAgreeOnAvx512) {
  const bool configure_found = PNC_TEST_CPU_HAS_AVX512 != 0;
  EXPECT_EQ(pnc::cpu_has_avx512(),
            configure_found && PNC_HAVE_AVX2_COPY == 1 && expected_cap() >= 2);
  EXPECT_TRUE(!pnc::cpu_has_avx512() || pnc::cpu_has_avx2()); // AVX-512 implies AVX2
}

TEST(CoreCpu, TheCapOfPncSimdIsTheOneOfTheEnvironment) {
  EXPECT_EQ(static_cast<int>(pnc::simd_cap()), expected_cap());
}

TEST(CoreCpu, PncSimdValuesAreParsedExactly) {
  using pnc::SimdLevel;
  SimdLevel l = SimdLevel::avx512;
  EXPECT_TRUE(pnc::parse_simd_level("baseline", l));
  EXPECT_EQ(l, SimdLevel::baseline);
  EXPECT_TRUE(pnc::parse_simd_level("avx2", l));
  EXPECT_EQ(l, SimdLevel::avx2);
  EXPECT_TRUE(pnc::parse_simd_level("avx512", l));
  EXPECT_EQ(l, SimdLevel::avx512);
  for (const char* bad : {"", "AVX2", "avx-512", "avx2 ", "sse2", "avx512f"}) {
    l = SimdLevel::avx2;
    EXPECT_FALSE(pnc::parse_simd_level(bad, l)) << "'" << bad << "'";
    EXPECT_EQ(l, SimdLevel::avx2) << "'" << bad << "' changed the level";
  }
  EXPECT_FALSE(pnc::parse_simd_level(nullptr, l));
}
