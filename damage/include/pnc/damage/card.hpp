#pragma once
// pnc/damage/card.hpp: the material card, the one file format that carries a fitted NDM
// from `pnc fit` to every solver (fe_material plugin, GIMP, deal.II). Format: docs/formats.md.
//
// HDF5 layout (SI units; every constant dataset has attributes `units`, `std_error`,
// `fitted`, `note`):
//   /model              attrs: law="NDM (Nair 2010)", variant="pnc"|"pp", card_version=1,
//                       decisions="docs/decisions.md D1-D12", voigt="11,22,33,23,13,12 ..."
//   /constants/<name>   scalar (Pa for C*, A*, B*; 1 for alpha)
//   /platelet_rotation  3x3, x_local = R x_global (dimensionless)
//   /fit                attrs: data_source, data_hash, stress_definition, termination,
//                       converged, iterations, initial_cost, final_cost, seconds, loss, ...
//   /verdict            attrs: level = "usable" | "usable with warnings" | "not usable",
//                       reasons (one per line; each "not usable: ..." or "warning: ...")
//   /fit                attrs also: error_model, alpha_choice, chi2, dof, chi2_p,
//                       strain_max (fit range, dimensionless; 0 = every row; D12h),
//                       rows_beyond_strain_max (rows beyond either range),
//                       stretch_max (fit range by lambda_max - 1; present when used; D12m),
//                       isotropic ("yes" when C44 and B4 were derived by isotropy; D396)
//   /fit/r2             rows: case, component (0..5), points, R^2, rms residual (Pa),
//                       chi^2 of the curve (NaN without data errors), runs, expected runs,
//                       runs-test p, lag-1 autocorrelation of the residuals
//   /fit/regression     rows: case, component, a (Pa), b (Pa), R^2; labels in
//                       /fit/regression_labels (one "lin,dam" per line)
//   /fit/solver_report  Ceres full report (text)
//   /provenance         attrs: software, created (UTC), command
#include "pnc/damage/fit.hpp"
#include "pnc/damage/ndm.hpp"

#include <limits>
#include <string>
#include <vector>

namespace pnc::damage {

struct FitRecord {
  bool present = false;
  std::string data_source, data_hash, stress_definition, termination, message, loss;
  std::string error_model, alpha_choice;
  /// fit range (D12h): largest strain component of the fitted rows, 0 = every row
  /// (dimensionless); rows of the data left out by it
  double strain_max = 0;
  int rows_beyond_strain_max = 0;
  /// fit range by stretch (D12m): largest lambda_max - 1 of the fitted rows, 0 = none
  double stretch_max = 0;
  /// fit option isotropic (D396): C44 and B4 derived, C44 = (C11 - C12)/2, B4 = B1 - B2/2
  bool isotropic = false;
  /// the law's shape error (D417): the 97.5 % bound of the residual trend common to the
  /// replicas, as a share of its curve's stress, largest over the curves (the pure polymer's:
  /// over its pooled roles, D397) (dimensionless; NaN: not tested, fewer than 3 replicas or not
  /// MD data)
  double shape_error = std::numeric_limits<double>::quiet_NaN();
  double chi2 = std::numeric_limits<double>::quiet_NaN(), chi2_p = chi2;
  int dof = 0;
  bool converged = false;
  int iterations = 0, residuals = 0, free_parameters = 0;
  double initial_cost = 0, final_cost = 0, seconds = 0;
  std::vector<ComponentFit> components;
  std::vector<RegressionLine> regression;
  std::string solver_report, warnings;
};

struct Card {
  NdmParameters params;            ///< SI (Pa), alpha dimensionless
  std::vector<double> std_error;   ///< per constant, SI; NaN if not fitted
  std::vector<bool> fitted;        ///< per constant
  std::vector<std::string> status; ///< per constant: fitted, derived, held, not identified,
                                   ///< at bound, given
  std::vector<std::string> note;   ///< per constant
  FitRecord fit;
  /// Quality verdict. Cards of version 1 (written before verdicts) read as "usable with
  /// warnings" with that reason; cards of given constants are "usable".
  Verdict verdict;
  std::string software, created, command;
};

/// A card straight from constants (no fit record): every constant marked as given.
Card card_from_parameters(const NdmParameters& p, const std::string& note);
/// A card from a fit.
Card card_from_fit(const FitReport& rep, const StressStrainData& data, const std::string& loss);
/// Writes atomically (temporary file + rename): a failure leaves no partial card.
void write_card(const std::string& path, Card card, const std::string& command);
/// Reads and validates (pnc::damage::validate): errors name the file and the dataset.
Card read_card(const std::string& path);

} // namespace pnc::damage
