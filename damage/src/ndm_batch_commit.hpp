#pragma once
// Pass 5 of the batched NDM route (ndm_batch.cpp): the result check of a chunk and its writes
// to the caller's arrays (decisions D261, D401). Internal to the damage library: included by
// ndm_batch.cpp only (its passes are inlined into one function per instruction set, D386).
#include "ndm_batch_chunk.hpp"
#include "pnc/damage/ndm.hpp"

#include <cstddef>

namespace pnc::damage::batch {

// Pass 5a: the result check of every point (stress, end state, energies; the tangent was
// checked where it was formed).
[[gnu::always_inline]] inline void check_results(std::size_t m, int n, Chunk& c) {
  for (std::size_t i = 0; i < m; ++i) {
    double x = c.bad[i] + nf(c.stored[i]) + nf(c.diss[i]);
    for (int k = 0; k < 6; ++k)
      x += nf(c.sig[k][i]);
    for (int k = 0; k < n; ++k)
      x += nf(c.kap[k][i]) + nf(c.D[k][i]);
    c.bad[i] = x;
  }
}

// dst[i] = src[i], i < M (M = kChunk: a full chunk, whose constant trip count lets the compiler
// unroll the copy; M = 0: m points).
template <std::size_t M>
[[gnu::always_inline]] inline void copy_points(std::size_t m, double* __restrict dst,
                                               const double* __restrict src) {
  const std::size_t mm = M ? M : m;
  for (std::size_t i = 0; i < mm; ++i)
    dst[i] = src[i];
}

// dst[i] = src[i] for the points of the chunk that did not fail.
template <std::size_t M>
[[gnu::always_inline]] inline void put_ok(bool all_ok, std::size_t m, const Chunk& c,
                                          double* __restrict dst, const double* __restrict src) {
  if (all_ok) {
    copy_points<M>(m, dst, src);
    return;
  }
  for (std::size_t i = 0; i < m; ++i)
    if (c.bad[i] == 0.0) dst[i] = src[i];
}

// The 36 tangent entries of one point from a compact block (entry rc of the point at
// src[rc][j]) to the caller's array at dst (entry 0 of the point), stride ld.
[[gnu::always_inline]] inline void put_tangent(const double (*src)[kChunk], std::size_t j,
                                               double* dst, std::size_t ld) {
#pragma GCC unroll 36
  for (int rc = 0; rc < 36; ++rc, dst += ld)
    *dst = src[rc][j];
}

// Pass 5b: writes to the caller's arrays, for the points that did not fail (M as for
// copy_points). `all_ok`: no point of the chunk failed, so the loops need no per-point test.
template <std::size_t M>
[[gnu::always_inline]] inline void
commit_impl(const PreparedNdm& q, const NdmBatch& b, std::size_t base, std::size_t m, int n,
            bool all_ok, const Chunk& c, const double (*Kk)[36], const std::size_t* kidx,
            std::size_t nk, const std::size_t* uidx, std::size_t nu, const std::size_t* gidx,
            std::size_t ng) {
  const std::size_t ld = b.ld;
  for (int k = 0; k < 6; ++k)
    put_ok<M>(all_ok, m, c, b.sigma + static_cast<std::size_t>(k) * ld + base, c.sig[k]);
  for (int k = 0; k < n; ++k) {
    put_ok<M>(all_ok, m, c, b.state1 + static_cast<std::size_t>(k) * ld + base, c.kap[k]);
    put_ok<M>(all_ok, m, c, b.state1 + static_cast<std::size_t>(n + k) * ld + base, c.D[k]);
  }
  if (b.stored) put_ok<M>(all_ok, m, c, b.stored + base, c.stored);
  if (b.dissipated) put_ok<M>(all_ok, m, c, b.dissipated + base, c.diss);
  if (b.status)
    for (std::size_t i = 0; i < m; ++i)
      b.status[base + i] = c.bad[i] == 0.0 ? 0 : 1;
  if (b.kind == TangentKind::none || !b.K) return;
  double* const K = b.K + base;
  // Every point first gets C0g (the elastic path, and every point for the elastic request);
  // then the unloading points their secant and the kernel points their own tangent.
  for (int r = 0; r < 6; ++r)
    for (int col = 0; col < 6; ++col) {
      const double v = q.C0g(r, col);
      double* __restrict dst = K + static_cast<std::size_t>(6 * r + col) * ld;
      if (all_ok) {
        const std::size_t mm = M ? M : m;
        for (std::size_t i = 0; i < mm; ++i)
          dst[i] = v;
      } else {
        for (std::size_t i = 0; i < m; ++i)
          if (c.bad[i] == 0.0) dst[i] = v;
      }
    }
  if (b.kind == TangentKind::elastic) return;
  for (std::size_t j = 0; j < nu; ++j) // the secant formed for the stress (unloading_stress)
    if (c.bad[uidx[j]] == 0.0) put_tangent(c.Ku, j, K + uidx[j], ld);
  for (std::size_t j = 0; j < ng; ++j) { // the consistent tangent of the growth pass (D399)
    const std::size_t i = gidx[j];
    if (c.bad[i] == 0.0 && c.vec_growth[i] != 0.0) put_tangent(c.Kg, j, K + i, ld);
  }
  for (std::size_t j = 0; j < nk; ++j) {
    const std::size_t i = kidx[j];
    if (c.bad[i] != 0.0) continue;
    double* dst = K + i;
#pragma GCC unroll 36
    for (int rc = 0; rc < 36; ++rc, dst += ld)
      *dst = Kk[j][rc];
  }
}

// Pass 5b for a full chunk or the last one; returns whether every point of the chunk is ok.
[[gnu::always_inline]] inline bool commit(const PreparedNdm& q, const NdmBatch& b, std::size_t base,
                                          std::size_t m, int n, const Chunk& c,
                                          const double (*Kk)[36], const std::size_t* kidx,
                                          std::size_t nk, const std::size_t* uidx, std::size_t nu,
                                          const std::size_t* gidx, std::size_t ng) {
  double nbad = 0.0; // (a sum: the loop vectorises)
  for (std::size_t i = 0; i < m; ++i)
    nbad += c.bad[i] == 0.0 ? 0.0 : 1.0;
  const bool all_ok = nbad == 0.0;
  if (m == kChunk)
    commit_impl<kChunk>(q, b, base, m, n, all_ok, c, Kk, kidx, nk, uidx, nu, gidx, ng);
  else
    commit_impl<0>(q, b, base, m, n, all_ok, c, Kk, kidx, nk, uidx, nu, gidx, ng);
  return all_ok;
}

} // namespace pnc::damage::batch
