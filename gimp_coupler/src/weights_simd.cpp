// Branch-free uGIMP 1-D weights of many points (weights_simd.hpp, D376), baseline, AVX2 and
// AVX-512 builds with a run-time choice (D377, D414). Compiled with -O3 -ffp-contract=off
// (gimp_coupler/CMakeLists.txt): no FMA contraction, so every build rounds every operation
// exactly as ugimp_weight does. Units: m, 1/m.
#include "pnc/gimp_coupler/weights_simd.hpp"

#include "pnc/gimp_coupler/weights.hpp"

// The AVX2 and AVX-512 builds exist where pnc/core/cpu.hpp says it can (GCC or Clang on x86);
// elsewhere both entry points are the portable loop.
#include "pnc/core/cpu.hpp"

namespace pnc::gimp {

namespace {

// The piecewise weight of ugimp_weight as a selection instead of an if-chain (D376): every
// piece is written as S = c + nS / dS_den, dS = nd / dd with c in {0, 1}, and the pieces are
// taken from the last one down, so that the lowest bound `xi <= t` that holds wins, as the
// first true test of the if-chain does (also for NaN: no test holds, S = dS = 0). Each piece
// performs the same operations as in ugimp_weight: 1 - q == 1 + (-q) and (-a) / b == -(a / b)
// exactly in IEEE arithmetic, and 0 + q == q for the q >= 0 of the quadratic tails.
inline __attribute__((always_inline)) void weights_body(std::size_t n, const double* __restrict xi,
                                                        const double* __restrict l, double L,
                                                        double* __restrict S,
                                                        double* __restrict dS) {
  for (std::size_t k = 0; k < n; ++k) {
    const double x = xi[k], h = l[k];
    const double L4l = 4.0 * L * h, L2l = 2.0 * L * h, Ll = L * h, Lpl = L + h;
    const double a1 = L + h + x, a5 = L + h - x;
    double c = 0.0, ns = 0.0, ds = 1.0, nd = 0.0, dd = 1.0; // xi > L + l: zero
    const bool q5 = x <= Lpl;                               // quadratic tail, right
    c = q5 ? 0.0 : c;
    ns = q5 ? a5 * a5 : ns;
    ds = q5 ? L4l : ds;
    nd = q5 ? -a5 : nd;
    dd = q5 ? L2l : dd;
    const bool q4 = x <= L - h; // linear, falling
    c = q4 ? 1.0 : c;
    ns = q4 ? -x : ns;
    ds = q4 ? L : ds;
    nd = q4 ? -1.0 : nd;
    dd = q4 ? L : dd;
    const bool q3 = x <= h; // quadratic top
    c = q3 ? 1.0 : c;
    ns = q3 ? -(x * x + h * h) : ns;
    ds = q3 ? L2l : ds;
    nd = q3 ? -x : nd;
    dd = q3 ? Ll : dd;
    const bool q2 = x <= -h; // linear, rising
    c = q2 ? 1.0 : c;
    ns = q2 ? x : ns;
    ds = q2 ? L : ds;
    nd = q2 ? 1.0 : nd;
    dd = q2 ? L : dd;
    const bool q1 = x <= -L + h; // quadratic tail, left
    c = q1 ? 0.0 : c;
    ns = q1 ? a1 * a1 : ns;
    ds = q1 ? L4l : ds;
    nd = q1 ? a1 : nd;
    dd = q1 ? L2l : dd;
    const bool q0 = x <= -L - h; // zero
    c = q0 ? 0.0 : c;
    ns = q0 ? 0.0 : ns;
    ds = q0 ? 1.0 : ds;
    nd = q0 ? 0.0 : nd;
    dd = q0 ? 1.0 : dd;
    S[k] = c + ns / ds;
    dS[k] = nd / dd;
  }
}

} // namespace

namespace simd {

void ugimp_weights_default(std::size_t n, const double* xi, const double* l, double L, double* S,
                           double* dS) {
  weights_body(n, xi, l, L, S, dS);
}

PNC_TARGET_AVX2 void ugimp_weights_avx2(std::size_t n, const double* xi, const double* l, double L,
                                        double* S, double* dS) {
  weights_body(n, xi, l, L, S, dS);
}

PNC_TARGET_AVX512 void ugimp_weights_avx512(std::size_t n, const double* xi, const double* l,
                                            double L, double* S, double* dS) {
  weights_body(n, xi, l, L, S, dS);
}

} // namespace simd

void ugimp_weights(std::size_t n, const double* xi, const double* l, double L, double* S,
                   double* dS) {
  if (pnc::cpu_has_avx512())
    simd::ugimp_weights_avx512(n, xi, l, L, S, dS);
  else if (pnc::cpu_has_avx2())
    simd::ugimp_weights_avx2(n, xi, l, L, S, dS);
  else
    simd::ugimp_weights_default(n, xi, l, L, S, dS);
}

namespace {

/// The body of compute_axis_weights_many (weights.hpp), inlined into each compiled copy.
/// `val` receives i0 and the values, `der` the derivatives: both AxisWeights<D>* (one record)
/// or AxisValues<D>* and AxisSlopes<D>* (the solver's split records, D422).
template <int D, class V, class G>
[[gnu::always_inline]] inline std::size_t
axis_weights_many_body(const Grid<D>& g, std::size_t n, const Eigen::Matrix<double, D, 1>* x,
                       const Eigen::Matrix<double, D, 1>* l, V* val, G* der) {
  constexpr std::size_t kChunk = 64, m = 3 * D;
  double xi[kChunk * m], hl[kChunk * m], S[kChunk * m], dS[kChunk * m];
  for (std::size_t c0 = 0; c0 < n; c0 += kChunk) {
    const std::size_t c1 = std::min(n, c0 + kChunk);
    for (std::size_t p = c0; p < c1; ++p)
      if (!axis_offsets(g, x[p], l[p], val[p].i0, xi + (p - c0) * m, hl + (p - c0) * m)) return p;
    weights_body((c1 - c0) * m, xi, hl, g.h, S, dS);
    for (std::size_t p = c0; p < c1; ++p) {
      std::copy(S + (p - c0) * m, S + (p - c0 + 1) * m, &val[p].w[0][0]);
      std::copy(dS + (p - c0) * m, dS + (p - c0 + 1) * m, &der[p].dw[0][0]);
    }
  }
  return n;
}

template <int D, class V, class G>
std::size_t axis_weights_many_default(const Grid<D>& g, std::size_t n,
                                      const Eigen::Matrix<double, D, 1>* x,
                                      const Eigen::Matrix<double, D, 1>* l, V* val, G* der) {
  return axis_weights_many_body(g, n, x, l, val, der);
}

// The offsets (floor, conversions) and the copies compiled for AVX2 and AVX-512 too (D407,
// D414): floor is one rounding instruction there (SSE4.1), a longer sequence in the baseline;
// the same values.
template <int D, class V, class G>
PNC_TARGET_AVX2 std::size_t
axis_weights_many_avx2(const Grid<D>& g, std::size_t n, const Eigen::Matrix<double, D, 1>* x,
                       const Eigen::Matrix<double, D, 1>* l, V* val, G* der) {
  return axis_weights_many_body(g, n, x, l, val, der);
}

template <int D, class V, class G>
PNC_TARGET_AVX512 std::size_t
axis_weights_many_avx512(const Grid<D>& g, std::size_t n, const Eigen::Matrix<double, D, 1>* x,
                         const Eigen::Matrix<double, D, 1>* l, V* val, G* der) {
  return axis_weights_many_body(g, n, x, l, val, der);
}

template <int D, class V, class G>
std::size_t axis_weights_many(const Grid<D>& g, std::size_t n, const Eigen::Matrix<double, D, 1>* x,
                              const Eigen::Matrix<double, D, 1>* l, V* val, G* der) {
  if (pnc::cpu_has_avx512()) return axis_weights_many_avx512(g, n, x, l, val, der);
  return pnc::cpu_has_avx2() ? axis_weights_many_avx2(g, n, x, l, val, der)
                             : axis_weights_many_default(g, n, x, l, val, der);
}

} // namespace

template <int D>
std::size_t compute_axis_weights_many(const Grid<D>& g, std::size_t n,
                                      const Eigen::Matrix<double, D, 1>* x,
                                      const Eigen::Matrix<double, D, 1>* l, AxisWeights<D>* aw) {
  return axis_weights_many(g, n, x, l, aw, aw);
}

template <int D>
std::size_t compute_axis_weights_many(const Grid<D>& g, std::size_t n,
                                      const Eigen::Matrix<double, D, 1>* x,
                                      const Eigen::Matrix<double, D, 1>* l, AxisValues<D>* values,
                                      AxisSlopes<D>* slopes) {
  return axis_weights_many(g, n, x, l, values, slopes);
}

template std::size_t compute_axis_weights_many<2>(const Grid<2>&, std::size_t,
                                                  const Eigen::Matrix<double, 2, 1>*,
                                                  const Eigen::Matrix<double, 2, 1>*,
                                                  AxisWeights<2>*);
template std::size_t compute_axis_weights_many<3>(const Grid<3>&, std::size_t,
                                                  const Eigen::Matrix<double, 3, 1>*,
                                                  const Eigen::Matrix<double, 3, 1>*,
                                                  AxisWeights<3>*);

template std::size_t compute_axis_weights_many<2>(const Grid<2>&, std::size_t,
                                                  const Eigen::Matrix<double, 2, 1>*,
                                                  const Eigen::Matrix<double, 2, 1>*,
                                                  AxisValues<2>*, AxisSlopes<2>*);
template std::size_t compute_axis_weights_many<3>(const Grid<3>&, std::size_t,
                                                  const Eigen::Matrix<double, 3, 1>*,
                                                  const Eigen::Matrix<double, 3, 1>*,
                                                  AxisValues<3>*, AxisSlopes<3>*);

} // namespace pnc::gimp
