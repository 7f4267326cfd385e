#pragma once
// pnc/core/cpu.hpp: the one run-time CPU query and the one function attribute of the kernels
// that are compiled twice, for the project's baseline (x86-64: SSE2) and for AVX2, and choose a
// copy at run time (the GIMP weights, D377; the batched NDM law, D386). No units.
//
// PNC_HAVE_AVX2_COPY is 1 where such a copy can be compiled (GCC or Clang on x86), else 0;
// PNC_TARGET_AVX2 is the attribute that compiles a function for AVX2 there (empty elsewhere).
// "avx2" does not enable FMA: compiled with -ffp-contract=off, both copies round every
// operation the same way.

#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
#define PNC_HAVE_AVX2_COPY 1
#define PNC_TARGET_AVX2 __attribute__((target("avx2")))
#else
#define PNC_HAVE_AVX2_COPY 0
#define PNC_TARGET_AVX2
#endif

namespace pnc {

/// Whether this CPU runs AVX2 instructions and this build has AVX2 copies
/// (PNC_HAVE_AVX2_COPY); asked once per process, then cached. Thread-safe.
bool cpu_has_avx2();

} // namespace pnc
