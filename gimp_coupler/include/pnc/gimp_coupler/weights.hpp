#pragma once
// pnc/gimp_coupler/weights.hpp: uGIMP shape functions on a regular background grid.
//
// The 1-D weight S(xi) and its derivative dS/dx_p (docs/theory.md §5.1) for xi = x_p - X_i, cell
// size L and particle half-length l, with 0 < l <= L/2. In 2-D/3-D the weight is the product over
// axes,
//   S_ip = prod_a S(xi_a),  dS_ip/dx_a = S'(xi_a) prod_{b != a} S(xi_b).
// Units: lengths in m, S dimensionless, dS/dx in 1/m.
//
// With l <= L/2 a particle touches at most two cells per axis, so its support holds at most
// three nodes per axis: 3^D nodes (9 in 2-D, 27 in 3-D); Stencil<D> holds them.
#include "pnc/gimp_coupler/weights_simd.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace pnc::gimp {

struct Weight1D {
  double S;  ///< weight, dimensionless
  double dS; ///< dS/dx_p, 1/m
};

/// uGIMP weight for xi = x_p - X_i (m), cell size L (m), particle half-length l (m), 0 < l <= L/2.
inline Weight1D ugimp_weight(double xi, double L, double l) {
  if (xi <= -L - l) return {0.0, 0.0};
  if (xi <= -L + l) {
    const double a = L + l + xi;
    return {a * a / (4.0 * L * l), a / (2.0 * L * l)};
  }
  if (xi <= -l) return {1.0 + xi / L, 1.0 / L};
  if (xi <= l) return {1.0 - (xi * xi + l * l) / (2.0 * L * l), -xi / (L * l)};
  if (xi <= L - l) return {1.0 - xi / L, -1.0 / L};
  if (xi <= L + l) {
    const double a = L + l - xi;
    return {a * a / (4.0 * L * l), -a / (2.0 * L * l)};
  }
  return {0.0, 0.0};
}

/// Regular background grid: nodes X = origin + h * (i, j, k), i in [0, n[0]) etc.
template <int D> struct Grid {
  using Vec = Eigen::Matrix<double, D, 1>;
  Vec origin = Vec::Zero(); ///< m
  double h = 1.0;           ///< cell size, m (cubic cells)
  std::array<int, D> n{};   ///< nodes per axis (cells + 1)
  std::int64_t nodes() const {
    std::int64_t k = 1;
    for (int a = 0; a < D; ++a)
      k *= n[a];
    return k;
  }
  std::int64_t index(const std::array<int, D>& ijk) const {
    std::int64_t id = ijk[D - 1];
    for (int a = D - 2; a >= 0; --a)
      id = id * n[a] + ijk[a];
    return id;
  }
  std::array<int, D> ijk(std::int64_t id) const {
    std::array<int, D> r{};
    for (int a = 0; a < D; ++a) {
      r[a] = static_cast<int>(id % n[a]);
      id /= n[a];
    }
    return r;
  }
  Vec position(std::int64_t id) const {
    const auto r = ijk(id);
    Vec x;
    for (int a = 0; a < D; ++a)
      x[a] = origin[a] + h * r[a];
    return x;
  }
  Vec upper() const {
    Vec x;
    for (int a = 0; a < D; ++a)
      x[a] = origin[a] + h * (n[a] - 1);
    return x;
  }
};

/// The 3^D nodes of one particle's support with weights and gradients.
template <int D> struct Stencil {
  static constexpr int size = D == 2 ? 9 : 27;
  using Vec = Eigen::Matrix<double, D, 1>;
  std::array<std::int64_t, size> node{};
  std::array<double, size> S{};
  std::array<Vec, size> dS{};
};

/// Per-axis weights of one particle: first node index per axis and the three 1-D weights
/// and derivatives per axis (the stencil is their tensor product).
template <int D> struct AxisWeights {
  std::array<int, D> i0{};
  std::array<std::array<double, 3>, D> w{}, dw{};
  static_assert(sizeof(w) == 3 * D * sizeof(double), "w, dw: 3 D contiguous doubles");
};

/// AxisWeights split in two records, as the solver caches them (D422): the first node index
/// per axis with the values, and the derivatives (1/m). G2P needs the values only and reads 56
/// of the 104 bytes of a particle's weights in 2-D (88 of 160 in 3-D).
template <int D> struct AxisValues {
  std::array<int, D> i0{};
  std::array<std::array<double, 3>, D> w{};
};
template <int D> struct AxisSlopes { std::array<std::array<double, 3>, D> dw{}; };

/// One particle's weights read from its two records, with AxisWeights' member names (the
/// stencil functions below take either).
template <int D> struct SplitWeights {
  const std::array<int, D>& i0;
  const std::array<std::array<double, 3>, D>& w;
  const std::array<std::array<double, 3>, D>& dw;
};
template <int D> SplitWeights<D> split_view(const AxisValues<D>& v, const AxisSlopes<D>& d) {
  return {v.i0, v.w, d.dw};
}
/// AxisWeights copied into the two records of the cache (D422), as a pair {values, slopes}.
template <int D> struct SplitRecords {
  AxisValues<D> values;
  AxisSlopes<D> slopes;
};
template <int D> SplitRecords<D> split(const AxisWeights<D>& aw) {
  SplitRecords<D> r;
  r.values.i0 = aw.i0;
  r.values.w = aw.w;
  r.slopes.dw = aw.dw;
  return r;
}

/// First node index per axis (`first`) and, for the three nodes k of each axis a, the offset
/// xi[3a + k] = x_a - X_k (m) and the half-length hl[3a + k] = l_a (m) that ugimp_weight takes.
/// Returns false if the support leaves the grid (a node index would fall outside [0, n_a)).
template <int D>
[[gnu::always_inline]] inline bool
axis_offsets(const Grid<D>& g, const Eigen::Matrix<double, D, 1>& x,
             const Eigen::Matrix<double, D, 1>& l, std::array<int, std::size_t{D}>& first,
             double* xi, double* hl) {
  for (int a = 0; a < D; ++a) {
    const double s = (x[a] - l[a] - g.origin[a]) / g.h;
    if (!(s >= 0.0)) return false; // also catches NaN
    int i0 = static_cast<int>(std::floor(s));
    if (i0 + 2 >= g.n[a]) {
      // A particle whose support ends exactly on the last node still fits.
      if (i0 + 1 == g.n[a] - 1 && x[a] + l[a] <= g.origin[a] + g.h * (g.n[a] - 1)) {
        i0 -= 1;
      } else {
        return false;
      }
    }
    first[a] = i0;
    for (int k = 0; k < 3; ++k) {
      xi[3 * a + k] = x[a] - (g.origin[a] + g.h * (i0 + k));
      hl[3 * a + k] = l[a];
    }
  }
  return true;
}

/// Computes the per-axis weights of a particle at x with half-lengths l (each 0 < l_a <= h/2)
/// through the branch-free ugimp_weights (D376; equal to ugimp_weight bit for bit).
/// Returns false if the support leaves the grid (a node index would fall outside [0, n_a)).
template <int D>
inline bool compute_axis_weights(const Grid<D>& g, const Eigen::Matrix<double, D, 1>& x,
                                 const Eigen::Matrix<double, D, 1>& l, AxisWeights<D>& aw) {
  double xi[3 * D], hl[3 * D];
  if (!axis_offsets(g, x, l, aw.i0, xi, hl)) return false;
  ugimp_weights(3 * D, xi, hl, g.h, &aw.w[0][0], &aw.dw[0][0]);
  return true;
}

/// compute_axis_weights of particles [0, n) (x, l, aw indexed alike) in chunks of 64 with one
/// branch-free weight loop per chunk: SIMD over particles and nodes (D376), the whole function
/// compiled for the baseline and for AVX2 with a run-time choice (D377, D407; same bits).
/// Returns the first particle whose support leaves the grid (its aw and the rest of its chunk
/// unset), or n. Defined for D = 2, 3 (weights_simd.cpp).
template <int D>
std::size_t compute_axis_weights_many(const Grid<D>& g, std::size_t n,
                                      const Eigen::Matrix<double, D, 1>* x,
                                      const Eigen::Matrix<double, D, 1>* l, AxisWeights<D>* aw);
/// The same weights written as split records (values with the first node indices, and the
/// derivatives; D422), bit for bit those of the overload above.
template <int D>
std::size_t compute_axis_weights_many(const Grid<D>& g, std::size_t n,
                                      const Eigen::Matrix<double, D, 1>* x,
                                      const Eigen::Matrix<double, D, 1>* l, AxisValues<D>* values,
                                      AxisSlopes<D>* slopes);

/// The 3^D stencil as the tensor product of per-axis weights: node indices and S, and grad S
/// when `kGradients` (without it st.dS is left as it was; D378). One loop for both, so node
/// and S are the same products in the same order either way (bit for bit).
/// (`aw`: AxisWeights<D> or SplitWeights<D>.)
template <bool kGradients, int D, class AW>
inline void assemble_stencil_parts(const Grid<D>& g, const AW& aw, Stencil<D>& st) {
  using Vec = Eigen::Matrix<double, D, 1>;
  const auto& w = aw.w; // (aw.dw is read only with kGradients: AxisValues has none)
  if constexpr (D == 2) {
    int c = 0;
    for (int j = 0; j < 3; ++j) {
      const std::int64_t row = static_cast<std::int64_t>(aw.i0[1] + j) * g.n[0] + aw.i0[0];
      for (int i = 0; i < 3; ++i, ++c) {
        st.node[c] = row + i;
        st.S[c] = w[0][i] * w[1][j];
        if constexpr (kGradients) st.dS[c] = Vec(aw.dw[0][i] * w[1][j], w[0][i] * aw.dw[1][j]);
      }
    }
  } else {
    int c = 0;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) {
        const std::int64_t row =
            (static_cast<std::int64_t>(aw.i0[2] + k) * g.n[1] + (aw.i0[1] + j)) * g.n[0] + aw.i0[0];
        const double wjk = w[1][j] * w[2][k];
        // the gradient's (j, k) factors once per row, not per node (unused without gradients)
        [[maybe_unused]] double djk = 0.0, jdk = 0.0;
        if constexpr (kGradients) {
          djk = aw.dw[1][j] * w[2][k];
          jdk = w[1][j] * aw.dw[2][k];
        }
        for (int i = 0; i < 3; ++i, ++c) {
          st.node[c] = row + i;
          st.S[c] = w[0][i] * wjk;
          if constexpr (kGradients) st.dS[c] = Vec(aw.dw[0][i] * wjk, w[0][i] * djk, w[0][i] * jdk);
        }
      }
  }
}

/// The 3^D stencil (node indices, S, grad S) as the tensor product of per-axis weights.
template <int D, template <int> class AW>
inline void assemble_stencil(const Grid<D>& g, const AW<D>& aw, Stencil<D>& st) {
  assemble_stencil_parts<true>(g, aw, st);
}

/// Fills `st` for a particle at x with half-lengths l (each 0 < l_a <= h/2). Returns false if
/// the support leaves the grid (a node index would fall outside [0, n_a)).
template <int D>
inline bool compute_stencil(const Grid<D>& g, const Eigen::Matrix<double, D, 1>& x,
                            const Eigen::Matrix<double, D, 1>& l, Stencil<D>& st) {
  AxisWeights<D> aw;
  if (!compute_axis_weights(g, x, l, aw)) return false;
  assemble_stencil(g, aw, st);
  return true;
}

} // namespace pnc::gimp
