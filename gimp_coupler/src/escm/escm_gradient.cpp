// Displacement gradients by docs/theory.md §6.3 (pnc/gimp_coupler/escm_gradient.hpp, D79).
#include "pnc/gimp_coupler/escm_gradient.hpp"
#include "pnc/core/error.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pnc::gimp::escm {

GradientTracker::GradientTracker(const Eigen::Vector2d& origin, double spacing, NodalFit fit)
    : origin_(origin), h_(spacing), fit_(fit) {
  if (!(spacing > 0) || !std::isfinite(spacing) || !origin.allFinite())
    throw std::invalid_argument("GradientTracker: spacing must be > 0 and finite (m), got " +
                                std::to_string(spacing));
}

void GradientTracker::reset(const std::vector<Eigen::Vector2d>& X,
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

void GradientTracker::restore(const std::vector<Eigen::Vector2d>& x,
                              const std::vector<Eigen::Matrix2d>& F,
                              const std::vector<char>& supported, long increments) {
  if (x.size() != x_.size() || F.size() != x_.size() || supported.size() != x_.size())
    throw std::invalid_argument("GradientTracker::restore: sizes do not match reset()");
  x_ = x;
  F_ = F;
  supported_ = supported;
  increments_ = increments;
}

void GradientTracker::update(const std::vector<Eigen::Vector2d>& x_new) {
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
      pnc::fail_simulation("escm: particle " + std::to_string(p), -1,
                           std::numeric_limits<double>::quiet_NaN(), "",
                           "non-finite position in the deformation-gradient update");
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
  // Particle increments (docs/theory.md §6.3) and the moments of the linear fit (D79).
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
  // docs/theory.md §6.3 / D79: nodal increments and whether each node had a full fit.
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
  // docs/theory.md §6.3: gradient, F update, H = F - I.
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
