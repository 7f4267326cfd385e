// The run-time CPU queries of cpu.hpp (D377, D386, D413).
#include "pnc/core/cpu.hpp"

namespace pnc {

bool cpu_has_avx2() {
#if PNC_HAVE_AVX2_COPY
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return has;
#else
  return false;
#endif
}

bool cpu_has_avx512() {
#if PNC_HAVE_AVX2_COPY
  // libgcc's answer for an AVX-512 feature includes the operating system's support of the
  // 512-bit and mask registers (XGETBV), so a kernel that does not save them reads false.
  static const bool has = [] {
    __builtin_cpu_init();
    return cpu_has_avx2() && __builtin_cpu_supports("avx512f") != 0 &&
           __builtin_cpu_supports("avx512cd") != 0 && __builtin_cpu_supports("avx512vl") != 0 &&
           __builtin_cpu_supports("avx512bw") != 0 && __builtin_cpu_supports("avx512dq") != 0;
  }();
  return has;
#else
  return false;
#endif
}

} // namespace pnc
