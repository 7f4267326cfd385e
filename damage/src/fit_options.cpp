// The fit's options and range: FitOptions::validate, alpha_mode_name, rows_in_fit_range (see
// pnc/damage/fit.hpp), the rows within the range and the plausible-stiffness check
// (fit_model.hpp), split from fit.cpp.
#include "fit_model.hpp"
#include "pnc/core/error.hpp"
#include "pnc/damage/fit.hpp"

#include <fmt/format.h>

#include <cmath>
#include <sstream>
#include <string>

namespace pnc::damage {

const char* alpha_mode_name(AlphaMode m) {
  switch (m) {
  case AlphaMode::fit:
    return "fit";
  case AlphaMode::hold:
    return "hold";
  default:
    return "automatic";
  }
}

// ------------------------------------------------------------------ options
void FitOptions::validate() const {
  const std::string src = "<fit options>";
  if (loss != "none" && loss != "huber" && loss != "cauchy")
    fail(src, "loss", loss, "must be one of none, huber, cauchy");
  if (!(loss_scale > 0) || !std::isfinite(loss_scale))
    fail(src, "loss_scale", std::to_string(loss_scale), "must be a finite number > 0");
  if (max_iterations <= 0)
    fail(src, "max_iterations", std::to_string(max_iterations), "must be > 0");
  if (!(function_tolerance > 0 && function_tolerance < 1))
    fail(src, "function_tolerance", std::to_string(function_tolerance), "must be in (0, 1)");
  if (alpha && !(*alpha >= 0.5 && *alpha <= 1.5))
    fail(src, "alpha", std::to_string(*alpha), "must be in [0.5, 1.5]");
  if (!(strain_max >= 0 && strain_max <= 10))
    fail(src, "strain_max", std::to_string(strain_max),
         "must be in [0, 10] (0 = every row; a strain, dimensionless)");
  if (!(stretch_max >= 0 && stretch_max <= 10))
    fail(src, "stretch_max", std::to_string(stretch_max),
         "must be in [0, 10] (0 = every row; lambda_max - 1, dimensionless)");
  if (strain_max > 0 && stretch_max > 0)
    fail(src, "stretch_max", std::to_string(stretch_max),
         "strain_max and stretch_max exclude each other (one fit range)");
  if (!(stiffness_min > 0) || !(stiffness_max > stiffness_min) || !std::isfinite(stiffness_max))
    fail(src, "stiffness range",
         std::to_string(stiffness_min) + ".." + std::to_string(stiffness_max),
         "must satisfy 0 < min < max < infinity (Pa)");
  if (prior && prior->model != model)
    fail(src, "prior", model_name(prior->model),
         std::string("prior card is for another model than ") + model_name(model));
  if (isotropic && model != Model::pp)
    fail(src, "isotropic", "true",
         std::string("the isotropy ties (C44 = (C11 - C12)/2, B4 = B1 - B2/2) are of the pure "
                     "polymer model pp, not of ") +
             model_name(model) + " (D396)");
  for (const auto& u : undefined) {
    if (constant_index(model, u.name) < 0)
      fail(src, "undefined", u.name, std::string("not a constant of model ") + model_name(model));
    if (u.reason.empty()) fail(src, "undefined." + u.name, "", "needs a reason");
  }
}

Eigen::Index rows_in_fit_range(const PathMatrix& strain, double strain_max, double stretch_max) {
  constexpr double slack = 1 + 1e-12; // a row written at the bound stays inside it
  Eigen::Index n = 0;
  for (; n < strain.rows(); ++n) {
    if (strain_max > 0 && strain.row(n).cwiseAbs().maxCoeff() > strain_max * slack) break;
    if (stretch_max > 0) {
      const Voigt e = strain.row(n).transpose();
      if (mode_stretches(Model::pp, e, false).lambda_max - 1 > stretch_max * slack) break;
    }
  }
  return n;
}

namespace fitmodel {
/// The leading rows of every curve within the fit range (decisions D12h, D12m); counts the others.
StressStrainData within_fit_range(const StressStrainData& all, double strain_max,
                                  double stretch_max, int& dropped) {
  dropped = 0;
  if (!(strain_max > 0) && !(stretch_max > 0)) return all;
  StressStrainData d = all;
  for (auto& c : d.cases) {
    const Eigen::Index keep = rows_in_fit_range(c.strain, strain_max, stretch_max);
    if (keep < 3)
      fail(all.source, fmt::format("case {}", c.id), fmt::format("{} row(s)", keep),
           fmt::format("fit range {} = {:g} leaves fewer than 3 rows of this case to fit",
                       strain_max > 0 ? "strain_max" : "stretch_max",
                       strain_max > 0 ? strain_max : stretch_max));
    dropped += static_cast<int>(c.strain.rows() - keep);
    c.strain.conservativeResize(keep, Eigen::NoChange);
    c.stress.conservativeResize(keep, Eigen::NoChange);
    if (c.stress_stderr.rows() > 0) c.stress_stderr.conservativeResize(keep, Eigen::NoChange);
  }
  return d;
}

// Refuses stiffnesses outside the plausible range (D12e): a unit mistake is the likely cause.
void check_stiffness_units(const FitReport& rep, const FitOptions& opt, const std::string& src) {
  const auto& names = constant_names(opt.model);
  for (std::size_t j = 0; j + 1 < names.size(); ++j) {
    const std::string& nm = names[j];
    const bool diagonal =
        nm == "C11" || nm == "C22" || nm == "C33" || nm == "C44" || nm == "C55" || nm == "C66";
    if (!diagonal || !rep.fitted[j]) continue;
    const double v = rep.params.k[j];
    if (v >= opt.stiffness_min && v <= opt.stiffness_max) continue;
    std::ostringstream msg;
    msg << "fitted stiffness " << v / 1e9 << " GPa is outside the plausible range ["
        << opt.stiffness_min / 1e6 << " MPa, " << opt.stiffness_max / 1e9
        << " GPa] of polymers and composites: "
        << (v > opt.stiffness_max
                ? "are the stresses in Pa instead of MPa (CSV columns s11_MPa.., and the "
                  "bare s11.. of older files, are MPa)?"
                : "are the stresses in GPa or kPa instead of MPa (or MPa values under "
                  "s11_Pa..), or is the data noise?")
        << " (check the units, or pass --no-unit-check)";
    fail(src, nm, std::to_string(v) + " Pa", msg.str());
  }
}

} // namespace fitmodel

} // namespace pnc::damage
