// The batched route of the NDM kernel (pnc/damage/ndm.hpp integrate_batch, decisions D260,
// D261). Points are taken in chunks of kChunk; within a chunk every pass is a loop over the
// points with the components in separate arrays (structure of arrays), written without
// branches on per-point data so that the compiler vectorises it:
//  1. eps = eps0 + deps, the platelet-frame strain el = T eps, the finiteness of the inputs;
//  2. the mode stretches of D7 (block-diagonal pnc strains in closed form, general strains and
//     pp with lambda_max in two vectorised halves around its cosine, D402);
//  3. kappa1, D1 and the path of each point: elastic (every mode below the onset), unloading
//     (no mode with damage growth) or kernel (damage growth);
//  4. sigma = C0g eps for the chunk (run with pass 1's rotation, in the chunk's one form of the
//     products with the strain, D401), sigma = (C0g + sum_m D_m dC1g_m) eps for the unloading
//     points gathered into a compact block, the damage growth (pnc and pp points) in loops over
//     a compact block as well (ndm_batch_growth.hpp, D399, D403, D419), integrate_row_major()
//     for the kernel points it hands back (a capped mode growing at a repeated lambda_max);
//  5. the result check and the writes to the caller's arrays.
// How the passes move their numbers (full chunks, one product form per chunk, padded compact
// blocks) is D401.
// Every expression is the one integrate_impl() (ndm.cpp) evaluates, in the same order, so the
// numbers are the same bit for bit (the test FeMaterialBatch.* checks it); the shared pieces
// come from ndm_internal.hpp.
#include "ndm_batch_chunk.hpp"
#include "ndm_batch_commit.hpp"
#include "ndm_batch_growth.hpp"
#include "ndm_internal.hpp"
#include "pnc/damage/ndm.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>

// The AVX2 copy of the batch (D386) where pnc/core/cpu.hpp can compile one (GCC or Clang on
// x86); elsewhere the baseline only.
#include "pnc/core/cpu.hpp"

namespace pnc::damage {

namespace {

using detail::damage_and_slope;

using namespace batch; // the chunk scratch, the damage-growth pass, the writes (ndm_batch_*.hpp)

// Pass 1: strains and input finiteness of points [0, m) of the chunk at `base`.
[[gnu::always_inline]] inline void load(const NdmBatch& b, std::size_t base, std::size_t m, int ns,
                                        Chunk& c) {
  for (int k = 0; k < 6; ++k) {
    const double* __restrict a = b.eps0 + static_cast<std::size_t>(k) * b.ld + base;
    const double* __restrict d = b.deps + static_cast<std::size_t>(k) * b.ld + base;
    double* __restrict e = c.eps[k];
    double* __restrict bad = c.bad;
    for (std::size_t i = 0; i < m; ++i) {
      e[i] = a[i] + d[i];
      bad[i] += nf(a[i]) + nf(d[i]) + nf(e[i]);
    }
  }
  for (int k = 0; k < ns; ++k) {
    const double* __restrict s = b.state0 + static_cast<std::size_t>(k) * b.ld + base;
    double* __restrict o = c.s0[k];
    double* __restrict bad = c.bad;
    for (std::size_t i = 0; i < m; ++i) {
      o[i] = s[i];
      bad[i] += nf(s[i]);
    }
  }
}

// Planes of the chunk's points [0, m) (ndm_batch_chunk.hpp).
[[gnu::always_inline]] inline Planes plane_kind(std::size_t m, const Chunk& c) {
  double np = 0.0; // number of plane strains (a sum: the loop vectorises)
  for (std::size_t i = 0; i < m; ++i)
    np += detail::is_plane(c.eps[2][i], c.eps[3][i], c.eps[4][i]) ? 1.0 : 0.0;
  return np == static_cast<double>(m) ? Planes::all : np == 0.0 ? Planes::none : Planes::mixed;
}

// Pass 1b: the platelet-frame strain el = T eps as local_strain() forms it (detail::times_row,
// D351), or a copy of eps.
template <Planes P>
[[gnu::always_inline]] inline void rotate(const PreparedNdm& q, std::size_t m, Chunk& c) {
  if (!q.rotated) {
    std::memcpy(c.el, c.eps, sizeof c.el);
    return;
  }
  for (int r = 0; r < 6; ++r) {
    double t[6];
    for (int j = 0; j < 6; ++j)
      t[j] = q.T(r, j);
    double* __restrict o = c.el[r];
    for (std::size_t i = 0; i < m; ++i)
      o[i] = times_row_as<P>(t, c.eps[0][i], c.eps[1][i], c.eps[2][i], c.eps[3][i], c.eps[4][i],
                             c.eps[5][i]);
  }
}

// Pass 2 (pnc): the mode stretches of D7 as compute_stretch() forms them. Block-diagonal
// strains (g23 = g13 = 0) in closed form; general strains as general_stretch() forms them
// (general_pass() below). Three loops over the chunk, chosen once per chunk: every point
// block-diagonal (a 2-D run: the general stretches are not formed), no point block-diagonal (a
// 3-D run: the closed form is not formed), or a mix (both formed, one kept per point). Each
// point gets the same numbers in all three (D352).
enum class Blocks { all, none, mixed };

[[gnu::always_inline]] inline Blocks block_kind(std::size_t m, const Chunk& c) {
  double nb = 0.0; // number of block-diagonal points (a sum: the loop vectorises)
  for (std::size_t i = 0; i < m; ++i)
    nb += (c.el[3][i] == 0.0) & (c.el[4][i] == 0.0) ? 1.0 : 0.0;
  return nb == static_cast<double>(m) ? Blocks::all : nb == 0.0 ? Blocks::none : Blocks::mixed;
}

// Pass 2 for general strains (D402): the stretches of compute_stretch() (pnc: general_stretch(),
// the caps by Sylvester's criterion; pp: lambda_max) in three loops over the points [0, m): C =
// F^T F, the uncapped stretches, their caps and the first half of lambda_max^2 (vectorised);
// the cosine of the trigonometric form for every point (vectorised, D409; formerly libm's acos
// and cos point by point, D388); lambda_max and the capped stretches (vectorised). Every expression
// is the kernel's (ndm_internal.hpp). Mixed: only the points that are not block-diagonal take the
// results, the others keep theirs.
template <Model M, bool Mixed>
[[gnu::always_inline]] inline void general_pass(std::size_t m, Chunk& c) {
  constexpr int N = M == Model::pnc ? 3 : 1;
  double un[3][kChunk], clip[3][kChunk], sh[3][kChunk], dsh[3][kChunk], val[kChunk], q[kChunk],
      pp[kChunk], r[kChunk], trig[kChunk], cos3[kChunk];
  for (std::size_t i = 0; i < m; ++i) {
    const double v[6] = {c.el[0][i], c.el[1][i], c.el[2][i], c.el[3][i], c.el[4][i], c.el[5][i]};
    double C[6];
    detail::cauchy_green(v, C);
    bool need = M == Model::pp; // lambda_max is needed: pp, or a capped pnc mode
    if constexpr (M == Model::pnc) {
      // mode k: (e_kk, e_ka, e_kb) with a = k + 1, b = k + 2 (mod 3), e = tensor(v)
      const double e01 = 0.5 * v[5], e02 = 0.5 * v[4], e12 = 0.5 * v[3];
      const double ea[3] = {e01, e12, e02}, eb[3] = {e02, e01, e12};
#pragma GCC unroll 3
      for (int k = 0; k < 3; ++k) {
        double u, g;
        const double t = detail::mode_shear(ea[k], eb[k]);
        detail::uncapped_stretch(v[k], t, u, g);
        const bool capped = (u > 0.0) & detail::exceeds_largest_eigenvalue<false>(C, u * u);
        un[k][i] = u;
        clip[k][i] = capped ? 1.0 : 0.0;
        sh[k][i] = t;
        dsh[k][i] = g;
        need = need | capped;
      }
    }
    double value, qi, ppi, ri;
    bool t;
    detail::eigen_start<false>(C, value, qi, ppi, ri, t);
    val[i] = value;
    q[i] = qi;
    pp[i] = ppi;
    r[i] = ri;
    trig[i] = (t & need) ? 1.0 : 0.0;
  }
  for (std::size_t i = 0; i < m; ++i) // every point: branch-free vector code (D409)
    cos3[i] = detail::eigen_cos(r[i]);
  for (std::size_t i = 0; i < m; ++i) {
    const double lmax = std::sqrt(detail::eigen_end(val[i], q[i], pp[i], cos3[i], trig[i] != 0.0));
    const bool keep = Mixed && (c.el[3][i] == 0.0) & (c.el[4][i] == 0.0); // block-diagonal
#pragma GCC unroll 3
    for (int k = 0; k < N; ++k) {
      const double lam = M == Model::pp ? lmax : (clip[k][i] != 0.0 ? lmax : un[k][i]);
      c.lam[k][i] = keep ? c.lam[k][i] : lam;
    }
    c.lmax[i] = keep ? c.lmax[i] : lmax; // a piece of the growth pass (D403; pp: D419)
    if constexpr (M == Model::pnc) {     // the pieces of the growth pass (D403)
#pragma GCC unroll 3
      for (int k = 0; k < 3; ++k) {
        c.tsh[k][i] = keep ? c.tsh[k][i] : sh[k][i];
        c.grow[k][i] = keep ? c.grow[k][i] : dsh[k][i];
        c.clip[k][i] = keep ? c.clip[k][i] : clip[k][i];
      }
    }
  }
}

[[gnu::always_inline]] inline void pnc_stretches(std::size_t m, Chunk& c) {
  const Blocks kind = block_kind(m, c);
  if (kind == Blocks::none) {
    general_pass<Model::pnc, false>(m, c);
    return;
  }
  double un[2], g[2], t, lmax;
  for (std::size_t i = 0; i < m; ++i) {
    double b[3];
    detail::block_stretches(c.el[0][i], c.el[1][i], c.el[2][i], c.el[5][i], lmax, b, un, g, t);
    for (int k = 0; k < 3; ++k)
      c.lam[k][i] = b[k];
    // the pieces of the growth pass (D399; compute_stretch()'s clipped = un > lambda_max; mode
    // 3 has no shear and no cap)
    c.lmax[i] = lmax;
    for (int k = 0; k < 2; ++k) {
      c.tsh[k][i] = t;
      c.grow[k][i] = g[k];
      c.clip[k][i] = un[k] > lmax ? 1.0 : 0.0;
    }
    c.tsh[2][i] = 0.0;
    c.grow[2][i] = 1.0;
    c.clip[2][i] = 0.0;
  }
  if (kind == Blocks::mixed) general_pass<Model::pnc, true>(m, c);
}

// Pass 3: kappa1 and D1 of every mode, and the path. A mode with damage growth (loading and
// dD != 0) needs the growth term of the tangent and dissipates: kernel path. Without growth,
// D1 = D0 for every mode (a mode that does not load keeps kappa; one that loads below the
// onset has D0 = D1 = 0), so the dissipated energy is 0 exactly.
template <int N>
[[gnu::always_inline]] inline void classify(const PreparedNdm& q, std::size_t m, Chunk& c) {
  const double alpha = q.p.alpha();
  const double ndb = detail::onset_margin(alpha);
  for (std::size_t i = 0; i < m; ++i) {
    double below = 1.0, grow = 0.0;
    for (int k = 0; k < N; ++k) {
      const double lam = c.lam[k][i], k0 = c.s0[k][i];
      const bool loading = lam > k0;
      const double k1 = loading ? lam : k0;
      const bool under = k1 < ndb; // mode_damage(), without its branch
      double D, dD;
      damage_and_slope(k1 / alpha, D, dD);
      D = under ? 0.0 : D;
      dD = under ? 0.0 : dD;
      c.kap[k][i] = k1;
      c.D[k][i] = D;
      below = under ? below : 0.0;
      const double growth = loading ? dD : 0.0; // dD of a loading mode
      c.dg[k][i] = growth;
      grow = growth != 0.0 ? 1.0 : grow;
    }
    const double path = below != 0.0 ? kElastic : kUnloading;
    c.path[i] = grow != 0.0 ? kKernel : path;
  }
}

// Pass 4a: sigma = C0g eps for every point of the chunk (the elastic path; the others are
// overwritten below), with the stored energy.
template <Planes P>
[[gnu::always_inline]] inline void elastic_stress(const PreparedNdm& q, std::size_t m, Chunk& c) {
  for (int r = 0; r < 6; ++r) {
    double a[6];
    for (int j = 0; j < 6; ++j)
      a[j] = q.C0g(r, j);
    double* __restrict o = c.sig[r];
    for (std::size_t i = 0; i < m; ++i)
      o[i] = times_row_as<P>(a, c.eps[0][i], c.eps[1][i], c.eps[2][i], c.eps[3][i], c.eps[4][i],
                             c.eps[5][i]);
  }
  for (std::size_t i = 0; i < m; ++i) {
    c.stored[i] = half_dot(c.sig, c.eps, i);
    c.diss[i] = 0.0;
  }
}

// Passes 1b and 4a, which take the chunk's form of the products with the strain.
template <Planes P>
[[gnu::always_inline]] inline void strain_products(const PreparedNdm& q, std::size_t m, Chunk& c) {
  rotate<P>(q, m, c);
  elastic_stress<P>(q, m, c);
}

// Pass 4b: the unloading points, gathered into a compact block: sigma = Cd eps, Cd formed
// entry by entry as the kernel does and, when their tangent is wanted (KeepSecant), kept in
// c.Ku (D387). idx lists the points (u of them).
template <int N, bool KeepSecant>
[[gnu::always_inline]] inline void unloading_stress(const PreparedNdm& q, const std::size_t* idx,
                                                    std::size_t u, Chunk& c) {
  constexpr int n = N;
  double e[6][kChunk], D[3][kChunk], s[6][kChunk], bad[kChunk];
  const std::size_t u4 = padded(u); // (lanes u..u4 repeat the last point; nothing of them is kept)
  for (std::size_t j = 0; j < u4; ++j) {
    const std::size_t i = idx[std::min(j, u - 1)];
    for (int k = 0; k < 6; ++k)
      e[k][j] = c.eps[k][i];
    for (int k = 0; k < 3; ++k)
      D[k][j] = k < n ? c.D[k][i] : 0.0;
    bad[j] = 0.0;
  }
  for (int r = 0; r < 6; ++r) {
    double a[6], d[3][6];
    for (int col = 0; col < 6; ++col) {
      a[col] = q.C0g(r, col);
      for (int k = 0; k < 3; ++k)
        d[k][col] = q.dC1g[static_cast<std::size_t>(k)](r, col);
    }
    double(*__restrict ku)[kChunk] = c.Ku + 6 * r; // entries (r, 0..5)
    for (std::size_t j = 0; j < u4; ++j) {
      double row[6];
      for (int col = 0; col < 6; ++col) {
        double x = a[col];
        for (int k = 0; k < n; ++k) {
          const double y = x + D[k][j] * d[k][col];
          x = D[k][j] != 0.0 ? y : x;
        }
        row[col] = x;
        if (KeepSecant) ku[col][j] = x;
        bad[j] += nf(x); // a tangent entry: finite unless the constants overflow
      }
      s[r][j] = detail::times_row(row, e[0][j], e[1][j], e[2][j], e[3][j], e[4][j], e[5][j]);
    }
  }
  for (std::size_t j = 0; j < u; ++j) {
    for (int k = 0; k < 6; ++k)
      c.sig[k][idx[j]] = s[k][j];
    c.bad[idx[j]] += bad[j];
    c.stored[idx[j]] = half_dot(c.sig, c.eps, idx[j]);
  }
}

// Pass 4c (ndm_batch_growth.hpp, D399) for the tangent `kind` (none: none or elastic). Out of
// line, one copy per instruction set: inlined into run(), its scratch (about 12 KB) made the
// other paths of a 3-D batch about a fifth slower for the same instructions (bench/README.md,
// "Results after D399").
template <int N, bool R, bool B>
[[gnu::always_inline]] inline void growth_kind(const PreparedNdm& q, TangentKind kind,
                                               const std::size_t* gidx, std::size_t ng, Chunk& c) {
  if (kind == TangentKind::consistent)
    growth_points<N, R, B, GrowthK::consistent>(q, gidx, ng, c);
  else if (kind == TangentKind::secant)
    growth_points<N, R, B, GrowthK::secant>(q, gidx, ng, c);
  else
    growth_points<N, R, B, GrowthK::none>(q, gidx, ng, c);
}
template <bool R, bool B>
[[gnu::always_inline]] inline void growth_with(const PreparedNdm& q, TangentKind kind,
                                               const std::size_t* gidx, std::size_t ng, Chunk& c) {
  if (q.p.model == Model::pnc)
    growth_kind<3, R, B>(q, kind, gidx, ng, c);
  else // the pp law's one mode (D419)
    growth_kind<1, R, B>(q, kind, gidx, ng, c);
}
// (No lambda here: a lambda would not inherit the AVX2 copy's target attribute.)
[[gnu::always_inline]] inline void growth_impl(const PreparedNdm& q, TangentKind kind, bool block,
                                               const std::size_t* gidx, std::size_t ng, Chunk& c) {
  if (q.rotated && block)
    growth_with<true, true>(q, kind, gidx, ng, c);
  else if (q.rotated)
    growth_with<true, false>(q, kind, gidx, ng, c);
  else if (block)
    growth_with<false, true>(q, kind, gidx, ng, c);
  else
    growth_with<false, false>(q, kind, gidx, ng, c);
}
[[gnu::noinline]] void growth_baseline(const PreparedNdm& q, TangentKind kind, bool block,
                                       const std::size_t* gidx, std::size_t ng, Chunk& c) {
  growth_impl(q, kind, block, gidx, ng, c);
}
#if PNC_HAVE_AVX2_COPY
[[gnu::noinline]] PNC_TARGET_AVX2 void growth_avx2(const PreparedNdm& q, TangentKind kind,
                                                   bool block, const std::size_t* gidx,
                                                   std::size_t ng, Chunk& c) {
  growth_impl(q, kind, block, gidx, ng, c);
}
[[gnu::noinline]] PNC_TARGET_AVX512 void growth_avx512(const PreparedNdm& q, TangentKind kind,
                                                       bool block, const std::size_t* gidx,
                                                       std::size_t ng, Chunk& c) {
  growth_impl(q, kind, block, gidx, ng, c);
}
#endif

// Pass 4d: a kernel point through integrate_row_major(); its tangent into K36 (pass 4c, the
// vectorised damage growth, is ndm_batch_growth.hpp).
[[gnu::always_inline]] inline void kernel_point(const PreparedNdm& q, const NdmBatch& b,
                                                std::size_t base, std::size_t i, int ns, Chunk& c,
                                                double* K36) {
  double e0[6], de[6], flat[6], sig[6];
  for (int k = 0; k < 6; ++k) {
    e0[k] = b.eps0[static_cast<std::size_t>(k) * b.ld + base + i];
    de[k] = b.deps[static_cast<std::size_t>(k) * b.ld + base + i];
  }
  for (int k = 0; k < ns; ++k)
    flat[k] = c.s0[k][i];
  const Model model = q.p.model;
  const NdmState s0 = state_from_array(model, flat);
  NdmState s1;
  NdmEnergy energy;
  ErrorBuffer err;
  const Status st = integrate_row_major(q, s0, s1, e0, de, sig, K36, err, b.kind, &energy);
  if (st != Status::ok) {
    c.bad[i] += 1.0;
    return;
  }
  state_to_array(model, s1, flat);
  const int n = model == Model::pnc ? 3 : 1;
  for (int k = 0; k < n; ++k) {
    c.kap[k][i] = flat[k];
    c.D[k][i] = flat[n + k];
  }
  for (int k = 0; k < 6; ++k)
    c.sig[k][i] = sig[k];
  c.stored[i] = energy.stored;
  c.diss[i] = energy.dissipated;
  if (K36)
    for (int k = 0; k < 36; ++k)
      c.bad[i] += nf(K36[k]);
}

// The copy of the batch: which instruction set run() is compiled for (D386, D413).
enum class Copy { baseline, avx2, avx512 };

// The whole batch, inlined (with every pass above) into one function per instruction set
// below, so that each gets its own vectorised loops (D386).
template <Copy I>
[[gnu::always_inline]] inline NdmBatchStats run(const PreparedNdm& q, const NdmBatch& b) {
  NdmBatchStats stats;
  stats.first_failed = b.n;
  const Model model = q.p.model;
  const int n = model == Model::pnc ? 3 : 1;
  const int ns = static_cast<int>(state_size(model));
  Chunk c;
  double Kk[kChunk][36]; // tangents of the kernel points of a chunk
  std::size_t uidx[kChunk], kidx[kChunk], gidx[kChunk];
  for (std::size_t base = 0; base < b.n; base += kChunk) {
    const std::size_t m = std::min(kChunk, b.n - base);
    std::fill(c.bad, c.bad + m, 0.0);
    load(b, base, m, ns, c);
    // the products with the strain in one form per chunk (D401): el = T eps and sigma = C0g eps
    // of the elastic path (the later passes overwrite the other points' stress)
    const Planes planes = plane_kind(m, c);
    if (planes == Planes::all)
      strain_products<Planes::all>(q, m, c);
    else if (planes == Planes::none)
      strain_products<Planes::none>(q, m, c);
    else
      strain_products<Planes::mixed>(q, m, c);
    if (model == Model::pnc)
      pnc_stretches(m, c);
    else
      general_pass<Model::pp, false>(m, c);
    if (n == 3)
      classify<3>(q, m, c);
    else
      classify<1>(q, m, c);
    std::size_t nu = 0, nk = 0, ng = 0;
    for (std::size_t i = 0; i < m; ++i) {
      if (c.bad[i] != 0.0) continue; // failed on input: no path
      if (c.path[i] == kUnloading) uidx[nu++] = i;
      if (c.path[i] != kKernel) continue;
      gidx[ng++] = i; // damage growth: the growth pass (D399, D403; pp: D419)
    }
    const bool want_K = b.kind != TangentKind::none && b.K;
    const bool secant = want_K && b.kind != TangentKind::elastic; // unloading: K = Cd
    if (nu && n == 3 && secant) unloading_stress<3, true>(q, uidx, nu, c);
    if (nu && n == 3 && !secant) unloading_stress<3, false>(q, uidx, nu, c);
    if (nu && n == 1 && secant) unloading_stress<1, true>(q, uidx, nu, c);
    if (nu && n == 1 && !secant) unloading_stress<1, false>(q, uidx, nu, c);
    const TangentKind gk = secant ? b.kind : TangentKind::none;
    bool block = true; // every growth point's strain block-diagonal
    for (std::size_t j = 0; j < ng; ++j)
      block = block && c.el[3][gidx[j]] == 0.0 && c.el[4][gidx[j]] == 0.0;
#if PNC_HAVE_AVX2_COPY
    if (ng && I == Copy::avx2) growth_avx2(q, gk, block, gidx, ng, c);
    if (ng && I == Copy::avx512) growth_avx512(q, gk, block, gidx, ng, c);
#endif
    if (ng && I == Copy::baseline) growth_baseline(q, gk, block, gidx, ng, c);
    for (std::size_t j = 0; j < ng; ++j) // lambda_max repeated where a capped mode grows
      if (c.vec_growth[gidx[j]] == 0.0) kidx[nk++] = gidx[j];
    for (std::size_t j = 0; j < nk; ++j)
      kernel_point(q, b, base, kidx[j], ns, c, want_K ? Kk[j] : nullptr);
    check_results(m, n, c);
    const bool all_ok = commit(q, b, base, m, n, c, Kk, kidx, nk, uidx, nu, gidx, ng);
    if (all_ok) { // every point has its path: the counts are those of the lists
      std::size_t grown = 0;
      for (std::size_t j = 0; j < ng; ++j)
        grown += c.vec_growth[gidx[j]] != 0.0 ? 1 : 0;
      stats.growth += grown;
      stats.kernel += nk;
      stats.unloading += nu;
      stats.elastic += m - nu - nk - grown;
      continue;
    }
    for (std::size_t i = 0; i < m; ++i) {
      if (c.bad[i] != 0.0) {
        if (stats.failed++ == 0) stats.first_failed = base + i;
      } else if (c.path[i] == kKernel && c.vec_growth[i] != 0.0) {
        ++stats.growth;
      } else if (c.path[i] == kKernel) {
        ++stats.kernel;
      } else if (c.path[i] == kUnloading) {
        ++stats.unloading;
      } else {
        ++stats.elastic;
      }
    }
  }
  return stats;
}

// SSE2, the project's baseline: for every x86-64 CPU.
[[gnu::noinline]] NdmBatchStats run_baseline(const PreparedNdm& q, const NdmBatch& b) {
  return run<Copy::baseline>(q, b);
}

#if PNC_HAVE_AVX2_COPY
// The same source for CPUs with AVX2 (4 doubles a vector) and with AVX-512 (8 doubles a vector,
// D413). No FMA: the file is compiled with -ffp-contract=off and
// neither target enables contraction, so every operation rounds as in the baseline and the
// three functions give the same bits (D386).
[[gnu::noinline]] PNC_TARGET_AVX2 NdmBatchStats run_avx2(const PreparedNdm& q, const NdmBatch& b) {
  return run<Copy::avx2>(q, b);
}
[[gnu::noinline]] PNC_TARGET_AVX512 NdmBatchStats run_avx512(const PreparedNdm& q,
                                                             const NdmBatch& b) {
  return run<Copy::avx512>(q, b);
}
#endif

const char* isa_name(BatchIsa isa) {
  switch (isa) {
  case BatchIsa::automatic:
    return "BatchIsa::automatic";
  case BatchIsa::baseline:
    return "BatchIsa::baseline";
  case BatchIsa::avx2:
    return "BatchIsa::avx2 (AVX2)";
  case BatchIsa::avx512:
    return "BatchIsa::avx512 (AVX-512 F, CD, VL, BW, DQ)";
  }
  return "an unknown BatchIsa value";
}

} // namespace

bool batch_isa_available(BatchIsa isa) {
  switch (isa) {
  case BatchIsa::automatic:
  case BatchIsa::baseline:
    return true;
  case BatchIsa::avx2:
    return pnc::cpu_has_avx2(); // false where the build has no AVX2 copy (cpu.hpp)
  case BatchIsa::avx512:
    return pnc::cpu_has_avx512(); // the same for AVX-512
  }
  return false;
}

NdmBatchStats integrate_batch(const PreparedNdm& q, const NdmBatch& b, BatchIsa isa) {
  if (!batch_isa_available(isa))
    throw std::invalid_argument(std::string("pnc::damage::integrate_batch: instruction set ") +
                                isa_name(isa) +
                                " was requested, but this CPU or build does not have it, or the "
                                "environment variable PNC_SIMD caps it (use BatchIsa::automatic "
                                "or BatchIsa::baseline)");
#if PNC_HAVE_AVX2_COPY
  if (isa == BatchIsa::automatic)
    isa = pnc::cpu_has_avx512() ? BatchIsa::avx512
          : pnc::cpu_has_avx2() ? BatchIsa::avx2
                                : BatchIsa::baseline;
  if (isa == BatchIsa::avx512) return run_avx512(q, b);
  if (isa == BatchIsa::avx2) return run_avx2(q, b);
#endif
  return run_baseline(q, b);
}

NdmBatchStats integrate_batch(const PreparedNdm& q, const NdmBatch& b) {
  return integrate_batch(q, b, BatchIsa::automatic);
}

} // namespace pnc::damage
