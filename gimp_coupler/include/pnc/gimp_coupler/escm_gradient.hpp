#pragma once
// pnc/gimp_coupler/escm_gradient.hpp: displacement gradients of a set of particles (continuum
// material points and atoms alike) by the post-processing method of dissertation section 6.1,
// eqs. 6.3-6.7, with decision D79 (docs/decisions.md); docs/escm.md, "Displacement gradient".
//
// 2-D, SI: positions and spacing in m; gradients dimensionless. At every increment k -> k+1
// (positions x^k -> x^{k+1}, increment du_p = x_p^{k+1} - x_p^k):
//  1. a regular background grid of bilinear elements (node I at origin + spacing (i, j)) is
//     laid over the current positions x^k; N_pI is the bilinear shape function of node I at
//     particle p (non-zero for the four nodes of the element containing x_p^k);
//  2. nodal incremental displacement dU_I from the particles with N_pI > 0 (eqs. 6.3-6.4):
//     by default (D79) the weighted least-squares linear fit dU(x) = a + B (x - x_I), weights
//     N_pI, dU_I = a; it reproduces any affine increment exactly. The printed eq. 6.4
//     (sum N_pI du_p / count) and the shape-function-weighted mean (sum N du / sum N) are
//     available for comparison;
//  3. gradient of the increment at each particle, d(du)/dx = sum_I dU_I (dN_pI/dx)^T with the
//     derivatives at x_p^k (eq. 6.5);
//  4. F^{k+1} = (I + d(du)/dx) F^k (eq. 6.6; D79: the printed F^k (I + d(du)/dx) is the
//     transposed composition, equal only when the increments commute), H = F - I (eq. 6.7),
//     H_ij = du_i/dX_j.
// Header-only (inline) so that it needs no build-system change; cost O(particles) per
// increment.
#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace pnc::gimp::escm {

/// Nodal incremental displacement (eq. 6.4 and D79).
enum class NodalFit {
  linear,     ///< weighted linear least squares, weights N_pI (default; affine-exact)
  weight_sum, ///< sum N_pI du_p / sum N_pI (exact for a uniform increment only)
  count,      ///< sum N_pI du_p / M_I, M_I = number of particles with N_pI > 0 (printed 6.4)
};

class GradientTracker {
public:
  /// Background grid: nodes at origin + spacing (i, j), m; spacing > 0.
  GradientTracker(const Eigen::Vector2d& origin, double spacing, NodalFit fit = NodalFit::linear);

  /// Starts tracking: reference positions X (m), F = I. `contributes[p]` (empty: all true)
  /// says whether particle p enters the nodal fit; the others only receive gradients.
  void reset(const std::vector<Eigen::Vector2d>& X, const std::vector<char>& contributes = {});
  /// One increment to the positions x_new (m), same order and size as in reset().
  void update(const std::vector<Eigen::Vector2d>& x_new);

  /// Resume (checkpoints): after reset() with the same particles, the state after
  /// `increments` updates: current positions x, F and the support flags.
  void restore(const std::vector<Eigen::Vector2d>& x, const std::vector<Eigen::Matrix2d>& F,
               const std::vector<char>& supported, long increments) {
    if (x.size() != x_.size() || F.size() != x_.size() || supported.size() != x_.size())
      throw std::invalid_argument("GradientTracker::restore: sizes do not match reset()");
    x_ = x;
    F_ = F;
    supported_ = supported;
    increments_ = increments;
  }
  std::size_t size() const { return x_.size(); }
  long increments() const { return increments_; }
  double spacing() const { return h_; }
  const std::vector<Eigen::Matrix2d>& F() const { return F_; }
  /// Displacement gradient H = F - I of particle p: H(0,0) du/dX, H(0,1) du/dY, H(1,0) dv/dX,
  /// H(1,1) dv/dY.
  Eigen::Matrix2d H(std::size_t p) const { return F_[p] - Eigen::Matrix2d::Identity(); }
  /// 1 if, at every increment so far, all four nodes of the particle's element had a full
  /// fit (linear: >= 3 non-collinear contributing particles; otherwise >= 1), else 0.
  const std::vector<char>& supported() const { return supported_; }

private:
  Eigen::Vector2d origin_;
  double h_;
  NodalFit fit_;
  std::vector<Eigen::Vector2d> x_;
  std::vector<char> contributes_;
  std::vector<Eigen::Matrix2d> F_;
  std::vector<char> supported_;
  long increments_ = 0;
};

// ---- implementation ----

inline GradientTracker::GradientTracker(const Eigen::Vector2d& origin, double spacing, NodalFit fit)
    : origin_(origin), h_(spacing), fit_(fit) {
  if (!(spacing > 0) || !std::isfinite(spacing) || !origin.allFinite())
    throw std::invalid_argument("GradientTracker: spacing must be > 0 and finite (m), got " +
                                std::to_string(spacing));
}

inline void GradientTracker::reset(const std::vector<Eigen::Vector2d>& X,
                                   const std::vector<char>& contributes) {
  if (!contributes.empty() && contributes.size() != X.size())
    throw std::invalid_argument("GradientTracker::reset: contributes has " +
                                std::to_string(contributes.size()) + " entries for " +
                                std::to_string(X.size()) + " particles");
  x_ = X;
  contributes_ = contributes.empty() ? std::vector<char>(X.size(), 1) : contributes;
  F_.assign(X.size(), Eigen::Matrix2d::Identity());
  supported_.assign(X.size(), 1);
  increments_ = 0;
}

inline void GradientTracker::update(const std::vector<Eigen::Vector2d>& x_new) {
  const std::size_t n = x_.size();
  if (x_new.size() != n)
    throw std::invalid_argument("GradientTracker::update: " + std::to_string(x_new.size()) +
                                " positions for " + std::to_string(n) + " particles");
  if (n == 0) return;
  // Element of each particle in the current configuration x^k and the grid's index range.
  std::vector<std::array<long, 2>> el(n);
  std::vector<Eigen::Vector2d> xi(n); // local coordinates in [0, 1)
  long i0 = 0, i1 = 0, j0 = 0, j1 = 0;
  for (std::size_t p = 0; p < n; ++p) {
    if (!x_[p].allFinite() || !x_new[p].allFinite())
      throw std::runtime_error("GradientTracker::update: non-finite position of particle " +
                               std::to_string(p));
    const Eigen::Vector2d s = (x_[p] - origin_) / h_;
    el[p] = {static_cast<long>(std::floor(s[0])), static_cast<long>(std::floor(s[1]))};
    xi[p] =
        Eigen::Vector2d(s[0] - static_cast<double>(el[p][0]), s[1] - static_cast<double>(el[p][1]));
    if (p == 0) {
      i0 = i1 = el[p][0];
      j0 = j1 = el[p][1];
    }
    i0 = std::min(i0, el[p][0]);
    i1 = std::max(i1, el[p][0]);
    j0 = std::min(j0, el[p][1]);
    j1 = std::max(j1, el[p][1]);
  }
  const long nx = i1 - i0 + 2, ny = j1 - j0 + 2; // nodes
  const auto node = [&](long i, long j) {
    return static_cast<std::size_t>((j - j0) * nx + i - i0);
  };
  const std::size_t nn = static_cast<std::size_t>(nx * ny);
  std::vector<Eigen::Matrix3d> M(nn, Eigen::Matrix3d::Zero());
  std::vector<Eigen::Matrix<double, 3, 2>> R(nn, Eigen::Matrix<double, 3, 2>::Zero());
  std::vector<int> count(nn, 0);
  // The four nodes of an element: (a, b) offsets, shape function and its gradient (1/m).
  const auto shape = [&](const Eigen::Vector2d& q, int a, int b, double& N, Eigen::Vector2d& dN) {
    const double fx = a ? q[0] : 1 - q[0], fy = b ? q[1] : 1 - q[1];
    const double sx = a ? 1.0 : -1.0, sy = b ? 1.0 : -1.0;
    N = fx * fy;
    dN = Eigen::Vector2d(sx * fy, sy * fx) / h_;
  };
  // Eq. 6.3 (and the moments of the linear fit, D79).
  for (std::size_t p = 0; p < n; ++p) {
    if (!contributes_[p]) continue;
    const Eigen::Vector2d du = x_new[p] - x_[p];
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        double N;
        Eigen::Vector2d dN;
        shape(xi[p], a, b, N, dN);
        if (!(N > 0)) continue;
        const std::size_t I = node(el[p][0] + a, el[p][1] + b);
        // Position relative to the node in units of the spacing.
        const Eigen::Vector3d q(1.0, xi[p][0] - a, xi[p][1] - b);
        M[I] += N * q * q.transpose();
        R[I] += N * q * du.transpose();
        ++count[I];
      }
  }
  // Eq. 6.4 / D79: nodal increments and whether each node had a full fit.
  std::vector<Eigen::Vector2d> dU(nn, Eigen::Vector2d::Zero());
  std::vector<char> full(nn, 0);
  for (std::size_t I = 0; I < nn; ++I) {
    if (count[I] == 0) continue;
    const double wsum = M[I](0, 0);
    if (fit_ == NodalFit::count) {
      dU[I] = R[I].row(0).transpose() / count[I];
      full[I] = 1;
      continue;
    }
    dU[I] = R[I].row(0).transpose() / wsum;
    if (fit_ == NodalFit::weight_sum) {
      full[I] = 1;
      continue;
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M[I], Eigen::EigenvaluesOnly);
    const Eigen::Vector3d ev = es.eigenvalues();
    if (count[I] >= 3 && ev[0] > 1e-3 * ev[2]) {
      const Eigen::Matrix<double, 3, 2> c = M[I].ldlt().solve(R[I]);
      dU[I] = c.row(0).transpose();
      full[I] = 1;
    }
  }
  // Eqs. 6.5-6.7.
  for (std::size_t p = 0; p < n; ++p) {
    Eigen::Matrix2d L = Eigen::Matrix2d::Zero();
    bool ok = true;
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        double N;
        Eigen::Vector2d dN;
        shape(xi[p], a, b, N, dN);
        const std::size_t I = node(el[p][0] + a, el[p][1] + b);
        ok = ok && full[I];
        L += dU[I] * dN.transpose();
      }
    F_[p] = (Eigen::Matrix2d::Identity() + L) * F_[p];
    if (!ok) supported_[p] = 0;
  }
  x_ = x_new;
  ++increments_;
}

} // namespace pnc::gimp::escm
