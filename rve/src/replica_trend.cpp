// The replica trend test (replica_trend.hpp, decisions D12k, D397).
#include "pnc/rve/replica_trend.hpp"

#include "pnc/damage/cases.hpp"
#include "pnc/damage/ndm.hpp"
#include "pnc/md/statistics.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
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
  // decision D417: the size of the trend, on a fine grid of x; bound = |mean| + k se, k the
  // two-sided 99 % factor (one-sided 99.5 % at each x; the joint fit's own scatter takes part
  // of it: the bound covers the true size in >= 97.5 % of Monte-Carlo trials)
  tc.coverage = md::coverage_factor(replicas - 1, 0.99);
  constexpr int kGrid = 201;
  std::vector<double> r(coef[0].size());
  tc.grid_mean.assign(kGrid, 0.0);
  tc.grid_se.assign(kGrid, 0.0);
  for (int g = 0; g < kGrid; ++g) {
    const double x = -1.0 + 2.0 * g / (kGrid - 1);
    for (std::size_t i = 0; i < r.size(); ++i) {
      r[i] = 0;
      for (int m = 0; m < 4; ++m)
        r[i] += coef[m][i] * legendre(m, x);
    }
    const md::ReplicaEstimate e = md::replica_mean_se(r);
    tc.grid_mean[static_cast<std::size_t>(g)] = std::fabs(e.mean);
    tc.grid_se[static_cast<std::size_t>(g)] = e.se;
  }
}

// The role of a curve of the isotropic pure polymer (decision D397).
std::string role_of(const CombinedCase& c, int component) {
  if (c.voigt >= 3) return component == c.voigt ? "shear" : "";
  if (component == c.voigt) return "driven extension";
  return component < 3 ? "lateral extension" : "";
}

// The two-sided 99 % Student factor of n - 1 dof; the factors up to kMaxReplicas replicas are
// computed once (each takes milliseconds and D420's projection asks for dozens per unit).
double coverage_of_replicas(int n) {
  static const std::array<double, kMaxReplicas + 1> table = [] {
    std::array<double, kMaxReplicas + 1> t{};
    for (int i = 2; i <= kMaxReplicas; ++i)
      t[static_cast<std::size_t>(i)] = md::coverage_factor(i - 1, 0.99);
    return t;
  }();
  return n >= 2 && n <= kMaxReplicas ? table[static_cast<std::size_t>(n)]
                                     : md::coverage_factor(n - 1, 0.99);
}

const char* stress_name(int component) {
  static const char* names[6] = {"sigma11", "sigma22", "sigma33", "sigma23", "sigma13", "sigma12"};
  return names[((component % 6) + 6) % 6];
}

} // namespace

double TrendCurve::amplitude() const {
  double a = 0;
  for (double m : grid_mean)
    a = std::max(a, m);
  return a;
}

double TrendCurve::bound() const {
  double b = 0;
  for (std::size_t g = 0; g < grid_mean.size() && g < grid_se.size(); ++g)
    b = std::max(b, grid_mean[g] + coverage * grid_se[g]);
  return b;
}

std::string TrendCurve::label() const {
  if (role.empty()) return fmt::format("case {} {}", case_id, stress_name(component));
  return fmt::format("{} ({} curves of cases {}; D397)", role, role_curves,
                     fmt::join(role_cases, ", "));
}

double TrendCurve::relative_bound() const {
  return scale > 0 ? bound() / scale : INFINITY; // a curve of zero stress: no share holds (D417)
}

int TrendCurve::replicas_for(double tolerance, int replicas, int max_replicas) const {
  // decision D420: the bound projected to N' replicas, the mean and the per-replica scatter
  // (se sqrt(N)) held at what N replicas measured
  const double limit = tolerance * scale;
  if (!(scale > 0) || grid_mean.empty() || replicas < 2) return 0;
  for (int n = replicas + 1; n <= max_replicas; ++n) {
    const double k = coverage_of_replicas(n);
    const double shrink = std::sqrt(static_cast<double>(replicas) / n);
    double b = 0;
    for (std::size_t g = 0; g < grid_mean.size(); ++g)
      b = std::max(b, grid_mean[g] + k * grid_se[g] * shrink);
    if (b <= limit) return n;
  }
  return 0;
}

const TrendCurve* ReplicaTrend::largest_shape() const {
  const TrendCurve* big = nullptr;
  double big_rel = -1;
  for (const auto* list : {&curves, &roles})
    for (const auto& c : *list) {
      if (c.pooled) continue; // judged through its role (D397)
      const double rel = c.relative_bound();
      if (rel > big_rel) big = &c, big_rel = rel;
    }
  return big;
}

double ReplicaTrend::shape_error() const {
  const TrendCurve* big = applicable ? largest_shape() : nullptr;
  return big ? big->relative_bound() : std::numeric_limits<double>::quiet_NaN();
}

std::size_t ReplicaTrend::tests() const {
  return std::max<std::size_t>(1, curves.size() + roles.size());
}

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
    double scale = 0; // sum of the curves' scales
    std::array<std::vector<double>, 4> sum;
  };
  std::map<std::string, Pool> pools;   // decision D397: the pure polymer's roles
  std::vector<std::string> curve_role; // per curve of out.curves: its role, "" for none
  for (const auto& fc : joint.components) {
    const CombinedCase* it = c.find(fc.case_id);
    if (!it) continue;
    const Eigen::Index n = damage::rows_in_fit_range(it->strain, strain_max, stretch_max);
    if (n < 5) continue; // four coefficients need more rows than that
    const Eigen::Matrix<double, Eigen::Dynamic, 6> e = it->strain.topRows(n);
    const auto model = damage::stress_path(joint.params, e);
    // x in [-1, 1] from the driven strain of the case over the fitted rows, and the residual,
    // both read along the case (times its sense, D424): a negative shear's coefficients are its
    // positive one's for a glass without a preferred sense, so a role pools them
    const double sense = damage::driven_sense(damage::deformation_case(fc.case_id));
    const Eigen::VectorXd along = sense * e.col(it->voigt);
    const double e0 = along.minCoeff(), e1 = along.maxCoeff();
    TrendCurve tc;
    tc.case_id = fc.case_id;
    tc.component = fc.component;
    tc.points = static_cast<int>(n);
    for (Eigen::Index k = 0; k < n; ++k) { // D417: the stress the trend is measured against
      double mean = 0;
      for (const auto& ys : it->replica_stress)
        mean += ys(k, fc.component);
      tc.scale =
          std::max(tc.scale, std::fabs(mean) / static_cast<double>(it->replica_stress.size()));
    }
    std::array<std::vector<double>, 4> coef;
    for (const auto& ys : it->replica_stress) {
      for (int m = 0; m < 4; ++m) {
        double num = 0, den = 0;
        for (Eigen::Index k = 0; k < n; ++k) {
          const double x = e1 > e0 ? 2 * (along[k] - e0) / (e1 - e0) - 1 : 0.0;
          const double pm = legendre(m, x);
          num += sense * (ys(k, fc.component) - model(k, fc.component)) * pm;
          den += pm * pm;
        }
        coef[m].push_back(den > 0 ? num / den : 0.0);
      }
    }
    test_coefficients(coef, c.replicas, tc);
    out.curves.push_back(tc);
    const std::string role =
        joint.params.model == damage::Model::pp ? role_of(*it, fc.component) : "";
    curve_role.push_back(role);
    if (role.empty()) continue;
    Pool& pool = pools[role];
    if (std::find(pool.cases.begin(), pool.cases.end(), fc.case_id) == pool.cases.end())
      pool.cases.push_back(fc.case_id);
    ++pool.curves;
    pool.scale += tc.scale;
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
    tc.role = role;
    tc.role_cases = pool.cases;
    tc.role_curves = pool.curves;
    tc.points = pool.points;
    for (auto& v : pool.sum)
      for (double& x : v)
        x /= pool.curves; // one replica's mean over the role: one independent sample
    test_coefficients(pool.sum, c.replicas, tc);
    tc.scale = pool.scale / pool.curves;
    out.roles.push_back(tc);
    for (std::size_t i = 0; i < out.curves.size(); ++i) // D417: judged through this role
      if (curve_role[i] == role) out.curves[i].pooled = true;
  }
  const TrendCurve* w = out.worst();
  out.p_family = w ? std::min(1.0, w->p * static_cast<double>(out.tests())) : 1.0;
  return out;
}

namespace {
// What more replicas would do for the shape error (decision D420): the count that brings every
// unit under the tolerance if the trends and the scatter stay as measured, or why none does.
std::string more_replicas(const ReplicaTrend& t, double max_shape_error) {
  int need = t.replicas;
  for (const auto* list : {&t.curves, &t.roles})
    for (const auto& c : *list) {
      if (c.pooled || !(c.relative_bound() > max_shape_error)) continue;
      const int n = c.replicas_for(max_shape_error, t.replicas);
      if (n == 0) {
        if (c.amplitude() >= max_shape_error * c.scale)
          return fmt::format("more replicas narrow the bound as 1/sqrt(N), but the mean trend "
                             "measured so far is {:.3g} % of the stress itself (D420)",
                             100 * c.amplitude() / c.scale);
        return fmt::format("more replicas narrow the bound as 1/sqrt(N), but more than {} "
                           "would be needed if the trend and the scatter stay as measured (D420)",
                           kMaxReplicas);
      }
      need = std::max(need, n);
    }
  return fmt::format("about {} replicas would bring it under {:.3g} % if the trend and the "
                     "scatter between replicas stay as measured (an estimate; add them to this "
                     "run with --resume --replicas {}, D418, D420)",
                     need, 100 * max_shape_error, need);
}
} // namespace

void judge_replica_trend(const ReplicaTrend& t, double p_misfit, double max_shape_error,
                         damage::Verdict& v) {
  const TrendCurve* big = t.applicable ? t.largest_shape() : nullptr;
  if (!big) return;
  const double rel = big->relative_bound(); // the shape error (D417)
  if (!(rel > max_shape_error)) return;     // the law's shape within the tolerance (D417)
  const double tests = static_cast<double>(t.tests());
  const double p = std::min(1.0, big->p * tests); // family-wise (D12k)
  const std::string where = (big->role.empty() ? "" : "pooled ") + big->label();
  const std::string size =
      fmt::format("up to {:.3g} MPa, {:.3g} % of its stress at the 97.5 % bound",
                  big->bound() * 1e-6, 100 * rel);
  if (p < p_misfit)
    v.warn(fmt::format("the model misses a trend common to the {} replicas ({}: Legendre "
                       "coefficients of the residuals against their between-replica errors, p = "
                       "{:.2g} family-wise over {} curves and pooled roles; D12k) of {}, above "
                       "the {:.3g} % a card may miss (D417)",
                       t.replicas, where, p, static_cast<int>(tests), size, 100 * max_shape_error));
  else
    v.warn(fmt::format("the law's shape is not resolved to {:.3g} % of the stress with {} "
                       "replicas: in {} no trend is resolved (p = {:.2g}), but one of {} cannot "
                       "be excluded (D417); {}",
                       100 * max_shape_error, t.replicas, where, p, size,
                       more_replicas(t, max_shape_error)));
}

std::string replica_trend_markdown(const ReplicaTrend& t, double max_shape_error) {
  if (!t.applicable) return "";
  std::string s = fmt::format(
      "### Misfit test across replicas (D12k)\n\nEach replica's residual curve about the joint "
      "fit projected on the Legendre polynomials P0..P3 of the driven strain over the fitted "
      "rows; the mean of each coefficient over the {} replicas against its between-replica "
      "standard error (Student t, {} dof). A trend the model misses is common to every replica; "
      "the correlated noise along one replica's curve is not (the runs test and the chi^2 "
      "p-value assume independent residuals and are not used for replica data).\n\n"
      "The last two columns give the size of the trend (D417): the largest |mean trend| over "
      "the fitted range and its 97.5 % upper bound (|mean| + the 99 % two-sided Student factor x "
      "its between-replica error), the bound also as a share of the curve's largest "
      "replica-mean stress.\n\n"
      "| curve | points | P0 | P1 | P2 | P3 | p (x4) | size | bound (share of stress) |\n"
      "|---|---|---|---|---|---|---|---|---|\n",
      t.replicas, t.replicas - 1);
  for (const auto* list : {&t.curves, &t.roles})
    for (const auto& c : *list) {
      s += fmt::format("| {}{} | {} |", c.role.empty() ? "" : "pooled: ", c.label(), c.points);
      for (int m = 0; m < 4; ++m)
        s += fmt::format(" {:+.3g} +- {:.2g} MPa |", c.mean[m] * 1e-6, c.se[m] * 1e-6);
      s += fmt::format(" {:.2g} | {:.3g} MPa | {:.3g} MPa ({:.3g} %) |\n", c.p,
                       c.amplitude() * 1e-6, c.bound() * 1e-6, 100 * c.relative_bound());
    }
  if (!t.roles.empty())
    s += "\nThe pure polymer's law is isotropic: the curves of one role (the driven or the "
         "lateral stress of an extension case, the stress of a shear) are one experiment in "
         "several directions, and each replica's coefficients averaged over a role are one "
         "sample of a pooled test (D397).\n";
  s += fmt::format(
      "\nFamily-wise p (Bonferroni over {} curves and {} pooled roles): {:.2g}. "
      "The law's shape error (the largest bound as a share of its stress, over the pooled roles "
      "and the curves in none; D417): {:.3g} %, at most {:.3g} % for a card without warnings.\n\n",
      t.curves.size(), t.roles.size(), t.p_family, 100 * t.shape_error(), 100 * max_shape_error);
  return s;
}

} // namespace pnc::rve
