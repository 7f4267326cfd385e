#pragma once
// Statistics of a least-squares fit (internal to pnc::damage): covariance estimators,
// goodness of fit, residual-structure tests and identifiability. Decision D11 says which is
// used when; docs/theory.md gives the formulas.
//
// Conventions: J is the Jacobian of the residual vector r with respect to the free parameters
// (rows = residuals, columns = parameters), both in the same units as the fit's residuals
// (standardised by the data's standard errors when those are known).
#include <Eigen/Dense>

#include <string>
#include <vector>

namespace pnc::damage::stats {

/// (J^T J)^-1: the covariance when r is standardised by correct, independent standard errors.
/// Returns false (cov untouched) when J^T J is numerically singular.
bool covariance_known_errors(const Eigen::MatrixXd& J, Eigen::MatrixXd& cov);

/// Heteroscedasticity-consistent "sandwich" covariance (HC3, MacKinnon & White 1985; the
/// small-sample choice of Long & Ervin 2000): (J^T J)^-1 J^T diag(r_i^2 / (1 - h_ii)^2) J
/// (J^T J)^-1 with the leverages h_ii of the hat matrix J (J^T J)^-1 J^T. HC2 (1 - h) and
/// HC0 under-cover with ~200 residuals and 22 constants (calibration test). Valid when the
/// point errors are unknown and unequal; needs independent residuals. Returns false when
/// J^T J is numerically singular.
bool covariance_sandwich(const Eigen::MatrixXd& J, const Eigen::VectorXd& r, Eigen::MatrixXd& cov);

/// Upper-tail probability P(X >= chi2) of a chi-square variable with `dof` degrees of freedom
/// (regularised incomplete gamma function Q(dof/2, chi2/2); series or continued fraction).
double chi2_upper_tail(double chi2, double dof);

/// Standard normal lower-tail probability Phi(z).
double normal_cdf(double z);

/// Wald-Wolfowitz runs test on the signs of a residual series in loading order (zeros are
/// dropped). Too few runs (long stretches of one sign) means the model misses a trend.
struct RunsTest {
  int n = 0;              ///< non-zero residuals
  int runs = 0;           ///< observed runs of one sign
  double expected = 0;    ///< expected runs for independent signs with these counts
  double z = 0;           ///< (runs - expected) / sd; NaN when undefined (n < 2 or one sign)
  double p_too_few = 1.0; ///< one-sided lower-tail probability Phi(z)
  double lag1 = 0;        ///< lag-1 autocorrelation of the residuals (about zero), NaN if n < 3
};
RunsTest runs_test(const std::vector<double>& r);

/// Parameters the data do not determine: a column of J that is zero (to rounding, relative
/// to the largest column), or a direction of the column-scaled J^T J whose singular value is
/// below `rel_tol` of the largest (then every parameter with weight > 0.2 in that direction).
/// `reason[j]` says why (empty for identified ones).
std::vector<bool> not_identified(const Eigen::MatrixXd& J, std::vector<std::string>& reason,
                                 const std::vector<std::string>& names, double rel_tol = 1e-8);

} // namespace pnc::damage::stats
