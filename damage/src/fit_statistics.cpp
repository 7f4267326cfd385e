// Statistics of a least-squares fit: see fit_statistics.hpp and docs/decisions.md D11.
#include "fit_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pnc::damage::stats {

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();

// Inverse of J^T J by a rank-revealing decomposition; false when numerically singular.
bool inverse_normal_matrix(const Eigen::MatrixXd& J, Eigen::MatrixXd& inv) {
  const Eigen::MatrixXd JtJ = J.transpose() * J;
  if (JtJ.rows() == 0) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(JtJ);
  const double emax = es.eigenvalues().maxCoeff(), emin = es.eigenvalues().minCoeff();
  if (!(emax > 0) || !(emin > emax * 1e-14)) return false;
  inv = es.eigenvectors() * es.eigenvalues().cwiseInverse().asDiagonal() *
        es.eigenvectors().transpose();
  return true;
}

// Regularised lower incomplete gamma P(a, x) by its series (x < a + 1).
double gamma_p_series(double a, double x) {
  double sum = 1.0 / a, del = sum, ap = a;
  for (int n = 0; n < 10000; ++n) {
    ap += 1.0;
    del *= x / ap;
    sum += del;
    if (std::abs(del) < std::abs(sum) * 1e-16) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}
// Regularised upper incomplete gamma Q(a, x) by its continued fraction (x >= a + 1; Lentz).
double gamma_q_fraction(double a, double x) {
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-16) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}
} // namespace

bool covariance_known_errors(const Eigen::MatrixXd& J, Eigen::MatrixXd& cov) {
  return inverse_normal_matrix(J, cov);
}

bool covariance_sandwich(const Eigen::MatrixXd& J, const Eigen::VectorXd& r, Eigen::MatrixXd& cov) {
  Eigen::MatrixXd inv;
  if (!inverse_normal_matrix(J, inv)) return false;
  // Leverages h_ii = J_i (J^T J)^-1 J_i^T; HC3 weights r_i^2 / (1 - h_ii)^2.
  const Eigen::MatrixXd JI = J * inv;
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(J.cols(), J.cols());
  for (Eigen::Index i = 0; i < J.rows(); ++i) {
    const double h = std::min(JI.row(i).dot(J.row(i)), 1.0 - 1e-12);
    const double w2 = r[i] * r[i] / ((1.0 - h) * (1.0 - h));
    meat.noalias() += w2 * J.row(i).transpose() * J.row(i);
  }
  cov = inv * meat * inv;
  return true;
}

double chi2_upper_tail(double chi2, double dof) {
  if (!(dof > 0) || !(chi2 >= 0)) return kNaN;
  if (chi2 == 0) return 1.0;
  const double a = 0.5 * dof, x = 0.5 * chi2;
  return x < a + 1.0 ? 1.0 - gamma_p_series(a, x) : gamma_q_fraction(a, x);
}

double normal_cdf(double z) {
  return 0.5 * std::erfc(-z / std::sqrt(2.0));
}

RunsTest runs_test(const std::vector<double>& r) {
  RunsTest t;
  std::vector<int> sign;
  for (double v : r)
    if (v != 0.0 && std::isfinite(v)) sign.push_back(v > 0 ? 1 : -1);
  t.n = static_cast<int>(sign.size());
  const double np = static_cast<double>(std::count(sign.begin(), sign.end(), 1));
  const double nm = t.n - np, n = t.n;
  t.runs = t.n > 0 ? 1 : 0;
  for (std::size_t i = 1; i < sign.size(); ++i)
    if (sign[i] != sign[i - 1]) ++t.runs;
  t.lag1 = kNaN;
  if (r.size() >= 3) {
    double num = 0, den = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      den += r[i] * r[i];
      if (i > 0) num += r[i] * r[i - 1];
    }
    t.lag1 = den > 0 ? num / den : kNaN;
  }
  if (t.n < 2 || np == 0 || nm == 0) {
    t.z = kNaN;
    t.expected = t.n > 0 ? 1 : 0;
    // every residual of one sign: P = 2 * 0.5^n for independent fair signs
    t.p_too_few = t.n >= 2 ? std::pow(0.5, t.n - 1) : 1.0;
    return t;
  }
  t.expected = 2 * np * nm / n + 1;
  const double var = (t.expected - 1) * (t.expected - 2) / (n - 1);
  t.z = var > 0 ? (t.runs - t.expected) / std::sqrt(var) : kNaN;
  t.p_too_few = std::isfinite(t.z) ? normal_cdf(t.z) : 1.0;
  return t;
}

std::vector<bool> not_identified(const Eigen::MatrixXd& J, std::vector<std::string>& reason,
                                 const std::vector<std::string>& names, double rel_tol) {
  const auto p = J.cols();
  std::vector<bool> out(static_cast<std::size_t>(p), false);
  reason.assign(static_cast<std::size_t>(p), "");
  if (p == 0) return out;
  Eigen::VectorXd norm = J.colwise().norm().transpose();
  const double top = norm.maxCoeff();
  std::vector<Eigen::Index> live;
  for (Eigen::Index j = 0; j < p; ++j) {
    if (!(norm[j] > 1e-12 * top)) {
      out[static_cast<std::size_t>(j)] = true;
      reason[static_cast<std::size_t>(j)] = "has no effect on the fitted stresses";
    } else {
      live.push_back(j);
    }
  }
  if (live.size() < 2) return out;
  Eigen::MatrixXd Js(J.rows(), static_cast<Eigen::Index>(live.size()));
  for (std::size_t c = 0; c < live.size(); ++c)
    Js.col(static_cast<Eigen::Index>(c)) = J.col(live[c]) / norm[live[c]];
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Js, Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  for (Eigen::Index k = 0; k < s.size(); ++k) {
    if (s[k] > rel_tol * s[0]) continue;
    const Eigen::VectorXd v = svd.matrixV().col(k);
    std::string with;
    std::vector<std::size_t> members;
    for (Eigen::Index c = 0; c < v.size(); ++c)
      if (std::abs(v[c]) > 0.2) members.push_back(static_cast<std::size_t>(live[c]));
    for (std::size_t j : members)
      with += (with.empty() ? "" : ", ") + names[j];
    for (std::size_t j : members) {
      out[j] = true;
      reason[j] = "only a combination of " + with + " is determined by the data";
    }
  }
  return out;
}

} // namespace pnc::damage::stats
