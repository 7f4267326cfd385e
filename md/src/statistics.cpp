// Error estimates of the deformation data (statistics.hpp; decisions D130-D134).
#include "pnc/md/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <tuple>

namespace pnc::md {

namespace {
double mean_of(const std::vector<double>& x) {
  double m = 0;
  for (double v : x)
    m += v;
  return x.empty() ? std::nan("") : m / static_cast<double>(x.size());
}
} // namespace

AutocorrelationTime integrated_autocorrelation_time(const std::vector<double>& x, double c) {
  AutocorrelationTime out;
  const std::size_t n = x.size();
  if (n < 2) {
    out.resolved = false;
    return out;
  }
  const double m = mean_of(x);
  double c0 = 0;
  for (double v : x)
    c0 += (v - m) * (v - m);
  c0 /= static_cast<double>(n);
  if (!(c0 > 0)) return out; // constant series: no correlation to measure
  const std::size_t wmax = std::max<std::size_t>(1, n / 4);
  double tau = 0.5;
  for (std::size_t w = 1; w <= wmax; ++w) {
    double ct = 0;
    for (std::size_t i = 0; i + w < n; ++i)
      ct += (x[i] - m) * (x[i + w] - m);
    tau += ct / static_cast<double>(n) / c0;
    out.window = static_cast<int>(w);
    if (static_cast<double>(w) >= c * tau) {
      out.tau_int = std::max(0.5, tau);
      return out;
    }
  }
  out.tau_int = std::max(0.5, tau);
  out.resolved = false;
  return out;
}

std::pair<double, double> block_mean_se(const std::vector<double>& x, int blocks) {
  const std::size_t n = x.size();
  const double mean = mean_of(x);
  const std::size_t nb = std::min<std::size_t>(static_cast<std::size_t>(std::max(blocks, 0)), n);
  if (nb < 2) return {mean, std::nan("")};
  const std::size_t per = n / nb; // trailing remainder samples only enter the mean
  std::vector<double> bm(nb, 0.0);
  for (std::size_t b = 0; b < nb; ++b) {
    for (std::size_t i = 0; i < per; ++i)
      bm[b] += x[b * per + i];
    bm[b] /= static_cast<double>(per);
  }
  const double mb = mean_of(bm);
  double vb = 0;
  for (double v : bm)
    vb += (v - mb) * (v - mb);
  vb /= static_cast<double>(nb - 1);
  return {mean, std::sqrt(vb / static_cast<double>(nb))};
}

HoldEstimate checked_block_se(const std::vector<double>& x, int blocks) {
  HoldEstimate h;
  const std::size_t n = x.size();
  std::tie(h.mean, h.se_block) = block_mean_se(x, blocks);
  if (blocks < 2 || n < 2) {
    h.se = h.se_tau = std::nan("");
    h.blocks_ok = false;
    return h;
  }
  double vx = 0;
  for (double v : x)
    vx += (v - h.mean) * (v - h.mean);
  vx /= static_cast<double>(n - 1);
  const AutocorrelationTime a = integrated_autocorrelation_time(x);
  const std::size_t per =
      n / static_cast<std::size_t>(
              blocks < 0
                  ? 0
                  : std::min<std::size_t>(static_cast<std::size_t>(blocks), n)); // block length
  h.tau_int = a.tau_int;
  const double g = 2.0 * a.tau_int;
  h.se_tau = std::sqrt(g * vx / static_cast<double>(n));
  // decision D132: block errors only from blocks much longer than the correlation time
  h.blocks_ok = a.resolved && static_cast<double>(per) >= kMinBlockOverInefficiency * g;
  h.se = h.blocks_ok ? h.se_block : std::max(h.se_block, h.se_tau);
  return h;
}

ReplicaEstimate replica_mean_se(const std::vector<double>& values) {
  ReplicaEstimate r;
  r.n = static_cast<int>(values.size());
  r.mean = mean_of(values);
  if (r.n < 2) {
    r.sd = r.se = std::nan("");
    return r;
  }
  double v = 0;
  for (double x : values)
    v += (x - r.mean) * (x - r.mean);
  r.sd = std::sqrt(v / (r.n - 1));
  r.se = r.sd / std::sqrt(static_cast<double>(r.n));
  return r;
}

double student_t_cdf(double t, int dof) {
  if (dof < 1) throw std::invalid_argument("student_t_cdf: dof must be >= 1");
  if (!std::isfinite(t)) return t > 0 ? 1.0 : 0.0;
  const double nu = dof, a = std::fabs(t);
  const double lnc =
      std::lgamma(0.5 * (nu + 1)) - std::lgamma(0.5 * nu) - 0.5 * std::log(nu * M_PI);
  auto pdf = [&](double x) { return std::exp(lnc - 0.5 * (nu + 1) * std::log1p(x * x / nu)); };
  // Simpson on [0, |t|]; the integrand is smooth and bounded, 4000 panels give ~1e-12
  const int m = 4000;
  const double h = a / m;
  double s = pdf(0) + pdf(a);
  for (int i = 1; i < m; ++i)
    s += (i % 2 ? 4.0 : 2.0) * pdf(i * h);
  const double half = s * h / 3.0;
  return t >= 0 ? 0.5 + half : 0.5 - half;
}

double coverage_factor(int dof, double coverage) {
  if (!(coverage > 0 && coverage < 1))
    throw std::invalid_argument("coverage_factor: coverage must be in (0, 1)");
  // memoised: the bisection costs ~1e5 density evaluations and callers ask for few (dof, p)
  static std::mutex mu;
  static std::map<std::pair<int, double>, double> cache;
  const std::lock_guard<std::mutex> lock(mu);
  if (const auto it = cache.find({dof, coverage}); it != cache.end()) return it->second;
  const double target = 0.5 + 0.5 * coverage;
  double lo = 0, hi = 1;
  while (student_t_cdf(hi, dof) < target)
    hi *= 2;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (student_t_cdf(mid, dof) < target ? lo : hi) = mid;
  }
  return cache[{dof, coverage}] = 0.5 * (lo + hi);
}

SlopeFit slope_through_origin(const Eigen::VectorXd& t, const Eigen::VectorXd& y,
                              const Eigen::VectorXd& se, double se_common) {
  if (t.size() != y.size() || (se.size() != 0 && se.size() != t.size()) || t.size() < 1)
    throw std::invalid_argument("slope_through_origin: t, y (and se) must have one size >= 1");
  double swt2 = 0, swty = 0, swt = 0, swt2s2 = 0;
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    const double w = se.size() ? 1.0 / (se[k] * se[k]) : 1.0;
    swt2 += w * t[k] * t[k];
    swty += w * t[k] * y[k];
    swt += w * t[k];
    if (se.size()) swt2s2 += w * w * t[k] * t[k] * se[k] * se[k];
  }
  if (!(swt2 > 0)) throw std::invalid_argument("slope_through_origin: all strains are zero");
  SlopeFit f;
  f.slope = swty / swt2;
  // var(b) = sum w^2 t^2 se^2 / (sum w t^2)^2 (= 1 / sum w t^2 with w = 1/se^2); no per-point
  // errors given: the residual scatter estimates them (n >= 2)
  if (se.size()) {
    f.se_independent = std::sqrt(swt2s2) / swt2;
  } else if (t.size() >= 2) {
    double rss = 0;
    for (Eigen::Index k = 0; k < t.size(); ++k)
      rss += std::pow(y[k] - f.slope * t[k], 2);
    f.se_independent = std::sqrt(rss / static_cast<double>(t.size() - 1) / swt2);
  } else {
    f.se_independent = std::numeric_limits<double>::quiet_NaN();
  }
  f.se_common = std::fabs(swt / swt2) * se_common;
  f.se = std::hypot(f.se_independent, f.se_common);
  return f;
}

} // namespace pnc::md
