// The replica trend test (replica_trend.hpp, decisions D12k, D397).
#include "pnc/rve/replica_trend.hpp"

#include "pnc/damage/ndm.hpp"
#include "pnc/md/statistics.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace pnc::rve {

namespace {

double legendre(int m, double x) {
  switch (m) {
  case 0:
    return 1.0;
  case 1:
    return x;
  case 2:
    return 0.5 * (3 * x * x - 1);
  default:
    return 0.5 * (5 * x * x * x - 3 * x);
  }
}

// The t-test of the four coefficients over the replicas (coef[m][replica], Pa).
void test_coefficients(const std::array<std::vector<double>, 4>& coef, int replicas,
                       TrendCurve& tc) {
  double pmin = 1;
  for (int m = 0; m < 4; ++m) {
    const md::ReplicaEstimate r = md::replica_mean_se(coef[m]);
    tc.mean[m] = r.mean;
    tc.se[m] = r.se;
    tc.t[m] = r.se > 0 ? r.mean / r.se : (r.mean == 0 ? 0.0 : INFINITY);
    const double p = 2 * (1 - md::student_t_cdf(std::fabs(tc.t[m]), replicas - 1));
    pmin = std::min(pmin, p);
  }
  tc.p = std::min(1.0, 4 * pmin);
}

// The role of a curve of the isotropic pure polymer (decision D397).
std::string role_of(const CombinedCase& c, int component) {
  if (c.voigt >= 3) return component == c.voigt ? "shear" : "";
  if (component == c.voigt) return "driven extension";
  return component < 3 ? "lateral extension" : "";
}

} // namespace

const TrendCurve* ReplicaTrend::worst() const {
  const TrendCurve* w = nullptr;
  for (const auto* list : {&curves, &roles})
    for (const auto& c : *list)
      if (!w || c.p < w->p) w = &c;
  return w;
}

ReplicaTrend replica_trend_test(const CombinedCases& c, const damage::FitReport& joint,
                                double strain_max, double stretch_max) {
  ReplicaTrend out;
  out.replicas = c.replicas;
  if (c.replicas < 3) {
    out.why_not = fmt::format("{} replica(s): the test needs >= 3", c.replicas);
    return out;
  }
  out.applicable = true;
  struct Pool {
    std::vector<int> cases;
    int curves = 0, points = 0;
    std::array<std::vector<double>, 4> sum;
  };
  std::map<std::string, Pool> pools; // decision D397: the pure polymer's roles
  for (const auto& fc : joint.components) {
    const auto it = std::find_if(c.cases.begin(), c.cases.end(),
                                 [&](const CombinedCase& cc) { return cc.id == fc.case_id; });
    if (it == c.cases.end()) continue;
    const Eigen::Index n = damage::rows_in_fit_range(it->strain, strain_max, stretch_max);
    if (n < 5) continue; // four coefficients need more rows than that
    const Eigen::Matrix<double, Eigen::Dynamic, 6> e = it->strain.topRows(n);
    const auto model = damage::stress_path(joint.params, e);
    // x in [-1, 1] from the driven strain of the case over the fitted rows
    const double e0 = e.col(it->voigt).minCoeff(), e1 = e.col(it->voigt).maxCoeff();
    TrendCurve tc;
    tc.case_id = fc.case_id;
    tc.component = fc.component;
    tc.points = static_cast<int>(n);
    std::array<std::vector<double>, 4> coef;
    for (const auto& ys : it->replica_stress) {
      for (int m = 0; m < 4; ++m) {
        double num = 0, den = 0;
        for (Eigen::Index k = 0; k < n; ++k) {
          const double x = e1 > e0 ? 2 * (e(k, it->voigt) - e0) / (e1 - e0) - 1 : 0.0;
          const double pm = legendre(m, x);
          num += (ys(k, fc.component) - model(k, fc.component)) * pm;
          den += pm * pm;
        }
        coef[m].push_back(den > 0 ? num / den : 0.0);
      }
    }
    test_coefficients(coef, c.replicas, tc);
    out.curves.push_back(tc);
    const std::string role =
        joint.params.model == damage::Model::pp ? role_of(*it, fc.component) : "";
    if (role.empty()) continue;
    Pool& pool = pools[role];
    if (std::find(pool.cases.begin(), pool.cases.end(), fc.case_id) == pool.cases.end())
      pool.cases.push_back(fc.case_id);
    ++pool.curves;
    pool.points = pool.points == 0 ? tc.points : std::min(pool.points, tc.points);
    for (int m = 0; m < 4; ++m) {
      pool.sum[m].resize(coef[m].size(), 0.0);
      for (std::size_t r = 0; r < coef[m].size(); ++r)
        pool.sum[m][r] += coef[m][r];
    }
  }
  for (auto& [role, pool] : pools) {
    if (pool.curves < 2) continue;
    TrendCurve tc;
    tc.role =
        fmt::format("{} ({} curves of cases {})", role, pool.curves, fmt::join(pool.cases, ", "));
    tc.points = pool.points;
    for (auto& v : pool.sum)
      for (double& x : v)
        x /= pool.curves; // one replica's mean over the role: one independent sample
    test_coefficients(pool.sum, c.replicas, tc);
    out.roles.push_back(tc);
  }
  const TrendCurve* w = out.worst();
  const std::size_t tests = out.curves.size() + out.roles.size();
  out.p_family =
      w ? std::min(1.0, w->p * static_cast<double>(std::max<std::size_t>(1, tests))) : 1.0;
  return out;
}

std::string replica_trend_markdown(const ReplicaTrend& t) {
  if (!t.applicable) return "";
  static const char* comp[6] = {"sigma11", "sigma22", "sigma33", "sigma23", "sigma13", "sigma12"};
  std::string s = fmt::format(
      "### Misfit test across replicas (D12k)\n\nEach replica's residual curve about the joint "
      "fit projected on the Legendre polynomials P0..P3 of the driven strain over the fitted "
      "rows; the mean of each coefficient over the {} replicas against its between-replica "
      "standard error (Student t, {} dof). A trend the model misses is common to every replica; "
      "the correlated noise along one replica's curve is not (the runs test and the chi^2 "
      "p-value assume independent residuals and are not used for replica data).\n\n"
      "| curve | points | P0 | P1 | P2 | P3 | p (x4) |\n|---|---|---|---|---|---|---|\n",
      t.replicas, t.replicas - 1);
  for (const auto* list : {&t.curves, &t.roles})
    for (const auto& c : *list) {
      if (c.role.empty())
        s += fmt::format("| case {} {} | {} |", c.case_id, comp[c.component % 6], c.points);
      else
        s += fmt::format("| pooled: {} | {} |", c.role, c.points);
      for (int m = 0; m < 4; ++m)
        s += fmt::format(" {:+.3g} +- {:.2g} MPa |", c.mean[m] * 1e-6, c.se[m] * 1e-6);
      s += fmt::format(" {:.2g} |\n", c.p);
    }
  if (!t.roles.empty())
    s += "\nThe pure polymer's law is isotropic: the curves of one role (the driven or the "
         "lateral stress of an extension case, the stress of a shear) are one experiment in "
         "several directions, and each replica's coefficients averaged over a role are one "
         "sample of a pooled test (D397).\n";
  s += fmt::format("\nFamily-wise p (Bonferroni over {} curves and {} pooled roles): {:.2g}.\n\n",
                   t.curves.size(), t.roles.size(), t.p_family);
  return s;
}

} // namespace pnc::rve
