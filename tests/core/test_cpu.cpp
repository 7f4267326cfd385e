// The run-time CPU queries of the AVX2 and AVX-512 kernel copies (pnc/core/cpu.hpp) against the
// configure check of the test build (tests/CMakeLists.txt, which runs __builtin_cpu_supports on the
// build machine: CI builds and runs on the same machine).
#include "pnc/core/cpu.hpp"

#include <gtest/gtest.h>

TEST(CoreCpu, TheLibraryAndTheConfigureCheckAgreeOnAvx2) {
  const bool configure_found = PNC_TEST_CPU_HAS_AVX2 != 0;
  EXPECT_EQ(pnc::cpu_has_avx2(), configure_found && PNC_HAVE_AVX2_COPY == 1);
  EXPECT_EQ(pnc::cpu_has_avx2(), pnc::cpu_has_avx2()); // cached, the same answer
}

TEST(CoreCpu, TheLibraryAndTheConfigureCheckAgreeOnAvx512) {
  const bool configure_found = PNC_TEST_CPU_HAS_AVX512 != 0;
  EXPECT_EQ(pnc::cpu_has_avx512(), configure_found && PNC_HAVE_AVX2_COPY == 1);
  EXPECT_TRUE(!pnc::cpu_has_avx512() || pnc::cpu_has_avx2()); // AVX-512 implies AVX2
}
