#pragma once
// pnc/gimp_coupler/weights_simd.hpp: the uGIMP 1-D weights of many points in one branch-free
// loop (D376), built three times: for the project's baseline (x86-64, SSE2), for AVX2 and for
// AVX-512, the widest the CPU has chosen at run time (D377, D414). Each point goes through the same
// pieces and the same floating-point operations as ugimp_weight (weights.hpp), so every build
// returns its values bit for bit (src/weights_simd.cpp is compiled with -ffp-contract=off: no FMA
// contraction). Units: xi and l in m, L in m; S dimensionless, dS in 1/m.
#include <cstddef>

namespace pnc::gimp {

/// S[k], dS[k] = ugimp_weight(xi[k], L, l[k]) for k < n (bit for bit; D376). Arrays must not
/// overlap. Runs the AVX-512 build when the CPU has it, else the AVX2 build when the CPU has
/// AVX2, else the baseline build (D377, D414).
void ugimp_weights(std::size_t n, const double* xi, const double* l, double L, double* S,
                   double* dS);

namespace simd {
/// The baseline (SSE2) build of ugimp_weights.
void ugimp_weights_default(std::size_t n, const double* xi, const double* l, double L, double* S,
                           double* dS);
/// The AVX2 build of ugimp_weights; call only when pnc::cpu_has_avx2() (pnc/core/cpu.hpp).
void ugimp_weights_avx2(std::size_t n, const double* xi, const double* l, double L, double* S,
                        double* dS);
/// The AVX-512 build of ugimp_weights; call only when pnc::cpu_has_avx512() (pnc/core/cpu.hpp).
void ugimp_weights_avx512(std::size_t n, const double* xi, const double* l, double L, double* S,
                          double* dS);
} // namespace simd

} // namespace pnc::gimp
