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
#include <Eigen/Core>

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
};

/// Computes the per-axis weights of a particle at x with half-lengths l (each 0 < l_a <= h/2).
/// Returns false if the support leaves the grid (a node index would fall outside [0, n_a)).
template <int D>
inline bool compute_axis_weights(const Grid<D>& g, const Eigen::Matrix<double, D, 1>& x,
                                 const Eigen::Matrix<double, D, 1>& l, AxisWeights<D>& aw) {
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
    aw.i0[a] = i0;
    for (int k = 0; k < 3; ++k) {
      const double xi = x[a] - (g.origin[a] + g.h * (i0 + k));
      const Weight1D r = ugimp_weight(xi, g.h, l[a]);
      aw.w[a][k] = r.S;
      aw.dw[a][k] = r.dS;
    }
  }
  return true;
}

/// The 3^D stencil (node indices, S, grad S) as the tensor product of per-axis weights.
template <int D>
inline void assemble_stencil(const Grid<D>& g, const AxisWeights<D>& aw, Stencil<D>& st) {
  using Vec = Eigen::Matrix<double, D, 1>;
  const auto& w = aw.w;
  const auto& dw = aw.dw;
  if constexpr (D == 2) {
    int c = 0;
    for (int j = 0; j < 3; ++j) {
      const std::int64_t row = static_cast<std::int64_t>(aw.i0[1] + j) * g.n[0] + aw.i0[0];
      for (int i = 0; i < 3; ++i, ++c) {
        st.node[c] = row + i;
        st.S[c] = w[0][i] * w[1][j];
        st.dS[c] = Vec(dw[0][i] * w[1][j], w[0][i] * dw[1][j]);
      }
    }
  } else {
    int c = 0;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) {
        const std::int64_t row =
            (static_cast<std::int64_t>(aw.i0[2] + k) * g.n[1] + (aw.i0[1] + j)) * g.n[0] + aw.i0[0];
        const double wjk = w[1][j] * w[2][k], djk = dw[1][j] * w[2][k], jdk = w[1][j] * dw[2][k];
        for (int i = 0; i < 3; ++i, ++c) {
          st.node[c] = row + i;
          st.S[c] = w[0][i] * wjk;
          st.dS[c] = Vec(dw[0][i] * wjk, w[0][i] * djk, w[0][i] * jdk);
        }
      }
  }
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
