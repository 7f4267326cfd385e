#pragma once
// pnc/rve/replica_trend.hpp: the misfit test of a fit to replica-mean curves (decision D12k).
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
// tested as well, and the family-wise p runs over curves and roles.
#include "pnc/damage/fit.hpp"
#include "pnc/rve/replicas.hpp"

#include <array>
#include <string>
#include <vector>

namespace pnc::rve {

struct TrendCurve {
  /// a curve: its case and Voigt component; a pooled role (D397): case_id 0 and `role`
  int case_id = 0, component = 0, points = 0;
  std::string role; ///< e.g. "driven extension (cases 1, 2, 3)"; empty for one curve
  std::array<double, 4> mean{}, se{}; ///< Pa: coefficients of P0..P3 over the replicas
  std::array<double, 4> t{};          ///< mean / se
  double p = 1; ///< smallest two-sided p of the four coefficients, times 4 (Bonferroni)
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
};

/// The test for the fitted curves of `joint` (its components list) on the replica curves of
/// `c`, over the rows the fit used (damage::rows_in_fit_range: every strain component <=
/// strain_max, lambda_max - 1 <= stretch_max; 0 = no bound).
ReplicaTrend replica_trend_test(const CombinedCases& c, const damage::FitReport& joint,
                                double strain_max, double stretch_max = 0);

/// Markdown section: per curve the coefficients, their errors and p.
std::string replica_trend_markdown(const ReplicaTrend& t);

} // namespace pnc::rve
