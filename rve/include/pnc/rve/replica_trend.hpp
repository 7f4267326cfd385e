#pragma once
// pnc/rve/replica_trend.hpp: the misfit test of a fit to replica-mean curves (decisions D12k,
// D417).
// Units: stresses Pa, strains dimensionless.
//
// All strain steps of one replica deform the same frozen structure, so its deviations from
// the mean are correlated along its curves (lag-1 autocorrelation 0.5-0.97 on the glass).
// Tests that take the residuals of the mean curves as independent (the runs test, the p-value
// of chi^2) then reject a correct model. Here each replica's residual curve about the joint
// fit is projected on the Legendre polynomials P0..P3 of the driven strain mapped onto [-1, 1]
// over the fitted rows: one replica is one independent sample of those four coefficients,
// whatever the correlation along its curve. A trend the model misses is common to every
// replica, so the mean of its coefficient differs from zero by more than the between-replica
// standard error allows (Student t with N - 1 degrees of freedom, two-sided).
//
// The pure polymer's law is isotropic (docs/theory.md section 1.1): its three extension cases
// are one experiment in three directions, and so are its three shears. A shape the law misses
// is then common to the curves of one role (the driven stress of an extension case, its
// lateral stresses, the stress of a shear), and one replica's coefficients averaged over the
// curves of a role are again one independent sample (decision D397): the pooled roles are
// tested as well, and the family-wise p runs over curves and roles. A curve is read along its
// case (strain and residual times the case's sense, D424), so a negative shear (cases 7-9)
// pools with the positive ones instead of cancelling their even Legendre terms.
//
// A resolved trend is also measured (decision D417): its size and an upper bound on it, as a
// share of the curve's stress; a card may miss up to MdCardGates::max_shape_error of it.
#include "pnc/damage/fit.hpp"
#include "pnc/damage/verdict.hpp"
#include "pnc/rve/replicas.hpp"

#include <array>
#include <string>
#include <vector>

namespace pnc::rve {

struct TrendCurve {
  /// a curve: its case and Voigt component; a pooled role (D397): case_id 0 and `role`
  int case_id = 0, component = 0, points = 0;
  std::string role;                   ///< e.g. "driven extension"; empty for one curve
  std::vector<int> role_cases;        ///< a pooled role: the cases of its curves
  int role_curves = 0;                ///< a pooled role: its number of curves
  std::array<double, 4> mean{}, se{}; ///< Pa: coefficients of P0..P3 over the replicas
  std::array<double, 4> t{};          ///< mean / se
  double p = 1; ///< smallest two-sided p of the four coefficients, times 4 (Bonferroni)
  /// The trend on a grid of x in [-1, 1] (decisions D417, D420). With r_i(x) = sum_m c_mi P_m(x)
  /// the trend of replica i: `grid_mean` = |rbar(x)|, its mean over the replicas, and `grid_se`
  /// = se(x), that mean's between-replica standard error, both Pa; `coverage` = k, the
  /// two-sided 99 % Student factor of N - 1 dof (dimensionless).
  std::vector<double> grid_mean, grid_se;
  double coverage = 0;
  /// Pa: the size of the trend, max over the grid of |rbar(x)| (decision D417)
  double amplitude() const;
  /// Pa: its 97.5 % upper bound, max over the grid of |rbar(x)| + k se(x) (decision D417). It is
  /// at least the true trend's largest |r(x)| in >= 97.5 % of the cases: at the x where the
  /// true trend is largest the one-sided level is 99.5 %, less what the joint fit's own scatter
  /// takes (measured by Monte Carlo, docs/decisions/damage.md D417).
  double bound() const;
  /// Pa: the stress the trend is measured against, max |replica-mean stress| of the curve over
  /// the fitted rows (a pooled role: the mean of its curves' scales)
  double scale = 0;
  /// "case 4 sigma12", or for a pooled role "driven extension (3 curves of cases 1, 2, 3; D397)"
  std::string label() const;
  /// bound / scale (dimensionless; +inf for a zero scale: no share of it holds the bound)
  double relative_bound() const;
  /// The replica count that would bring relative_bound() to at most `tolerance` (dimensionless)
  /// if the mean trend and the scatter between the `replicas` replicas stayed as measured
  /// (decision D420): the smallest N' > replicas, up to `max_replicas`, with max over the grid
  /// of |rbar(x)| + k(N' - 1) se(x) sqrt(replicas / N') <= tolerance scale; 0 when none is
  /// (the mean trend alone at the tolerance, or more than max_replicas needed).
  int replicas_for(double tolerance, int replicas, int max_replicas = kMaxReplicas) const;
  /// a curve of a pooled role (D397): judged through its role for the shape error (D417)
  bool pooled = false;
};

struct ReplicaTrend {
  bool applicable = false; ///< needs >= 3 replicas (>= 2 degrees of freedom)
  std::string why_not;     ///< when not applicable
  int replicas = 0;
  std::vector<TrendCurve> curves; ///< one per fitted curve of the joint fit
  /// pure polymer (D397): one per role with >= 2 curves, their coefficients averaged per replica
  std::vector<TrendCurve> roles;
  /// min over curves and roles of p, times their number (Bonferroni)
  double p_family = 1;
  /// the curve or role with the smallest p
  const TrendCurve* worst() const;
  /// The units the shape is judged by (decision D417): the pooled roles and the curves that
  /// are in none; the one with the largest relative_bound() (a zero scale counts as the
  /// largest), nullptr when there is none.
  const TrendCurve* largest_shape() const;
  /// The number of tests the family-wise p counts: curves plus pooled roles, at least 1.
  std::size_t tests() const;
  /// The law's shape error (decision D417): largest_shape()'s relative_bound() (dimensionless;
  /// NaN when not applicable). The true trend of each unit is below its bound in >= 97.5 % of
  /// the cases.
  double shape_error() const;
};

/// The verdict of the test (decisions D12k, D417): the card states the law's shape to within
/// `max_shape_error` of each stress, so a unit whose bound exceeds that share of its stress is
/// a warning, naming it and the size: "the model misses a trend common to the N replicas" when
/// the test resolves its trend (p times the number of curves and roles below `p_misfit`),
/// "the law's shape is not resolved" when it does not (too few replicas). Within it, resolved
/// or not, no finding (the card records the size, FitRecord::shape_error). Nothing when the
/// test is not applicable.
void judge_replica_trend(const ReplicaTrend& t, double p_misfit, double max_shape_error,
                         damage::Verdict& v);

/// The test for the fitted curves of `joint` (its components list) on the replica curves of
/// `c`, over the rows the fit used (damage::rows_in_fit_range: every strain component <=
/// strain_max, lambda_max - 1 <= stretch_max; 0 = no bound).
ReplicaTrend replica_trend_test(const CombinedCases& c, const damage::FitReport& joint,
                                double strain_max, double stretch_max = 0);

/// Markdown section: per curve the coefficients, their errors, p and the trend's size; its
/// last line quotes `max_shape_error` (dimensionless), the tolerance the verdict used.
std::string replica_trend_markdown(const ReplicaTrend& t, double max_shape_error);

} // namespace pnc::rve
