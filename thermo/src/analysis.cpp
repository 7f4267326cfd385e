// Quadrature, block averages, FEP and fits for thermo/ (no LAMMPS).
#include "pnc/thermo/analysis.hpp"

#include "pnc/core/error.hpp"
#include "pnc/md/statistics.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace pnc::thermo {

Quadrature gauss_legendre(int n, double a, double b) {
  if (n < 1 || n > 64) fail("<quadrature>", "points", std::to_string(n), "must be in 1..64");
  Quadrature q;
  q.name = "gauss";
  q.nodes.resize(n);
  q.weights.resize(n);
  const double pi = std::acos(-1.0);
  for (int i = 0; i < n; ++i) {
    // Newton on P_n from the Chebyshev-like first guess; roots of P_n on [-1, 1]
    double x = std::cos(pi * (i + 0.75) / (n + 0.5));
    double dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) {
        p1 = x;
        p0 = 1;
      }
      dp = n * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::fabs(dx) < 1e-16) break;
    }
    // recompute the derivative at the converged root
    double p0 = 1, p1 = x;
    for (int k = 2; k <= n; ++k) {
      const double p2 = ((2.0 * k - 1) * x * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    dp = n == 1 ? 1.0 : n * (x * p1 - p0) / (x * x - 1);
    const double w = 2.0 / ((1 - x * x) * dp * dp);
    // roots come out descending in x: store ascending
    q.nodes[n - 1 - i] = 0.5 * (a + b) + 0.5 * (b - a) * x;
    q.weights[n - 1 - i] = 0.5 * (b - a) * w;
  }
  return q;
}

Quadrature trapezoid(int n, double a, double b) {
  if (n < 2) fail("<quadrature>", "points", std::to_string(n), "trapezoid needs >= 2 points");
  Quadrature q;
  q.name = "trapezoid";
  const double h = (b - a) / (n - 1);
  for (int i = 0; i < n; ++i) {
    q.nodes.push_back(a + h * i);
    q.weights.push_back((i == 0 || i == n - 1) ? 0.5 * h : h);
  }
  return q;
}

Quadrature make_rule(const std::string& rule, int n, const std::string& source) {
  if (rule == "gauss") return gauss_legendre(n);
  if (rule == "trapezoid") return trapezoid(n);
  fail(source, "rule", rule, "must be \"gauss\" or \"trapezoid\"");
}

Estimate integrate(const Quadrature& q, const std::vector<double>& means,
                   const std::vector<double>& stderrs) {
  if (means.size() != q.nodes.size() || stderrs.size() != q.nodes.size())
    fail("<quadrature>", "values",
         fmt::format("{} values for {} nodes", means.size(), q.nodes.size()),
         "one mean and one standard error per node");
  Estimate e;
  double v = 0;
  for (std::size_t i = 0; i < means.size(); ++i) {
    e.value += q.weights[i] * means[i];
    v += q.weights[i] * q.weights[i] * stderrs[i] * stderrs[i];
  }
  e.se = std::sqrt(v);
  return e;
}

Estimate block_mean(const std::vector<double>& x, int blocks) {
  if (x.empty()) fail("<block average>", "samples", "0", "needs at least one sample");
  // the same estimator as the deformation driver's stress points (NaN s.e. below 2 blocks)
  const auto [mean, se] = md::block_mean_se(x, std::max(blocks, 0));
  Estimate e;
  e.value = mean;
  e.se = se;
  return e;
}

Estimate fep(const std::vector<double>& du, double kT, int blocks) {
  if (du.empty()) fail("<fep>", "samples", "0", "needs at least one sample");
  const double shift = *std::min_element(du.begin(), du.end());
  std::vector<double> w(du.size());
  for (std::size_t i = 0; i < du.size(); ++i)
    w[i] = std::exp(-(du[i] - shift) / kT);
  const Estimate m = block_mean(w, blocks);
  Estimate e;
  e.value = shift - kT * std::log(m.value);
  e.se = kT * m.se / m.value;
  return e;
}

PolyFit polyfit(const std::vector<double>& x, const std::vector<double>& y,
                const std::vector<double>& sy, int degree, bool scale_by_chi2) {
  const int n = static_cast<int>(x.size());
  const int p = degree + 1;
  if (degree < 1 || degree > 2) fail("<fit>", "degree", std::to_string(degree), "must be 1 or 2");
  if (static_cast<int>(y.size()) != n || (!sy.empty() && static_cast<int>(sy.size()) != n))
    fail("<fit>", "data", "", "x, y (and sy) must have the same length");
  if (n < p)
    fail("<fit>", "points", std::to_string(n), fmt::format("need >= {} for degree {}", p, degree));
  Eigen::MatrixXd A(n, p);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    const double w = sy.empty() ? 1.0 : 1.0 / sy[i];
    if (!std::isfinite(w) || w <= 0)
      fail("<fit>", "sy", fmt::format("{}", sy[i]), "standard errors must be finite and > 0");
    for (int j = 0; j < p; ++j)
      A(i, j) = w * std::pow(x[i], j);
    b(i) = w * y[i];
  }
  const Eigen::MatrixXd AtA = A.transpose() * A;
  const Eigen::VectorXd c = AtA.ldlt().solve(A.transpose() * b);
  Eigen::MatrixXd cov = AtA.inverse();
  PolyFit f;
  f.dof = n - p;
  const double chi2 = (A * c - b).squaredNorm();
  f.chi2_reduced = f.dof > 0 ? chi2 / f.dof : std::nan("");
  if (scale_by_chi2 && f.dof > 0) cov *= f.chi2_reduced;
  for (int j = 0; j < p; ++j) {
    f.c.push_back(c(j));
    f.se.push_back(std::sqrt(cov(j, j)));
  }
  return f;
}

double t95(int dof) {
  static const double t[30] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306,
                               2.262,  2.228, 2.201, 2.179, 2.160, 2.145, 2.131, 2.120,
                               2.110,  2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064,
                               2.060,  2.056, 2.052, 2.048, 2.045, 2.042};
  if (dof < 1) return std::nan("");
  return dof <= 30 ? t[dof - 1] : 1.96;
}

namespace {
/// Standard error of a least-squares slope from residual-like terms r_i: the slope error is
/// sum_i c_i r_i with c_i = (x_i - mean x)/Sxx; the sums of c_i r_i over `blocks` contiguous
/// blocks longer than the correlation time are independent, so var = nb/(nb-2) sum_b B_b^2
/// (two fitted parameters). NaN with fewer than 3 blocks (at most n/2 blocks).
double blocked_slope_se(const std::vector<double>& x, double mx, double sxx,
                        const std::vector<double>& r, int blocks) {
  const std::size_t n = x.size();
  const std::size_t nb =
      std::min<std::size_t>(static_cast<std::size_t>(std::max(blocks, 0)), n / 2);
  if (nb < 3) return std::nan("");
  const std::size_t per = n / nb;
  double v = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    const std::size_t end = b + 1 == nb ? n : (b + 1) * per;
    double B = 0;
    for (std::size_t i = b * per; i < end; ++i)
      B += (x[i] - mx) / sxx * r[i];
    v += B * B;
  }
  return std::sqrt(v * static_cast<double>(nb) / static_cast<double>(nb - 2));
}
} // namespace

Estimate block_slope(const std::vector<double>& x, const std::vector<double>& y, int blocks) {
  const std::size_t n = x.size();
  if (y.size() != n || n < 4)
    fail("<slope>", "samples", std::to_string(n), "need >= 4 (x, y) pairs");
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
  }
  if (!(sxx > 0)) fail("<slope>", "x", "", "all x equal: no slope");
  Estimate e;
  e.value = sxy / sxx;
  const double c0 = my - e.value * mx;
  std::vector<double> r(n);
  for (std::size_t i = 0; i < n; ++i)
    r[i] = y[i] - c0 - e.value * x[i];
  e.se = blocked_slope_se(x, mx, sxx, r, blocks);
  return e;
}

Estimate block_slope_ratio(const std::vector<double>& x, const std::vector<double>& yn,
                           const std::vector<double>& yd, int blocks) {
  const std::size_t n = x.size();
  if (yn.size() != n || yd.size() != n || n < 6)
    fail("<slope ratio>", "samples", std::to_string(n), "need >= 6 samples of equal length");
  double mx = 0;
  for (double v : x)
    mx += v;
  mx /= static_cast<double>(n);
  double sxx = 0;
  for (double v : x)
    sxx += (v - mx) * (v - mx);
  if (!(sxx > 0)) fail("<slope ratio>", "x", "", "all x equal: no slope");
  auto fit = [&](const std::vector<double>& y, double& c0, double& c1) {
    double my = 0, sxy = 0;
    for (double v : y)
      my += v;
    my /= static_cast<double>(n);
    for (std::size_t i = 0; i < n; ++i)
      sxy += (x[i] - mx) * (y[i] - my);
    c1 = sxy / sxx;
    c0 = my - c1 * mx;
  };
  double an, bn, ad, bd;
  fit(yn, an, bn);
  fit(yd, ad, bd);
  Estimate e;
  e.value = bn / bd;
  // error of bn/bd ~ (dbn - R dbd)/bd, dbn = sum c_i rn_i etc.
  std::vector<double> r(n);
  for (std::size_t i = 0; i < n; ++i)
    r[i] = (yn[i] - an - bn * x[i]) - e.value * (yd[i] - ad - bd * x[i]);
  e.se = blocked_slope_se(x, mx, sxx, r, blocks) / std::fabs(bd);
  return e;
}

} // namespace pnc::thermo
