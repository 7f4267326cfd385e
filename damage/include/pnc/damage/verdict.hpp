#pragma once
// pnc/damage/verdict.hpp: the quality verdict every material card carries.
//
// A card is `usable`, `usable with warnings` or `not usable`, with one sentence per reason.
// `pnc fit` and `pnc characterize` exit with code 4 for a `not usable` card (written all the
// same, marked); `pnc card show` and the reports print the verdict; the fe_material plugin
// refuses a `not usable` card unless the host asks for it explicitly. The rules and their
// thresholds are decision D12d (docs/decisions.md); VerdictLimits holds the thresholds.
#include "pnc/damage/ndm.hpp"

#include <string>
#include <vector>

namespace pnc::damage {

enum class VerdictLevel { usable = 0, usable_with_warnings = 1, not_usable = 2 };
/// "usable", "usable with warnings", "not usable".
const char* verdict_name(VerdictLevel v);
/// Inverse of verdict_name; throws pnc::InputError naming `source` otherwise.
VerdictLevel parse_verdict(const std::string& text, const std::string& source);

struct Verdict {
  VerdictLevel level = VerdictLevel::usable;
  /// One sentence per finding, each starting with "not usable: " or "warning: ".
  std::vector<std::string> reasons;
  void refuse(const std::string& why);
  void warn(const std::string& why);
};

/// Thresholds of the verdict (dimensionless unless stated).
struct VerdictLimits {
  double r2_not_usable = 0.0; ///< a fitted curve with R^2 below: worse than its mean
  double r2_warning = 0.9;    ///< below: the curve is poorly described
  double p_misfit = 1e-3;     ///< family-wise level of the chi^2 and runs tests
  /// false: the residuals are correlated along the curves (replica-mean MD curves), so the
  /// runs test and the chi^2 p-value, which assume independent residuals, are not applied;
  /// the caller tests misfit another way (pnc::rve::replica_trend_test, decision D12k)
  bool independent_residuals = true;
  /// standard error above this fraction of the constant's scale (|value|, or for a damage
  /// constant the largest undamaged stiffness it reduces)
  double relative_error_warning = 0.5;
  double modulus_min = 1e6;  ///< Pa; a Young's modulus below is no solid polymer
  double modulus_max = 1e12; ///< Pa
};

struct FitReport;        // fit.hpp
struct StressStrainData; // data.hpp

/// What "usable" means for a card fitted to molecular-dynamics data (`pnc characterize`,
/// decision D12f). A card passes only when every driven curve has `min_linear_points` points
/// before the damage onset, every fitted constant has a standard error within
/// `max_relative_error` of its scale, the point errors come from at least `min_replicas`
/// independent replicas, and chi^2/dof against those errors lies in [chi2_dof_min,
/// chi2_dof_max]; each gate that fails is a warning (the card stays loadable, marked
/// "usable with warnings"). R^2 >= VerdictLimits::r2_warning is judged by judge_fit already.
struct MdCardGates {
  int replicas = 1;                 ///< independent replicas behind the point errors (input)
  int min_replicas = 4;             ///< fewer: errors of one structure (thermal noise only)
  int min_linear_points = 8;        ///< per driven curve, before the fitted damage onset
  double max_relative_error = 0.10; ///< standard error / the constant's scale
  double chi2_dof_min = 0.5;        ///< below: errors too large (or correlated points)
  double chi2_dof_max = 2.0;        ///< above: the model or the errors are wrong
  /// the law's shape error (the 97.5 % bound of the residual trend common to the replicas, as
  /// a fraction of its curve's stress) above this is a warning, whether the misfit test
  /// resolves the trend or not (applied by pnc::rve::judge_replica_trend; decision D417): the
  /// same 10 % as max_relative_error
  double max_shape_error = 0.10;
  /// static (0 K) data have no noise: the replica and chi^2 gates do not apply
  bool deterministic = false;
};

/// The verdict of a fit: from R^2 per curve, chi^2/dof and its p-value, the runs tests,
/// identifiability, the solver's termination, and physical checks (C0 positive definite,
/// Young's moduli in [modulus_min, modulus_max], Poisson ratios, tensile stress positive
/// before the damage onset in every driven case).
Verdict judge_fit(const FitReport& report, const VerdictLimits& limits = {});

/// Adds the MD gates (MdCardGates) to `v`, from the fit and the data it was fitted to.
void judge_md_card(const FitReport& report, const StressStrainData& data, const MdCardGates& gates,
                   Verdict& v);

namespace detail {
/// The scale a constant's standard error is compared with: |value|, and for a damage constant
/// at least the largest undamaged stiffness of the C1 entries it multiplies.
double constant_scale(const NdmParameters& p, std::size_t j);
} // namespace detail

} // namespace pnc::damage
