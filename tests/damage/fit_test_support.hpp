#pragma once
// Shared helpers of the NDM fit tests (test_fit.cpp, test_fit_pooled.cpp,
// test_fit_isotropic.cpp). Internal to the tests.
#include "pnc/damage/fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

namespace pnc_fit_test {

using namespace pnc::damage;

/// The constants as the fit's theta map takes them: MPa, alpha dimensionless.
inline std::vector<double> constants_mpa(const NdmParameters& p) {
  std::vector<double> k(p.size());
  for (std::size_t i = 0; i < k.size(); ++i)
    k[i] = i + 1 == k.size() ? p.k[i] : p.k[i] / 1e6;
  return k;
}

/// Central differences of detail::residuals_and_jacobian's residuals in every theta
/// (step 1e-5 (1 + |theta_j|)): the reference for the analytic Jacobian.
inline Eigen::MatrixXd central_difference_jacobian(const StressStrainData& d, Model m,
                                                   const std::vector<double>& th,
                                                   const std::vector<int>& tied = {}) {
  Eigen::MatrixXd fd;
  for (std::size_t j = 0; j < th.size(); ++j) {
    auto tp = th, tm = th;
    const double h = 1e-5 * (1 + std::abs(th[j]));
    tp[j] += h;
    tm[j] -= h;
    Eigen::VectorXd rp, rm;
    detail::residuals_and_jacobian(d, m, tp, rp, nullptr, tied);
    detail::residuals_and_jacobian(d, m, tm, rm, nullptr, tied);
    if (j == 0) fd.resize(rp.size(), static_cast<Eigen::Index>(th.size()));
    fd.col(static_cast<Eigen::Index>(j)) = (rp - rm) / (2 * h);
  }
  return fd;
}

/// Monte-Carlo one-sigma coverage: for `n` data sets made by `data(seed_i)`, the fraction of
/// fits per constant with |k - truth| <= its standard error. Every fit must converge.
inline std::vector<double> one_sigma_coverage(const std::function<StressStrainData(int)>& data,
                                              const FitOptions& o, const NdmParameters& truth,
                                              int n) {
  std::vector<int> covered(truth.size(), 0);
  for (int s = 0; s < n; ++s) {
    const FitReport r = fit_ndm(data(s), o);
    EXPECT_TRUE(r.converged) << r.message;
    for (std::size_t i = 0; i < truth.size(); ++i)
      covered[i] += std::abs(r.params.k[i] - truth.k[i]) <= r.std_error[i];
  }
  std::vector<double> out(truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i)
    out[i] = static_cast<double>(covered[i]) / n;
  return out;
}

} // namespace pnc_fit_test
