// The card verdict: see pnc/damage/verdict.hpp and docs/decisions.md D12d.
#include "pnc/damage/verdict.hpp"

#include "pnc/core/error.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/moduli.hpp"
#include "pnc/damage/reference.hpp"

#include <fmt/format.h>

#include <cmath>

namespace pnc::damage {

namespace {
const char* component_name(int i) {
  static const char* n[6] = {"sigma11", "sigma22", "sigma33", "sigma23", "sigma13", "sigma12"};
  return i >= 0 && i < 6 ? n[i] : "?";
}

void judge_statistics(const FitReport& rep, const VerdictLimits& L, Verdict& v) {
  if (rep.termination == "FAILURE" || rep.termination == "USER_FAILURE")
    v.refuse("the solver failed (" + rep.termination + "): " + rep.message);
  else if (!rep.converged)
    v.warn("the solver stopped before convergence (" + rep.termination + "): " + rep.message);
  int series = 0;
  for (const auto& c : rep.components)
    if (c.points >= 2) ++series;
  for (const auto& c : rep.components) {
    const std::string curve = fmt::format("case {} {}", c.case_id, component_name(c.component));
    if (std::isfinite(c.r2) && c.r2 < L.r2_not_usable)
      v.refuse(fmt::format("{}: R^2 = {:.3g}: the fitted curve describes the data worse than "
                           "their mean",
                           curve, c.r2));
    else if (std::isfinite(c.r2) && c.r2 < L.r2_warning)
      v.warn(fmt::format("{}: R^2 = {:.3g} < {}: the curve is poorly described", curve, c.r2,
                         L.r2_warning));
    if (L.independent_residuals && c.runs_p * series < L.p_misfit)
      v.warn(fmt::format("{}: the residuals run in long stretches of one sign ({} runs, {:.1f} "
                         "expected; p = {:.2g}, Bonferroni over {} curves): the model misses a "
                         "trend of this curve",
                         curve, c.runs, c.runs_expected, c.runs_p * series, series));
  }
  if (L.independent_residuals && std::isfinite(rep.chi2_p) && rep.chi2_p < L.p_misfit)
    v.warn(fmt::format("the model does not fit the data within their standard errors: "
                       "chi^2/dof = {:.3g} ({} dof, p = {:.2g}); the model, alpha or the "
                       "errors are wrong, and the standard errors were scaled up by "
                       "sqrt(chi^2/dof)",
                       rep.chi2 / rep.dof, rep.dof, rep.chi2_p));
}

void judge_constants(const FitReport& rep, const VerdictLimits& L, Verdict& v) {
  const auto& names = constant_names(rep.params.model);
  if (!rep.declared_undefined.empty()) {
    std::string list;
    for (const auto& u : rep.declared_undefined)
      list += (list.empty() ? "" : ", ") + u.name;
    v.warn(fmt::format("{} constant(s) are not defined by these data ({}): {}; they are held "
                       "at the prior and carry no information from this run",
                       rep.declared_undefined.size(), list, rep.declared_undefined[0].reason));
  }
  for (std::size_t j = 0; j < names.size() && j < rep.status.size(); ++j) {
    if (rep.status[j] == "not identified") v.warn(names[j] + " is not identified: " + rep.note[j]);
    if (!rep.fitted[j] || j >= rep.std_error.size()) continue;
    const double se = rep.std_error[j], val = rep.params.k[j];
    const double ref = detail::constant_scale(rep.params, j);
    if (std::isfinite(se) && se > L.relative_error_warning * ref)
      v.warn(fmt::format("{} = {:.4g} +- {:.2g}: the standard error exceeds {:.0f} % of its "
                         "scale {:.3g} (the value, or for a damage constant the stiffness it "
                         "reduces)",
                         names[j], val, se, 100 * L.relative_error_warning, ref));
  }
  if (!rep.status.empty() && rep.status.back() == "held" &&
      rep.alpha_choice.find(" pass ") != std::string::npos)
    v.warn("alpha is held although the data pass the damage onset: a wrong alpha biases every "
           "other constant (fit it: --fit-alpha, or the automatic default)");
}

void judge_physics(const NdmParameters& p, const std::vector<ComponentFit>& curves,
                   const VerdictLimits& L, Verdict& v) {
  const Matrix6 C0 = stiffness_c0(p);
  Eigen::SelfAdjointEigenSolver<Matrix6> es(C0);
  if (!(es.eigenvalues().minCoeff() > 0)) {
    v.refuse(fmt::format("the undamaged stiffness C0 is not positive definite (smallest "
                         "eigenvalue {:.3g} Pa)",
                         es.eigenvalues().minCoeff()));
    return;
  }
  const DerivedModuli d = derive_moduli(p);
  for (auto [name, E] : {std::pair<const char*, double>{"E1", d.E1}, {"E2", d.E2}, {"E3", d.E3}})
    if (!(E >= L.modulus_min && E <= L.modulus_max))
      v.refuse(fmt::format("Young's modulus {} = {:.3g} Pa is outside [{:.3g}, {:.3g}] Pa, the "
                           "range of solid polymers and their composites",
                           name, E, L.modulus_min, L.modulus_max));
  const double nus[6] = {d.nu12, d.nu13, d.nu23, d.nu21, d.nu31, d.nu32};
  for (double nu : nus)
    if (nu < 0) {
      v.warn(
          fmt::format("a Poisson ratio is negative ({:.3g}): auxetic, unusual for a polymer", nu));
      break;
    }
  // Stress of the sign of the driven strain before the damage onset in every driven case.
  const double onset = p.alpha() * critical_stretch() - 1.0;
  // decision D12i: an onset below zero strain damages the virgin material
  if (onset < -1e-9)
    v.warn(fmt::format("alpha = {:.4g} puts the damage onset at the stretch {:.4g} < 1 (alpha < "
                       "1/lambda_c = {:.4g}): the law is damaged at zero strain, so C0 and the "
                       "derived moduli are not the material's initial stiffness (a held or given "
                       "alpha: a fitted one is bounded below by 1/lambda_c)",
                       p.alpha(), p.alpha() * critical_stretch(), 1.0 / critical_stretch()));
  for (const auto& c : curves) {
    const DeformationCase& dc = deformation_case(c.case_id);
    const int driven = single_driven(dc, "the card verdict"); // D360
    if (c.component != driven || !(onset > 0)) continue;
    Eigen::Matrix<double, 1, 6> row = case_strain(c.case_id, 0.5 * onset).transpose();
    const double s = stress_path(p, row)(0, driven);
    // along the case: a negative shear's stress is negative before damage (D424)
    if (!(driven_sense(dc) * s > 0))
      v.refuse(fmt::format("case {}: the stress {} at half the onset strain ({:.3g}) is {:.3g} "
                           "Pa, not of the sign of its strain",
                           c.case_id, component_name(driven), 0.5 * onset, s));
  }
}
} // namespace

// The scale a constant's standard error is compared with: its own value, and for a damage
// constant also the undamaged stiffness of the entries of C1 it multiplies (a damage constant
// may truly be zero, as A26 of the tables is).
double detail::constant_scale(const NdmParameters& p, std::size_t j) {
  double ref = std::abs(p.k[j]);
  const std::string& name = constant_names(p.model)[j];
  if (name[0] != 'A' && name[0] != 'B') return ref;
  NdmParameters unit;
  unit.model = p.model;
  unit.k[j] = 1.0;
  const Matrix6 C0 = stiffness_c0(p);
  for (int m = 0; m < 3; ++m) {
    const Matrix6 dC = stiffness_c1_dD(unit, m);
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b)
        if (dC(a, b) != 0.0) ref = std::max(ref, std::abs(C0(a, b)));
  }
  return ref;
}

const char* verdict_name(VerdictLevel v) {
  switch (v) {
  case VerdictLevel::usable:
    return "usable";
  case VerdictLevel::usable_with_warnings:
    return "usable with warnings";
  default:
    return "not usable";
  }
}

VerdictLevel parse_verdict(const std::string& text, const std::string& source) {
  for (VerdictLevel v :
       {VerdictLevel::usable, VerdictLevel::usable_with_warnings, VerdictLevel::not_usable})
    if (text == verdict_name(v)) return v;
  fail(source, "verdict", text, "must be 'usable', 'usable with warnings' or 'not usable'");
}

void Verdict::refuse(const std::string& why) {
  reasons.push_back("not usable: " + why);
  level = VerdictLevel::not_usable;
}

void Verdict::warn(const std::string& why) {
  reasons.push_back("warning: " + why);
  if (level == VerdictLevel::usable) level = VerdictLevel::usable_with_warnings;
}

Verdict judge_fit(const FitReport& rep, const VerdictLimits& limits) {
  Verdict v;
  judge_statistics(rep, limits, v);
  judge_constants(rep, limits, v);
  judge_physics(rep.params, rep.components, limits, v);
  return v;
}

} // namespace pnc::damage
