#pragma once
// Pass 4c of the batched NDM route (ndm_batch.cpp; decisions D399, D403, D419): the
// damage-growth points of the pnc law and of the pp law (its one mode, lambda_max: always the
// capped row), in loops over the points instead of one integrate_row_major() call each (a point
// whose capped mode grows at a repeated lambda_max is handed back to the kernel, which takes
// Eigen's solver for the direction). For each point the kernel's numbers
// (integrate_impl() in ndm.cpp), expression for expression and in its order: the secant Cd =
// C0g + sum_m D_m dC1g_m, sigma = Cd eps, the consistent tangent Cd + sum_m a_m g_m over the
// modes with damage growth (a = T^T dC1_m el, g = (dD_m / alpha) (d lambda_m / d el) T), the
// stored energy and the released one, -1/2 sum_m (D1_m - D0_m) el . dC1_m el. Internal to the
// damage library: included by ndm_batch.cpp only.
#include "ndm_batch_chunk.hpp"
#include "ndm_internal.hpp"
#include "pnc/damage/ndm.hpp"

#include <algorithm>
#include <array>
#include <cstddef>

namespace pnc::damage::batch {

// Every loop over components below is unrolled (#pragma GCC unroll): GCC vectorises only the
// innermost loop, so the loop over the points must be the only loop left in its body.

// d lambda_m / d el of a mode (stretch_row()): where the cap binds (clip), the capped row
// (detail::capped_stretch_row()); else the unit row of the mode, plus with shear t > 0 the
// shear entries f e_I, f = (d lambda / d t) 0.5 / (2 t): entries 5 and 4 of mode 1, 3 and 5 of
// mode 2, 4 and 3 of mode 3 (stretch_row()'s pair_index). (A block-diagonal strain has t = 0
// and no cap in mode 3.)
template <int M>
[[gnu::always_inline]] inline void growth_row(double t, double grow, bool clip,
                                              const double (&capped)[6], const double (&l)[6],
                                              double (&row)[6]) {
#pragma GCC unroll 6
  for (double& x : row)
    x = 0.0;
  row[M] = 1.0;
  const double f = grow * 0.5 / (2 * t);
  const bool sheared = t > 0;
  constexpr int ia = M == 0 ? 5 : (M == 1 ? 3 : 4), ib = M == 0 ? 4 : (M == 1 ? 5 : 3);
  row[ia] = sheared ? f * l[ia] : 0.0;
  row[ib] = sheared ? f * l[ib] : 0.0;
#pragma GCC unroll 6
  for (int k = 0; k < 6; ++k)
    row[k] = clip ? capped[k] : row[k];
}

// T^T v with the columns of T in tc (tc[r][k] = T(k, r)): detail::transpose_times().
[[gnu::always_inline]] inline void transpose_times(const double (&tc)[6][6], const double (&v)[6],
                                                   double (&o)[6]) {
#pragma GCC unroll 6
  for (int r = 0; r < 6; ++r)
    o[r] = detail::row_full(tc[r], v[0], v[1], v[2], v[3], v[4], v[5]);
}

// The growth terms a_m (A) and g_m (G) of mode M for point j, and its part of the released
// energy; act: the mode grows (dD != 0 while loading).
// PP: the pp law (mode 0 only, dC1 e by pp_c1_times; D419).
template <int M, bool Rotated, bool Consistent, bool PP>
[[gnu::always_inline]] inline void
growth_mode(const std::array<double, kMaxConstants>& k, const double (&tc)[6][6], double alpha,
            double ndb, const double (&l)[6], double k0, double D1, double dg, double t,
            double grow, bool clip, const double (&capped)[6], double& released, double (&a)[6],
            double (&g)[6]) {
  double v[6];
  if constexpr (PP)
    detail::pp_c1_times(k, l, v);
  else
    detail::pnc_c1_times(k, M, l, v);
  // the released energy of the mode (the kernel's mode_damage() of the start kappa)
  double D0, dD0;
  detail::damage_and_slope(k0 / alpha, D0, dD0);
  D0 = k0 < ndb ? 0.0 : D0;
  const double r = released - 0.5 * (D1 - D0) * dot6(l, v);
  released = D1 != D0 ? r : released;
  if constexpr (Consistent) {
    double row[6];
    growth_row<M>(t, grow, clip, capped, l, row);
    const double f = dg / alpha;
    if constexpr (Rotated) {
      double rt[6];
      transpose_times(tc, v, a);
      transpose_times(tc, row, rt);
#pragma GCC unroll 6
      for (int c = 0; c < 6; ++c)
        g[c] = f * rt[c];
    } else {
#pragma GCC unroll 6
      for (int c = 0; c < 6; ++c) {
        a[c] = v[c];
        g[c] = f * row[c];
      }
    }
  }
}

// Voigt entries 23 and 13 (indices 3, 4): the shears out of the x1-x2 plane.
constexpr bool out_of_plane(int k) {
  return k == 3 || k == 4;
}

// Which tangent the growth pass forms into c.Kg: none (none or elastic requested: the caller
// writes C0g), the secant Cd, or the consistent tangent.
enum class GrowthK { none, secant, consistent };

// The damage-growth points idx[0..u) of the chunk (D399, D403). Block: every one of them has a
// block-diagonal platelet-frame strain, so mode 3 has no shear and no cap, and without rotation
// the tangent entries of the out-of-plane shears are skipped (below). N: the law's modes, 3
// (pnc) or 1 (pp, D419: its mode is lambda_max, the capped row, whatever c.clip holds).
template <int N, bool Rotated, bool Block, GrowthK Kind>
[[gnu::always_inline]] inline void growth_points(const PreparedNdm& q, const std::size_t* idx,
                                                 std::size_t u, Chunk& c) {
  static_assert(N == 1 || N == 3, "the pp (1) or the pnc law (3)");
  constexpr bool PP = N == 1;
  constexpr bool Consistent = Kind == GrowthK::consistent;
  constexpr bool Skip = Block && !Rotated;
  const double alpha = q.p.alpha();
  const double ndb = detail::onset_margin(alpha);
  double tc[6][6];
#pragma GCC unroll 6
  for (int r = 0; r < 6; ++r)
#pragma GCC unroll 6
    for (int k = 0; k < 6; ++k)
      tc[r][k] = Rotated ? q.T(k, r) : 0.0;
  double e[6][kChunk], D[3][kChunk], s[6][kChunk], bad[kChunk], rel[kChunk];
  double A[3][6][kChunk], G[3][6][kChunk], act[3][kChunk], ok[kChunk];
  // the points' inputs gathered into compact arrays, so that the loops below run without
  // indirection (the vectoriser has no gather for them)
  double l[6][kChunk], k0[3][kChunk], dg[3][kChunk], t[3][kChunk], lmax[kChunk], grow[3][kChunk],
      clip[3][kChunk];
  const std::size_t u4 = padded(u); // (lanes u..u4 repeat the last point; nothing of them is kept)
  for (std::size_t j = 0; j < u4; ++j) {
    const std::size_t i = idx[std::min(j, u - 1)];
#pragma GCC unroll 6
    for (int k = 0; k < 6; ++k) {
      l[k][j] = c.el[k][i];
      e[k][j] = c.eps[k][i];
    }
#pragma GCC unroll 6
    for (int m = 0; m < 3; ++m) { // pp: modes 1 and 2 absent (no damage, no growth)
      D[m][j] = m < N ? c.D[m][i] : 0.0;
      dg[m][j] = m < N ? c.dg[m][i] : 0.0;
      k0[m][j] = m < N ? c.s0[m][i] : 0.0;
    }
    lmax[j] = c.lmax[i];
#pragma GCC unroll 6
    for (int m = 0; m < 3; ++m) { // pp: lambda_max, the capped row (compute_stretch())
      t[m][j] = PP ? 0.0 : c.tsh[m][i];
      grow[m][j] = PP ? 1.0 : c.grow[m][i];
      clip[m][j] = PP ? (m == 0 ? 1.0 : 0.0) : c.clip[m][i];
    }
  }
  // per point: the modes' growth terms and the released energy
  for (std::size_t j = 0; j < u4; ++j) {
    double lj[6], a[3][6], g[3][6];
#pragma GCC unroll 6
    for (int k = 0; k < 6; ++k)
      lj[k] = l[k][j];
#pragma GCC unroll 6
    for (int m = 0; m < N; ++m)
      act[m][j] = dg[m][j] != 0.0 ? 1.0 : 0.0;
    double released = 0.0;
    const bool clip0 = clip[0][j] != 0.0, clip1 = clip[1][j] != 0.0,
               clip2 = !Block && clip[2][j] != 0.0;
    double capped[6] = {0, 0, 0, 0, 0, 0};
    // lambda_max's direction must be unique where a capped mode grows (1: the pass may take the
    // point); doubles, not bools: the vectoriser selects between doubles
    double direction = 1.0;
    if constexpr (Consistent) {
      const double unique = detail::capped_stretch_row(lj, lmax[j], capped) ? 1.0 : 0.0;
      const bool capped_growth =
          (clip0 & (dg[0][j] != 0.0)) | (clip1 & (dg[1][j] != 0.0)) | (clip2 & (dg[2][j] != 0.0));
      direction = capped_growth ? unique : 1.0;
    }
    growth_mode<0, Rotated, Consistent, PP>(q.p.k, tc, alpha, ndb, lj, k0[0][j], D[0][j], dg[0][j],
                                            t[0][j], grow[0][j], clip0, capped, released, a[0],
                                            g[0]);
    if constexpr (!PP) {
      growth_mode<1, Rotated, Consistent, false>(q.p.k, tc, alpha, ndb, lj, k0[1][j], D[1][j],
                                                 dg[1][j], t[1][j], grow[1][j], clip1, capped,
                                                 released, a[1], g[1]);
      growth_mode<2, Rotated, Consistent, false>(
          q.p.k, tc, alpha, ndb, lj, k0[2][j], D[2][j], dg[2][j], Block ? 0.0 : t[2][j],
          Block ? 1.0 : grow[2][j], clip2, capped, released, a[2], g[2]);
    }
    rel[j] = released;
    bad[j] = 0.0;
    ok[j] = direction;
    if constexpr (Consistent)
#pragma GCC unroll 6
      for (int m = 0; m < N; ++m)
#pragma GCC unroll 6
        for (int k = 0; k < 6; ++k)
          if (!Skip || !out_of_plane(k)) { // (the others are +-0: see below)
            A[m][k][j] = a[m][k];
            G[m][k][j] = g[m][k];
          }
  }
  // the secant Cd entry by entry (as unloading_stress()), the stress, the tangent
#pragma GCC unroll 6
  for (int r = 0; r < 6; ++r) { // (unrolled too: its constants then stay in registers)
    double a0[6], d[3][6];
#pragma GCC unroll 6
    for (int col = 0; col < 6; ++col) {
      a0[col] = q.C0g(r, col);
#pragma GCC unroll 6
      for (int m = 0; m < N; ++m)
        d[m][col] = q.dC1g[static_cast<std::size_t>(m)](r, col);
    }
    double(*__restrict kg)[kChunk] = c.Kg + 6 * r; // entries (r, 0..5)
    for (std::size_t j = 0; j < u4; ++j) {
      double row[6];
      // (unrolled, so that the loop over the points is the one loop the vectoriser sees)
#pragma GCC unroll 6
      for (int col = 0; col < 6; ++col) {
        double x = a0[col];
#pragma GCC unroll 3
        for (int m = 0; m < N; ++m) {
          const double y = x + D[m][j] * d[m][col];
          x = D[m][j] != 0.0 ? y : x;
        }
        row[col] = x;
        // K += a_m g_m in the modes' order. Without rotation the entries 3 and 4 (Voigt 23, 13)
        // of a_m and g_m are +-0 for a block-diagonal strain (dC1_m el, the uncapped and the
        // capped stretch rows), and the entries of Cd in their rows and columns are +0 or not
        // zero (C0g and dC1g_m have +0 there but on the diagonal, whose C44, C55 are > 0), so
        // adding the +-0 products would change no bit: those 20 of 36 are skipped (D399).
        if constexpr (Consistent)
          if (!Skip || !(out_of_plane(r) || out_of_plane(col)))
#pragma GCC unroll 3
            for (int m = 0; m < N; ++m) {
              const double y = x + A[m][r][j] * G[m][col][j];
              x = act[m][j] != 0.0 ? y : x;
            }
        if constexpr (Kind != GrowthK::none) {
          kg[col][j] = x;
          bad[j] += nf(x);
        }
      }
      s[r][j] = detail::times_row(row, e[0][j], e[1][j], e[2][j], e[3][j], e[4][j], e[5][j]);
    }
  }
  for (std::size_t j = 0; j < u; ++j) {
    const std::size_t i = idx[j];
#pragma GCC unroll 6
    for (int k = 0; k < 6; ++k)
      c.sig[k][i] = s[k][j];
    c.bad[i] += ok[j] != 0.0 ? bad[j] : 0.0;
    c.stored[i] = half_dot(c.sig, c.eps, i);
    c.diss[i] = rel[j];
    c.vec_growth[i] = ok[j]; // 0: the kernel takes the point (ndm_batch.cpp)
  }
}

} // namespace pnc::damage::batch
