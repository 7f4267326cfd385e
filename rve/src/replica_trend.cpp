// The replica trend test (replica_trend.hpp, decision D12k).
#include "pnc/rve/replica_trend.hpp"

#include "pnc/damage/ndm.hpp"
#include "pnc/md/statistics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

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

} // namespace

ReplicaTrend replica_trend_test(const CombinedCases& c, const damage::FitReport& joint,
                                double strain_max, double stretch_max) {
  ReplicaTrend out;
  out.replicas = c.replicas;
  if (c.replicas < 3) {
    out.why_not = fmt::format("{} replica(s): the test needs >= 3", c.replicas);
    return out;
  }
  out.applicable = true;
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
    double pmin = 1;
    for (int m = 0; m < 4; ++m) {
      const md::ReplicaEstimate r = md::replica_mean_se(coef[m]);
      tc.mean[m] = r.mean;
      tc.se[m] = r.se;
      tc.t[m] = r.se > 0 ? r.mean / r.se : (r.mean == 0 ? 0.0 : INFINITY);
      const double p = 2 * (1 - md::student_t_cdf(std::fabs(tc.t[m]), c.replicas - 1));
      pmin = std::min(pmin, p);
    }
    tc.p = std::min(1.0, 4 * pmin);
    out.curves.push_back(tc);
  }
  double pmin = 1;
  for (const auto& tc : out.curves)
    pmin = std::min(pmin, tc.p);
  out.p_family =
      std::min(1.0, pmin * static_cast<double>(std::max<std::size_t>(1, out.curves.size())));
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
  for (const auto& c : t.curves) {
    s += fmt::format("| case {} {} | {} |", c.case_id, comp[c.component % 6], c.points);
    for (int m = 0; m < 4; ++m)
      s += fmt::format(" {:+.3g} +- {:.2g} MPa |", c.mean[m] * 1e-6, c.se[m] * 1e-6);
    s += fmt::format(" {:.2g} |\n", c.p);
  }
  s += fmt::format("\nFamily-wise p (Bonferroni over {} curves): {:.2g}.\n\n", t.curves.size(),
                   t.p_family);
  return s;
}

} // namespace pnc::rve
