#pragma once
// pnc/thermo/analysis.hpp: the numerics of thermodynamic integration and of the bending
// analysis -- quadrature rules on an interval, propagation of standard errors through them,
// block-averaged standard errors, free-energy perturbation, weighted straight-line and
// quadratic fits with confidence intervals. No LAMMPS here (pure functions, unit-tested).
//
// Units: whatever the caller passes (thermo/ uses LAMMPS `real`: kcal/mol, A, fs, K).
#include <string>
#include <vector>

namespace pnc::thermo {

/// Nodes and weights of a quadrature rule on [a, b] (sum of weights = b - a).
struct Quadrature {
  std::string name; ///< "gauss" or "trapezoid"
  std::vector<double> nodes, weights;
};

/// n-point Gauss-Legendre on [a, b] (n = 1..64), nodes ascending. n = 3 on [0, 1] is the
/// dissertation's Table 6.1 (nodes 0.5 -+ sqrt(15)/10, weights 5/18, 8/18, 5/18; the
/// table's 0.113/0.887 and 0.556/0.889 (x 1/2) are these rounded, decision D61).
Quadrature gauss_legendre(int n, double a = 0.0, double b = 1.0);
/// Composite trapezoid with n >= 2 equally spaced nodes including both ends.
Quadrature trapezoid(int n, double a = 0.0, double b = 1.0);
/// "gauss" or "trapezoid" with n points; throws InputError (source, field "rule") otherwise.
Quadrature make_rule(const std::string& rule, int n, const std::string& source);

struct Estimate {
  double value = 0;
  double se = 0; ///< one standard error
};

/// sum_i w_i m_i with standard error sqrt(sum_i w_i^2 se_i^2) (independent points).
Estimate integrate(const Quadrature& q, const std::vector<double>& means,
                   const std::vector<double>& stderrs);

/// Mean and standard error of a correlated series by block averaging: `blocks` contiguous
/// blocks of equal length (trailing remainder only in the mean), se = sd(block means)/sqrt(nb).
Estimate block_mean(const std::vector<double>& x, int blocks);

/// Free-energy perturbation A(b) - A(a) = -kT ln < exp(-du/kT) >_a from samples of
/// du = U_b - U_a taken in ensemble a; the standard error by block averaging of the
/// exponential average and the delta method (se = kT se(<e>) / <e>). Shifted by min(du) for
/// numerical safety.
Estimate fep(const std::vector<double>& du, double kT, int blocks);

/// Weighted least-squares polynomial fit y = c0 + c1 x (+ c2 x^2 when degree 2); weights
/// 1/sy^2 (all ones when sy is empty). Covariance scaled by the reduced chi^2 when
/// `scale_by_chi2` (and dof > 0), i.e. errors from the scatter about the fit.
struct PolyFit {
  std::vector<double> c;  ///< coefficients c0, c1[, c2]
  std::vector<double> se; ///< their standard errors
  double chi2_reduced = 0;
  int dof = 0;
};
PolyFit polyfit(const std::vector<double>& x, const std::vector<double>& y,
                const std::vector<double>& sy, int degree, bool scale_by_chi2);

/// Two-sided 95 % quantile of Student's t with `dof` degrees of freedom (1.96 for dof > 30).
double t95(int dof);

/// Least-squares slope of y against x with intercept, and its standard error for a
/// time-correlated series: the slope error is sum_i c_i r_i (c_i = (x_i - mean x)/Sxx,
/// r the residuals); its variance is estimated from the sums over `blocks` (>= 3)
/// contiguous blocks, var = nb/(nb-2) sum_b B_b^2.
Estimate block_slope(const std::vector<double>& x, const std::vector<double>& y, int blocks);

/// Ratio of the slopes of yn and yd against x (e.g. dF/da / dd/da = dF/dd with a noise-free
/// regressor a, which avoids the errors-in-variables bias of regressing F on a noisy d),
/// with a block standard error by the delta method over the same residual block sums.
Estimate block_slope_ratio(const std::vector<double>& x, const std::vector<double>& yn,
                           const std::vector<double>& yd, int blocks);

} // namespace pnc::thermo
