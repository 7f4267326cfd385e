#pragma once
// pnc/damage/fit.hpp: joint nonlinear least-squares fit of the NDM to stress-strain curves
// of the deformation cases, with Ceres (the toolkit's improvement over the dissertation's
// case-by-case linear regression, which is kept as a cross-check and as the initial guess).
//
// Units: data in Pa (pnc::damage::StressStrainData); the solve works in MPa; results
// (FitReport::params, stderr) are in Pa again.
//
// Parameterisation (decision D10): the 3x3 normal block of C0 is C_n = L L^T with a lower
// triangular L whose diagonal is bounded below, so C0 stays positive definite during the
// solve (pp: C11 - C12 > 0 and C11 + 2 C12 > 0); shear stiffnesses are bounded below by a
// positive number; A/B constants are free; alpha (optional) is bounded to [0.5, 1.5].
// Every residual is evaluated by pnc::damage::integrate() along the case's strain path.
//
// Honesty of the result (decisions D11, D12b-D12e): standard errors from the data's own
// per-point errors when every fitted point has one (else a heteroscedasticity-consistent
// sandwich estimate), chi^2/dof against those errors, a runs test on the residuals of every
// fitted curve, identifiability of every constant at the solution (constants the data do
// not determine are held at the prior and say why), and a verdict (verdict.hpp).
#include "pnc/damage/data.hpp"
#include "pnc/damage/ndm.hpp"
#include "pnc/damage/verdict.hpp"

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace pnc::damage {

/// How alpha (the critical-stretch factor) is treated. `automatic` fits it when the data pass
/// the damage onset of the starting alpha somewhere (a held alpha then biases every other
/// constant, D12b) and holds it otherwise; `fit` always fits it; `hold` never does.
enum class AlphaMode { automatic, fit, hold };
const char* alpha_mode_name(AlphaMode m);

/// A constant the caller knows the data cannot define (e.g. the shear and damage constants of
/// a material that relaxes within a strain hold, pnc/rve/phase_check.hpp), with the reason.
struct UndefinedConstant {
  std::string name;   ///< constant name of the model (constant_names), e.g. "C44", "alpha"
  std::string reason; ///< shown in the card's note and in the verdict
};

struct FitOptions {
  Model model = Model::pnc;
  AlphaMode alpha_mode = AlphaMode::automatic;
  std::optional<double> alpha;       ///< alpha to use / start from; default: the dissertation's
  std::string loss = "none";         ///< "none", "huber" or "cauchy"
  double loss_scale = 1.0;           ///< robust-loss scale, in units of the residual (MPa or sd)
  int max_iterations = 200;          ///< > 0
  double function_tolerance = 1e-12; ///< in (0, 1)
  /// Values for constants the data cannot determine (a missing shear case, damage never
  /// reached). Default: the dissertation's constants (pnc::damage::dissertation_parameters).
  std::optional<NdmParameters> prior;
  std::string prior_source = "dissertation tables 6.6-6.11";
  /// Plausible range (Pa) of the fitted diagonal stiffnesses C11..C66 of polymers and their
  /// composites; a fit outside it is refused as a probable unit mistake (stress in Pa given
  /// as MPa gives 1e6 times the stiffness) unless check_units is false (D12e).
  double stiffness_min = 1e5;  ///< 0.1 MPa
  double stiffness_max = 1e12; ///< 1000 GPa
  bool check_units = true;
  /// Constants declared undefined by the data: held at the prior (alpha: at its start value)
  /// with status "not identified" and the reason; the verdict warns and says why.
  std::vector<UndefinedConstant> undefined;
  /// Fit range (decision D12h): only the leading rows of every curve whose largest strain
  /// component |e| (engineering shear) is at most strain_max are fitted; 0 = every row.
  /// Dimensionless. The card records it: beyond it the law is extrapolated.
  double strain_max = 0;
  /// Fit range by stretch (decision D12m), exclusive with strain_max: only the leading rows of
  /// every curve whose largest principal stretch minus one, lambda_max - 1 of docs/theory.md
  /// eq. (1.4), is at most stretch_max are fitted; 0 = every row. Dimensionless. The same
  /// bound admits a normal strain e and a simple shear gamma ~ 2 e: the range the damage
  /// driver sees, whatever the case.
  double stretch_max = 0;
  /// Pure polymer only (decision D396): an isotropic solid with isotropic damage. C44 and B4
  /// are not fitted but derived, C44 = (C11 - C12) / 2 and B4 = B1 - B2 / 2 (status "derived",
  /// standard errors propagated from C11, C12, B1, B2), so that the damaged stiffness
  /// C0 + D C1 stays isotropic. Off: the cubic reading with C44 and B4 free (docs/theory.md
  /// section 1.1). A constant in `undefined` is held, not derived.
  bool isotropic = false;

  /// Throws pnc::InputError naming the option and the constraint it breaks.
  void validate() const;
};

struct ComponentFit {
  int case_id;
  int component; ///< Voigt index 0..5
  int points;
  double r2;  ///< 1 - SS_res / SS_tot of the joint fit
  double rms; ///< root-mean-square residual, Pa
  /// sum of squared standardised residuals of this curve (NaN without data errors)
  double chi2 = std::numeric_limits<double>::quiet_NaN();
  int runs = 0;             ///< runs of one residual sign, in loading order
  double runs_expected = 0; ///< expected runs for independent residuals
  double runs_p = 1.0;      ///< P(this few runs or fewer | independent residuals)
  double lag1 = 0;          ///< lag-1 autocorrelation of the residuals
};

/// One line of the dissertation-style per-case linear regression
/// sigma_i = a * eps_drive + b * D * eps_drive (Tables 6.6-6.11).
struct RegressionLine {
  int case_id;
  int component;
  std::string linear_label; ///< C0 entry that a estimates, e.g. "C12"
  std::string damage_label; ///< C1 coefficient that b estimates, e.g. "A10", "2A1"
  double a;                 ///< Pa
  double b;                 ///< Pa; NaN when the data never reach damage onset
  double r2;
};

struct FitReport {
  NdmParameters params;          ///< fitted constants, Pa
  std::vector<double> std_error; ///< per constant, Pa (alpha: 1); NaN if held
  std::vector<bool> fitted;      ///< false: held at the prior (see note)
  /// per constant: "fitted", "derived" (from fitted ones by isotropy, D396), "held" (by option
  /// or for lack of data), "at bound" (alpha, D12i) or "not identified"
  /// (the data do not determine it: held at the prior)
  std::vector<std::string> status;
  std::vector<std::string> note; ///< why a constant was held, per constant
  std::string alpha_choice;      ///< how alpha was treated and why
  /// FitOptions::strain_max of the fit (0 = every row), and the rows left out by it
  double strain_max = 0;
  int rows_beyond_strain_max = 0;
  double stretch_max = 0; ///< FitOptions::stretch_max (rows beyond it are counted above too)
  bool isotropic = false; ///< FitOptions::isotropic: C44 and B4 derived (D396)
  /// the caller's FitOptions::undefined, as given (names and reasons)
  std::vector<UndefinedConstant> declared_undefined;
  /// "data standard errors" or "sandwich (HC3)": where the standard errors come from
  std::string error_model;
  double chi2 = std::numeric_limits<double>::quiet_NaN();   ///< sum of r^2 (data errors only)
  int dof = 0;                                              ///< residuals - free parameters
  double chi2_p = std::numeric_limits<double>::quiet_NaN(); ///< P(chi^2_dof >= chi2)
  Verdict verdict;                                          ///< judge_fit() of this report
  std::vector<ComponentFit> components;
  std::vector<RegressionLine> regression;
  // how the solve ended
  bool converged = false;
  std::string termination;  ///< Ceres termination type
  std::string message;      ///< Ceres message
  std::string brief_report; ///< Ceres BriefReport
  std::string full_report;  ///< Ceres FullReport
  int iterations = 0;
  double initial_cost = 0, final_cost = 0; ///< Ceres cost (1/2 sum r^2), r in MPa or sd
  double seconds = 0;
  int residuals = 0;
  int free_parameters = 0;
  std::string warnings; ///< e.g. singular covariance
};

/// Fit. Throws pnc::InputError for data the model cannot use (a missing extension case, a
/// case the model does not have, too few points).
FitReport fit_ndm(const StressStrainData& data, const FitOptions& options);

/// The number of leading rows of a strain path inside the fit range: every strain component
/// |e| <= strain_max (when > 0) and lambda_max - 1 <= stretch_max (when > 0); all rows when
/// both are 0 (decisions D12h, D12m). One rule for the fit and everything that judges it.
Eigen::Index rows_in_fit_range(const PathMatrix& strain, double strain_max, double stretch_max);

/// The dissertation's per-case linear regressions alone (cross-check).
std::vector<RegressionLine> regress_cases(const StressStrainData& data, Model model, double alpha);

namespace detail {
/// Flat parameter vector theta (MPa) <-> constants (MPa); see decision D10. `tied`: the
/// constants derived from others (isotropy, D396; indices into constant_names), whose theta
/// coordinates are then unused.
std::vector<double> theta_from_constants(Model m, const std::vector<double>& k);
std::vector<double> constants_from_theta(Model m, const std::vector<double>& theta,
                                         const std::vector<int>& tied = {});
/// G = d constants / d theta.
Eigen::MatrixXd dconstants_dtheta(Model m, const std::vector<double>& theta,
                                  const std::vector<int>& tied = {});
/// Residuals (MPa or in units of the data sd) and their analytic Jacobian w.r.t. theta over
/// all points of `data`, exactly as the Ceres cost functions compute them (for tests).
void residuals_and_jacobian(const StressStrainData& data, Model m, const std::vector<double>& theta,
                            Eigen::VectorXd& r, Eigen::MatrixXd* J,
                            const std::vector<int>& tied = {});
} // namespace detail

} // namespace pnc::damage
