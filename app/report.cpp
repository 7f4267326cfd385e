#include "report.hpp"

#include "pnc/damage/reference.hpp"

#include <fmt/format.h>

#include <cmath>

namespace pnc::app {

namespace {
const char* kComp[6] = {"11", "22", "33", "23", "13", "12"};
}

nlohmann::json num(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

double display_value(const std::string& name, double si) {
  return name == "alpha" ? si : si / 1e9;
}
const char* display_units(const std::string& name) {
  return name == "alpha" ? "" : "GPa";
}

std::string constants_table(const damage::Card& c) {
  std::string s = fmt::format("  {:<6} {:>12} {:>11}  {:<5} {}\n", "const", "value", "std.err",
                              "units", "status");
  const auto& names = damage::constant_names(c.params.model);
  for (std::size_t i = 0; i < names.size(); ++i) {
    const double v = display_value(names[i], c.params.k[i]);
    const double e = display_value(names[i], c.std_error[i]);
    const std::string err =
        std::isfinite(e) ? fmt::format("{:11.4g}", e) : fmt::format("{:>11}", "-");
    s += fmt::format("  {:<6} {:12.5g} {}  {:<5} {}{}\n", names[i], v, err, display_units(names[i]),
                     i < c.status.size() ? c.status[i] : (c.fitted[i] ? "fitted" : "held"),
                     c.note[i].empty() ? "" : ": " + c.note[i]);
  }
  return s;
}

std::string verdict_text(const damage::Verdict& v) {
  std::string s = fmt::format("  verdict: {}\n", damage::verdict_name(v.level));
  for (const auto& r : v.reasons)
    s += "    - " + r + "\n";
  return s;
}

nlohmann::json verdict_json(const damage::Verdict& v) {
  return {{"level", damage::verdict_name(v.level)}, {"reasons", v.reasons}};
}

nlohmann::json constants_json(const damage::Card& c) {
  nlohmann::json j = nlohmann::json::object();
  const auto& names = damage::constant_names(c.params.model);
  for (std::size_t i = 0; i < names.size(); ++i) {
    j[names[i]] = {{"value", c.params.k[i]},
                   {"std_error", num(c.std_error[i])},
                   {"units", names[i] == "alpha" ? "1" : "Pa"},
                   {"fitted", static_cast<bool>(c.fitted[i])},
                   {"status", i < c.status.size() ? c.status[i] : ""},
                   {"note", c.note[i]}};
  }
  return j;
}

std::string fit_tables(const damage::FitRecord& f, damage::Model m) {
  std::string s = "  fit quality (joint NDM fit):\n";
  s += fmt::format("    standard errors from: {}; alpha {}\n", f.error_model, f.alpha_choice);
  if (f.stretch_max > 0) // decision D12m
    s += fmt::format("    fit range: rows with largest principal stretch - 1 <= {:g} ({} row(s) "
                     "beyond it not fitted; the law is extrapolated there)\n",
                     f.stretch_max, f.rows_beyond_strain_max);
  if (f.isotropic) // decision D396
    s += "    isotropic: C44 = (C11 - C12)/2 and B4 = B1 - B2/2 derived from the fitted "
         "constants, not fitted\n";
  if (f.strain_max > 0) // decision D12h
    s += fmt::format("    fit range: rows with every strain component <= {:g} ({} row(s) beyond it "
                     "not fitted; the law is extrapolated there)\n",
                     f.strain_max, f.rows_beyond_strain_max);
  if (std::isfinite(f.chi2) && f.dof > 0)
    s += fmt::format("    chi^2/dof = {:.4g} ({} dof), P(chi^2 >= observed) = {:.3g}\n",
                     f.chi2 / f.dof, f.dof, f.chi2_p);
  if (!std::isnan(f.shape_error)) // decision D417
    s += fmt::format(
        "    shape error of the law: the residual trend common to the replicas "
        "stays below {:.3g} % of its curve's stress (97.5 % bound, largest curve or pooled "
        "role)\n",
        100 * f.shape_error);
  for (const auto& c : f.components)
    s += fmt::format("    case {} sigma{}: R^2 = {:.4f}, rms residual = {:.3g} MPa ({} points), "
                     "runs {} (expected {:.1f}, p = {:.2g}), lag-1 autocorrelation {:.2f}\n",
                     c.case_id, kComp[c.component], c.r2, c.rms / 1e6, c.points, c.runs,
                     c.runs_expected, c.runs_p, c.lag1);
  s += "  per-case linear regression sigma_i = a eps + b D eps (dissertation's method), GPa:\n";
  for (const auto& l : f.regression) {
    std::string printed;
    for (const auto& p : damage::printed_regression(m)) {
      if (p.case_id == l.case_id && p.component == l.component)
        printed = fmt::format("   [printed: {} = {:.4g}, {} = {:.4g}]", p.lin_label,
                              p.lin_value / 1e9, p.dam_label, p.dam_value / 1e9);
    }
    const std::string b = std::isfinite(l.b) ? fmt::format("{:.4g}", l.b / 1e9) : "n/a (no damage)";
    s += fmt::format("    case {} sigma{}: {} = {:.4g}, {} = {}, R^2 = {:.4f}{}\n", l.case_id,
                     kComp[l.component], l.linear_label, l.a / 1e9, l.damage_label, b, l.r2,
                     printed);
  }
  return s;
}

nlohmann::json fit_json(const damage::FitRecord& f) {
  nlohmann::json j;
  j["converged"] = f.converged;
  j["termination"] = f.termination;
  j["iterations"] = f.iterations;
  j["initial_cost"] = num(f.initial_cost);
  j["final_cost"] = num(f.final_cost);
  j["solve_time_s"] = num(f.seconds); // wall time of the Ceres solve
  j["residuals"] = f.residuals;
  j["free_parameters"] = f.free_parameters;
  j["warnings"] = f.warnings;
  j["error_model"] = f.error_model;
  j["alpha_choice"] = f.alpha_choice;
  j["strain_max"] = f.strain_max; // dimensionless, 0 = every row (D12h)
  j["rows_beyond_strain_max"] = f.rows_beyond_strain_max;
  j["stretch_max"] = f.stretch_max; // lambda_max - 1, dimensionless, 0 = none (D12m)
  j["isotropic"] = f.isotropic;     // C44 and B4 derived by isotropy (D396)
  // the 97.5 % bound of the replicas' common residual trend / its curve's stress,
  // dimensionless, null = not tested (D417)
  j["shape_error"] = num(f.shape_error);
  j["chi2"] = num(f.chi2);
  j["dof"] = f.dof;
  j["chi2_p"] = num(f.chi2_p);
  j["r2"] = nlohmann::json::array();
  for (const auto& c : f.components)
    j["r2"].push_back({{"case", c.case_id},
                       {"component", kComp[c.component]},
                       {"r2", num(c.r2)},
                       {"rms_Pa", num(c.rms)},
                       {"chi2", num(c.chi2)},
                       {"runs", c.runs},
                       {"runs_expected", num(c.runs_expected)},
                       {"runs_p", num(c.runs_p)},
                       {"lag1", num(c.lag1)}});
  j["regression"] = nlohmann::json::array();
  for (const auto& l : f.regression)
    j["regression"].push_back({{"case", l.case_id},
                               {"component", kComp[l.component]},
                               {l.linear_label, num(l.a)},
                               {l.damage_label, num(l.b)},
                               {"r2", num(l.r2)}});
  return j;
}

} // namespace pnc::app
