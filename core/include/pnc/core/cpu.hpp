#pragma once
// pnc/core/cpu.hpp: the run-time CPU queries and the function attributes of the kernels that are
// compiled more than once, for the project's baseline (x86-64: SSE2), for AVX2 and for AVX-512,
// and choose a copy at run time (the GIMP weights, D377, D414; the batched NDM law, D386, D413),
// and the cap of the environment variable PNC_SIMD on that choice (D415). No units.
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

/// The instruction sets of the vector copies, narrowest first.
enum class SimdLevel { baseline = 0, avx2 = 1, avx512 = 2 };

/// Reads a value of the environment variable PNC_SIMD: "baseline", "avx2" or "avx512" (exact,
/// lower case). Returns false for anything else (level unchanged).
bool parse_simd_level(const char* text, SimdLevel& level);

/// The widest copy this process may run (D415): PNC_SIMD read once (unset or empty: avx512,
/// no cap). An unknown value is reported once on stderr, naming the variable, the value and
/// the accepted ones, and caps nothing. The cap lets a user keep the AVX2 copies on a CPU whose
/// clock drops under 512-bit code, and the tests run the narrower copies on a wide CPU.
SimdLevel simd_cap();

/// Whether this CPU runs AVX2 instructions, this build has AVX2 copies (PNC_HAVE_AVX2_COPY)
/// and simd_cap() allows them; asked once per process, then cached. Thread-safe.
bool cpu_has_avx2();

/// Whether this CPU (and its operating system, which must save the 512-bit registers) runs
/// AVX-512 F, CD, VL, BW and DQ instructions, this build has AVX-512 copies
/// (PNC_HAVE_AVX2_COPY) and simd_cap() allows them; asked once per process, then cached.
/// Thread-safe. Implies cpu_has_avx2().
bool cpu_has_avx512();

} // namespace pnc
