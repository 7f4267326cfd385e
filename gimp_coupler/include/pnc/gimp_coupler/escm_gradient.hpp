#pragma once
// pnc/gimp_coupler/escm_gradient.hpp: displacement gradients of a set of particles (continuum
// material points and atoms alike) by the source's post-processing method,
// docs/theory.md §6.3, with decision D79 (docs/decisions.md); docs/escm.md, "Displacement
// gradient".
//
// 2-D, SI: positions and spacing in m; gradients dimensionless. At every increment k -> k+1
// (positions x^k -> x^{k+1}, increment du_p = x_p^{k+1} - x_p^k):
//  1. a regular background grid of bilinear elements (node I at origin + spacing (i, j)) is
//     laid over the current positions x^k; N_pI is the bilinear shape function of node I at
//     particle p (non-zero for the four nodes of the element containing x_p^k);
//  2. nodal incremental displacement dU_I from the particles with N_pI > 0 (docs/theory.md §6.3):
//     by default (D79) the weighted least-squares linear fit dU(x) = a + B (x - x_I), weights
//     N_pI, dU_I = a; it reproduces any affine increment exactly. The source's printed nodal
//     average (sum N_pI du_p / count) and the shape-function-weighted mean (sum N du / sum N) are
//     available for comparison;
//  3. gradient of the increment at each particle, d(du)/dx = sum_I dU_I (dN_pI/dx)^T with the
//     derivatives at x_p^k (docs/theory.md §6.3);
//  4. F^{k+1} = (I + d(du)/dx) F^k (docs/theory.md §6.3; D79: the printed F^k (I + d(du)/dx) is the
//     transposed composition, equal only when the increments commute), H = F - I (§6.3),
//     H_ij = du_i/dX_j.
// Cost O(particles) per increment. Implementation: src/escm_gradient.cpp.
#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace pnc::gimp::escm {

/// Nodal incremental displacement (docs/theory.md §6.3 and D79).
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
               const std::vector<char>& supported, long increments);
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

} // namespace pnc::gimp::escm
