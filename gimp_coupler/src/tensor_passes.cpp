// The row kernels of the uGIMP step (tensor_passes.hpp, D404), compiled for the baseline, for
// AVX2 and for AVX-512 (D377's run-time choice, D414). Compiled with -O3 -ffp-contract=off
// (CMakeLists.txt): no FMA contraction, and every lane loop keeps each lane's own order of
// operations, so all copies give the same bits. Units as in tensor_passes.hpp.
#include "tensor_passes.hpp"

#include "pnc/core/cpu.hpp"

namespace pnc::gimp::detail {

namespace {

/// Row s of aw's stencil along axis 0 (see tensor_passes.hpp): its first node, r and rd
/// (s = j in 2-D, 3 k + j in 3-D). Scalars computed where they are used: an array of rows
/// filled first and read back made the compiler reload pairs of scalar stores as vectors
/// (store-forwarding stalls).
/// Without kDer, rd is left unset and aw's derivatives are not read (G2P: AxisValues, D422).
template <int D, bool kDer = true> struct Row {
  static constexpr int n = D == 2 ? 3 : 9;
  std::int64_t node;
  double r, rd[D - 1];
  template <class AW> [[gnu::always_inline]] inline Row(const Grid<D>& g, const AW& aw, int s) {
    const auto& w = aw.w;
    if constexpr (D == 2) {
      node = static_cast<std::int64_t>(aw.i0[1] + s) * g.n[0] + aw.i0[0];
      r = w[1][s];
      if constexpr (kDer) rd[0] = aw.dw[1][s];
    } else {
      const int j = s % 3, k = s / 3;
      node =
          (static_cast<std::int64_t>(aw.i0[2] + k) * g.n[1] + (aw.i0[1] + j)) * g.n[0] + aw.i0[0];
      r = w[1][j] * w[2][k];
      if constexpr (kDer) {
        rd[0] = aw.dw[1][j] * w[2][k];
        rd[1] = w[1][j] * aw.dw[2][k];
      }
    }
  }
};

/// L doubles as L / 4 four-wide vectors and L % 4 scalars (GCC/Clang vector extension; in the
/// baseline copy each vector operation is split into SSE2 halves). Written out so that the
/// compiler vectorises along the lanes of a row, not across rows (which it did with plain
/// loops, through gathers). Element-wise operations only: each lane keeps its own rounding.
template <int L> struct Lanes {
  typedef double v4 __attribute__((vector_size(32), aligned(8), may_alias));
  static constexpr int V = L / 4, R = L % 4;
  v4 v[V];
  double t[R];
  [[gnu::always_inline]] inline static Lanes load(const double* p) {
    Lanes x;
    for (int k = 0; k < V; ++k)
      x.v[k] = *reinterpret_cast<const v4*>(p + 4 * k);
    for (int k = 0; k < R; ++k)
      x.t[k] = p[4 * V + k];
    return x;
  }
  [[gnu::always_inline]] inline static Lanes zero() {
    Lanes x;
    for (int k = 0; k < V; ++k)
      x.v[k] = v4{0.0, 0.0, 0.0, 0.0};
    for (int k = 0; k < R; ++k)
      x.t[k] = 0.0;
    return x;
  }
  [[gnu::always_inline]] inline void store(double* p) const {
    for (int k = 0; k < V; ++k)
      *reinterpret_cast<v4*>(p + 4 * k) = v[k];
    for (int k = 0; k < R; ++k)
      p[4 * V + k] = t[k];
  }
  [[gnu::always_inline]] inline double operator[](int q) const {
    return q < 4 * V ? v[q / 4][q % 4] : t[q - 4 * V];
  }
  [[gnu::always_inline]] inline Lanes& operator+=(const Lanes& o) {
    for (int k = 0; k < V; ++k)
      v[k] += o.v[k];
    for (int k = 0; k < R; ++k)
      t[k] += o.t[k];
    return *this;
  }
  [[gnu::always_inline]] inline Lanes& operator-=(const Lanes& o) {
    for (int k = 0; k < V; ++k)
      v[k] -= o.v[k];
    for (int k = 0; k < R; ++k)
      t[k] -= o.t[k];
    return *this;
  }
  [[gnu::always_inline]] inline friend Lanes operator-(Lanes a, const Lanes& b) { return a -= b; }
  [[gnu::always_inline]] inline friend Lanes operator+(Lanes a, const Lanes& b) { return a += b; }
  [[gnu::always_inline]] inline friend Lanes operator*(double s, const Lanes& a) {
    Lanes x;
    for (int k = 0; k < V; ++k)
      x.v[k] = s * a.v[k];
    for (int k = 0; k < R; ++k)
      x.t[k] = s * a.t[k];
    return x;
  }
};

/// The lanes q = D i + a of a row with value f(i, a), built in registers (filling an array
/// and loading it as vectors would stall on store forwarding).
template <int D, class F> [[gnu::always_inline]] inline Lanes<3 * D> lanes_of(F f) {
  using Ln = Lanes<3 * D>;
  Ln x;
  auto at = [&](int q) { return f(q / D, q % D); };
  for (int k = 0; k < Ln::V; ++k)
    x.v[k] = typename Ln::v4{at(4 * k), at(4 * k + 1), at(4 * k + 2), at(4 * k + 3)};
  for (int k = 0; k < Ln::R; ++k)
    x.t[k] = at(4 * Ln::V + k);
  return x;
}

template <int D, class AW>
[[gnu::always_inline]] inline void scatter_body(const Grid<D>& g, const AW& aw,
                                                const P2GParticle<D>& in, bool external,
                                                const NodeArrays& out) {
  using Ln = Lanes<3 * D>;
  const auto& w0 = aw.w[0];
  const auto& d0 = aw.dw[0];
  // per unit r: momentum w0_i (m v)_a, external force w0_i fext_a, internal force
  // d0_i sV[a][0] (times r) and w0_i sV[a][c] (times rd[c - 1])
  double mv[D], sV[D][D];
  for (int a = 0; a < D; ++a) {
    mv[a] = in.m * in.v[a];
    for (int c = 0; c < D; ++c)
      sV[a][c] = in.sigma[a + 3 * c] * in.V;
  }
  const Ln PW = lanes_of<D>([&](int i, int a) { return w0[i] * mv[a]; });
  const Ln EW =
      external ? lanes_of<D>([&](int i, int a) { return w0[i] * in.fext[a]; }) : Ln::zero();
  const Ln FA = lanes_of<D>([&](int i, int a) { return d0[i] * sV[a][0]; });
  Ln FB[D - 1];
  for (int c = 1; c < D; ++c)
    FB[c - 1] = lanes_of<D>([&](int i, int a) { return w0[i] * sV[a][c]; });
  const double MW[3] = {w0[0] * in.m, w0[1] * in.m, w0[2] * in.m};
#pragma GCC unroll 9
  for (int s = 0; s < Row<D>::n; ++s) {
    const Row<D> rw(g, aw, s);
    const std::int64_t row = rw.node;
    const double r = rw.r;
    double* m = out.m + row;
    for (int i = 0; i < 3; ++i)
      m[i] += r * MW[i];
    double* p = out.p + D * row;
    (Ln::load(p) + r * PW).store(p);
    Ln t = r * FA;
    for (int c = 1; c < D; ++c)
      t += rw.rd[c - 1] * FB[c - 1];
    double* f = out.fi + D * row;
    (Ln::load(f) - t).store(f);
    if (external) {
      double* e = out.fe + D * row;
      (Ln::load(e) + r * EW).store(e);
    }
  }
}

template <int D, class AW>
[[gnu::always_inline]] inline void scatter_force_body(const Grid<D>& g, const AW& aw,
                                                      const double* sigma, double V, double* fi) {
  using Ln = Lanes<3 * D>;
  const auto& w0 = aw.w[0];
  const auto& d0 = aw.dw[0];
  double sV[D][D];
  for (int a = 0; a < D; ++a)
    for (int c = 0; c < D; ++c)
      sV[a][c] = sigma[a + 3 * c] * V;
  const Ln FA = lanes_of<D>([&](int i, int a) { return d0[i] * sV[a][0]; });
  Ln FB[D - 1];
  for (int c = 1; c < D; ++c)
    FB[c - 1] = lanes_of<D>([&](int i, int a) { return w0[i] * sV[a][c]; });
#pragma GCC unroll 9
  for (int s = 0; s < Row<D>::n; ++s) {
    const Row<D> rw(g, aw, s);
    Ln t = rw.r * FA;
    for (int c = 1; c < D; ++c)
      t += rw.rd[c - 1] * FB[c - 1];
    double* f = fi + D * rw.node;
    (Ln::load(f) - t).store(f);
  }
}

template <int D, class AW>
[[gnu::always_inline]] inline void gradient_body(const Grid<D>& g, const AW& aw, const double* v,
                                                 double (&grad)[D][D]) {
  using Ln = Lanes<3 * D>;
  Ln acc[D]; // acc[0]: sum r v; acc[c]: sum rd[c-1] v
  for (int c = 0; c < D; ++c)
    acc[c] = Ln::zero();
#pragma GCC unroll 9
  for (int s = 0; s < Row<D>::n; ++s) {
    const Row<D> rw(g, aw, s);
    const Ln x = Ln::load(v + D * rw.node);
    acc[0] += rw.r * x;
    for (int c = 1; c < D; ++c)
      acc[c] += rw.rd[c - 1] * x;
  }
  const auto& w0 = aw.w[0];
  const auto& d0 = aw.dw[0];
  for (int a = 0; a < D; ++a)
    for (int c = 0; c < D; ++c) {
      const auto& P = c == 0 ? d0 : w0;
      grad[a][c] = P[0] * acc[c][a] + P[1] * acc[c][D + a] + P[2] * acc[c][2 * D + a];
    }
}

template <int D>
[[gnu::always_inline]] inline void
velocities_body(const Grid<D>& g, const AxisValues<D>& aw, const double* vs, const double* vn,
                const double* v0, double (&vs_p)[D], double (&dv_p)[D]) {
  using Ln = Lanes<3 * D>;
  Ln ax = Ln::zero(), av = Ln::zero();
#pragma GCC unroll 9
  for (int s = 0; s < Row<D>::n; ++s) {
    const Row<D, false> rw(g, aw, s);
    const std::int64_t q = D * rw.node;
    const double r = rw.r;
    ax += r * Ln::load(vs + q);
    av += r * (Ln::load(vn + q) - Ln::load(v0 + q));
  }
  const auto& w0 = aw.w[0];
  for (int a = 0; a < D; ++a) {
    vs_p[a] = w0[0] * ax[a] + w0[1] * ax[D + a] + w0[2] * ax[2 * D + a];
    dv_p[a] = w0[0] * av[a] + w0[1] * av[D + a] + w0[2] * av[2 * D + a];
  }
}

// The three copies: the same bodies under the baseline, the AVX2 and the AVX-512 targets.
#define PNC_ROW_COPY(NS, ATTR)                                                                     \
  namespace NS {                                                                                   \
  template <int D>                                                                                 \
  ATTR void scatter(const Grid<D>& g, const AxisValues<D>& av, const AxisSlopes<D>& ad,            \
                    const P2GParticle<D>& in, bool external, const NodeArrays& out) {              \
    scatter_body(g, split_view(av, ad), in, external, out);                                        \
  }                                                                                                \
  template <int D>                                                                                 \
  ATTR void scatter_force(const Grid<D>& g, const AxisValues<D>& av, const AxisSlopes<D>& ad,      \
                          const double* sigma, double V, double* fi) {                             \
    scatter_force_body(g, split_view(av, ad), sigma, V, fi);                                       \
  }                                                                                                \
  template <int D>                                                                                 \
  ATTR void gradient(const Grid<D>& g, const AxisValues<D>& av, const AxisSlopes<D>& ad,           \
                     const double* v, double (&grad)[D][D]) {                                      \
    gradient_body(g, split_view(av, ad), v, grad);                                                 \
  }                                                                                                \
  template <int D>                                                                                 \
  ATTR void velocities(const Grid<D>& g, const AxisValues<D>& av, const double* vs,                \
                       const double* vn, const double* v0, double (&vs_p)[D], double (&dv_p)[D]) { \
    velocities_body(g, av, vs, vn, v0, vs_p, dv_p);                                                \
  }                                                                                                \
  template <int D>                                                                                 \
  const RowKernels<D> kernels{scatter<D>, scatter_force<D>, gradient<D>, velocities<D>};           \
  }

PNC_ROW_COPY(baseline, )
PNC_ROW_COPY(avx2, PNC_TARGET_AVX2)
PNC_ROW_COPY(avx512, PNC_TARGET_AVX512)
#undef PNC_ROW_COPY

} // namespace

template <int D> const RowKernels<D>& row_kernels(int copy) {
  if (!PNC_HAVE_AVX2_COPY) return baseline::kernels<D>;
  return copy == 2 ? avx512::kernels<D> : copy == 1 ? avx2::kernels<D> : baseline::kernels<D>;
}

template <int D> const RowKernels<D>& row_kernels() {
  return row_kernels<D>(pnc::cpu_has_avx512() ? 2 : pnc::cpu_has_avx2() ? 1 : 0);
}

template const RowKernels<2>& row_kernels<2>(int);
template const RowKernels<3>& row_kernels<3>(int);
template const RowKernels<2>& row_kernels<2>();
template const RowKernels<3>& row_kernels<3>();

} // namespace pnc::gimp::detail
