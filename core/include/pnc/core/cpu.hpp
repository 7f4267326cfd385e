#pragma once
// pnc/core/cpu.hpp: the run-time CPU queries and the function attributes of the kernels that are
// compiled more than once, for the project's baseline (x86-64: SSE2), for AVX2 and (the batched
// NDM law) for AVX-512, and choose a copy at run time (the GIMP weights, D377; the batched NDM
// law, D386, D413). No units.
//
// PNC_HAVE_AVX2_COPY is 1 where such copies can be compiled (GCC or Clang on x86), else 0;
// PNC_TARGET_AVX2 and PNC_TARGET_AVX512 are the attributes that compile a function for AVX2 and
// for AVX-512 (F, CD, VL, BW, DQ: the x86-64-v4 set without FMA) there (empty elsewhere).
// Neither enables FMA: compiled with -ffp-contract=off, every copy rounds every operation the
// same way.

#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
#define PNC_HAVE_AVX2_COPY 1
#define PNC_TARGET_AVX2 __attribute__((target("avx2")))
#define PNC_TARGET_AVX512                                                                          \
  __attribute__((target("avx2,avx512f,avx512cd,avx512vl,avx512bw,avx512dq")))
#else
#define PNC_HAVE_AVX2_COPY 0
#define PNC_TARGET_AVX2
#define PNC_TARGET_AVX512
#endif

namespace pnc {

/// Whether this CPU runs AVX2 instructions and this build has AVX2 copies
/// (PNC_HAVE_AVX2_COPY); asked once per process, then cached. Thread-safe.
bool cpu_has_avx2();

/// Whether this CPU (and its operating system, which must save the 512-bit registers) runs
/// AVX-512 F, CD, VL, BW and DQ instructions and this build has AVX-512 copies
/// (PNC_HAVE_AVX2_COPY); asked once per process, then cached. Thread-safe. Implies
/// cpu_has_avx2().
bool cpu_has_avx512();

} // namespace pnc
