// The MD gates of the card verdict (pnc/damage/verdict.hpp MdCardGates, decision D12f).
#include "pnc/damage/data.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/verdict.hpp"

#include <fmt/format.h>

#include <cmath>

namespace pnc::damage {

namespace {

/// Points of a curve in the linear range of `p` (decision D12j): the leading loading rows at
/// which the fitted law's driven stress differs from its undamaged response (the same law
/// with every damage constant zero) by at most the point's standard error; without point
/// errors, the rows before any damage (D > 0). Integrated along the rows.
int points_in_linear_range(const NdmParameters& p, const CaseCurve& c) {
  NdmParameters elastic = p;
  const auto& names = constant_names(p.model);
  for (std::size_t j = 0; j < names.size(); ++j)
    if (names[j][0] == 'A' || names[j][0] == 'B') elastic.k[j] = 0.0;
  const int driven = single_driven(deformation_case(c.id), "the linear-range count"); // D360
  NdmState s0, s1, u0, u1;
  Voigt e0 = Voigt::Zero(), sigma, sigma_el;
  ErrorBuffer err;
  for (Eigen::Index k = 0; k < c.strain.rows(); ++k) {
    const Voigt e = c.strain.row(k).transpose();
    if (integrate(p, s0, s1, e0, e - e0, sigma, nullptr, err) != Status::ok ||
        integrate(elastic, u0, u1, e0, e - e0, sigma_el, nullptr, err) != Status::ok)
      return static_cast<int>(k);
    const double se = c.stress_stderr.rows() > k ? c.stress_stderr(k, driven) : 0.0;
    if (se > 0 ? std::abs(sigma[driven] - sigma_el[driven]) > se
               : (s1.D[0] > 0 || s1.D[1] > 0 || s1.D[2] > 0))
      return static_cast<int>(k);
    s0 = s1;
    u0 = u1;
    e0 = e;
  }
  return static_cast<int>(c.strain.rows());
}

} // namespace

void judge_md_card(const FitReport& rep, const StressStrainData& data, const MdCardGates& g,
                   Verdict& v) {
  // point errors: independent replicas, not blocks of one structure (D130)
  if (!g.deterministic && g.replicas < g.min_replicas)
    v.warn(fmt::format("the point errors come from {} independent replica(s) (fewer than {}): "
                       "they measure the thermal noise of {} but not the scatter between RVEs, "
                       "so the standard errors are not yet trustworthy; run with "
                       "\"run\": {{\"replicas\": {}}} or more",
                       g.replicas, g.min_replicas,
                       g.replicas == 1 ? std::string("one structure")
                                       : fmt::format("{} structures", g.replicas),
                       g.min_replicas));
  // chi^2/dof against those errors
  if (g.deterministic) {
    // no noise to compare the scatter with (static rows, D120)
  } else if (!std::isfinite(rep.chi2) || rep.dof <= 0)
    v.warn("the data carry no point errors: chi^2/dof cannot be checked against them");
  else {
    const double r = rep.chi2 / rep.dof;
    if (r < g.chi2_dof_min || r > g.chi2_dof_max)
      v.warn(fmt::format(
          "chi^2/dof = {:.3g} is outside [{}, {}]: {}", r, g.chi2_dof_min, g.chi2_dof_max,
          r < g.chi2_dof_min ? "the point errors are larger than the scatter about the fit "
                               "(overestimated, or the points are correlated)"
                             : "the scatter about the fit is larger than the point errors "
                               "(the model or the errors are wrong)"));
  }
  // every fitted constant resolved to max_relative_error of its scale
  const auto& names = constant_names(rep.params.model);
  for (std::size_t j = 0; j < names.size() && j < rep.std_error.size() && j < rep.fitted.size();
       ++j) {
    if (!rep.fitted[j]) continue;
    const double se = rep.std_error[j], scale = detail::constant_scale(rep.params, j);
    if (!(std::isfinite(se) && se <= g.max_relative_error * scale))
      v.warn(fmt::format("{} = {:.4g} +- {:.2g}: the standard error is {} of its scale {:.3g} "
                         "(an MD card needs <= {:.0f} %)",
                         names[j], rep.params.k[j], se,
                         std::isfinite(se) ? fmt::format("{:.0f} %", 100 * se / scale)
                                           : std::string("not finite"),
                         scale, 100 * g.max_relative_error));
  }
  // enough points in the linear range of every driven curve
  for (const auto& c : data.cases) {
    const int n = points_in_linear_range(rep.params, c);
    if (n < g.min_linear_points)
      v.warn(fmt::format("case {}: {} point(s) in the linear range (where the fitted damage "
                         "changes the stress by less than the point's standard error; an MD "
                         "card needs >= {} to fix the elastic constants)",
                         c.id, n, g.min_linear_points));
  }
}

} // namespace pnc::damage
