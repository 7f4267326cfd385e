// The fit's options and range: FitOptions::validate, alpha_mode_name and rows_in_fit_range
// (see pnc/damage/fit.hpp), split from fit.cpp.
#include "pnc/core/error.hpp"
#include "pnc/damage/fit.hpp"

#include <cmath>
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

} // namespace pnc::damage
