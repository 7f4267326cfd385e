// The run-time CPU queries of cpu.hpp (D377, D386, D413) and the PNC_SIMD cap (D415).
#include "pnc/core/cpu.hpp"

#include <cstdlib>
#include <cstring>
#include <iostream>

namespace pnc {

bool parse_simd_level(const char* text, SimdLevel& level) {
  if (text == nullptr) return false;
  if (std::strcmp(text, "baseline") == 0) {
    level = SimdLevel::baseline;
  } else if (std::strcmp(text, "avx2") == 0) {
    level = SimdLevel::avx2;
  } else if (std::strcmp(text, "avx512") == 0) {
    level = SimdLevel::avx512;
  } else {
    return false;
  }
  return true;
}

SimdLevel simd_cap() {
  static const SimdLevel cap = [] {
    SimdLevel level = SimdLevel::avx512;
    const char* v = std::getenv("PNC_SIMD");
    if (v != nullptr && *v != '\0' && !parse_simd_level(v, level))
      std::cerr << "pnc: warning: environment variable PNC_SIMD: value '" << v
                << "' is not one of 'baseline', 'avx2', 'avx512'; ignored (the widest copies "
                   "this CPU has are used)\n";
    return level;
  }();
  return cap;
}

bool cpu_has_avx2() {
#if PNC_HAVE_AVX2_COPY
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0 && simd_cap() >= SimdLevel::avx2;
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
    return cpu_has_avx2() && simd_cap() >= SimdLevel::avx512 &&
           __builtin_cpu_supports("avx512f") != 0 && __builtin_cpu_supports("avx512cd") != 0 &&
           __builtin_cpu_supports("avx512vl") != 0 && __builtin_cpu_supports("avx512bw") != 0 &&
           __builtin_cpu_supports("avx512dq") != 0;
  }();
  return has;
#else
  return false;
#endif
}

} // namespace pnc
