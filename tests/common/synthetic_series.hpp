#pragma once
// Synthetic time series for the statistics tests (tests/md, tests/rve): AR(1) series with their
// exact variance of the mean, and the binomial band of a coverage count.
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

namespace pnc::test {

/// AR(1) x_t = phi x_{t-1} + e_t, started in its stationary distribution, Var(x) = 1.
inline std::vector<double> ar1(std::mt19937_64& g, std::size_t n, double phi) {
  std::normal_distribution<double> z(0.0, 1.0);
  std::vector<double> x(n);
  const double s = std::sqrt(1 - phi * phi);
  x[0] = z(g);
  for (std::size_t i = 1; i < n; ++i)
    x[i] = phi * x[i - 1] + s * z(g);
  return x;
}

/// Exact variance of the mean of m consecutive AR(1) samples with Var(x) = 1.
inline double ar1_var_mean(std::size_t m, double phi) {
  double s = 1;
  for (std::size_t t = 1; t < m; ++t)
    s += 2 * (1 - static_cast<double>(t) / static_cast<double>(m)) *
         std::pow(phi, static_cast<double>(t));
  return s / static_cast<double>(m);
}

/// Binomial band: |p_hat - p| <= 3 sqrt(p (1 - p) / n) fails for a calibrated interval with
/// probability 0.27 %.
inline double binomial_band(double p, int n) {
  return 3 * std::sqrt(p * (1 - p) / n);
}

} // namespace pnc::test
