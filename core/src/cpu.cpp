// The run-time CPU query of cpu.hpp (D377, D386).
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

} // namespace pnc
