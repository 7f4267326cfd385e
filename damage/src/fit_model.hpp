#pragma once
// The NDM fit's model side (internal to pnc::damage): the theta <-> constants map (decision
// D10), one residual term per data point with its analytic Jacobian (D11, D12), and the
// dissertation's per-case regression labels. fit.cpp drives Ceres and the statistics.
#include "pnc/damage/fit.hpp"

#include <Eigen/Dense>

#include <vector>

namespace pnc::damage::fitmodel {

constexpr double kMPa = 1e6;

/// Sizes of the Ceres parameter blocks of theta: pnc {C_n Cholesky 6, shear 3, A 12, alpha},
/// pp {u v 2, shear 1, B 3, alpha}.
std::vector<int> block_sizes(Model m);
int n_theta(Model m);
NdmParameters params_from_constants(Model m, const std::vector<double>& k);

/// Isotropy ties of the pure polymer (decision D396): the constants that FitOptions::isotropic
/// derives from others, C44 = (C11 - C12) / 2 and B4 = B1 - B2 / 2, as indices into
/// constant_names(pp); empty for pnc or without the option.
std::vector<int> isotropy_ties(Model m, bool isotropic);
/// T (n x n) with k_tied = T k: the identity but for the rows of the `tied` constants, which
/// take their linear combination of the others. For tests and the fit's chain rule.
Eigen::MatrixXd tie_matrix(Model m, const std::vector<int>& tied);
/// The ties of `opt` that apply: isotropy_ties without the constants the caller declares
/// undefined (those are held at the prior, not derived).
std::vector<int> applicable_ties(Model m, const FitOptions& opt);
/// Before the solve: the tied constants are not free (fitted = false), status "derived", the
/// note says from what; they leave `held_at_onset` (their column is zero by construction).
void mark_derived(const std::vector<int>& tied, FitReport& rep, std::vector<int>& held_at_onset);
/// After the solve: a derived constant carries a propagated standard error (fitted = true)
/// when every constant it is derived from was fitted; else its note says it follows held ones.
void finish_derived(Model m, const std::vector<int>& tied, FitReport& rep);

/// One data point of one case: the state before it, its strain increment, the fitted
/// components, the data (MPa) and the scale each residual is divided by (MPa).
struct PointTerm {
  Model model;
  int case_id;
  std::vector<int> comps;
  NdmState s0;
  Voigt eps0, deps;
  Voigt data;  // MPa
  Voigt scale; // MPa
};

/// Residuals of one point and d r / d constants (rows x n), constants in MPa (alpha: 1).
void point_residual(const PointTerm& t, const std::vector<double>& k, double* r,
                    Eigen::MatrixXd* dr_dk);
/// Terms of every point of `data`; states from a path driven at `alpha_for_states` (kappa
/// does not depend on the constants). Scales: the data's standard errors where positive,
/// else their median per case and component, else 1 MPa.
std::vector<PointTerm> build_terms(const StressStrainData& data, Model m, double alpha_for_states);
/// True when every fitted component of every point has a positive standard error in the data.
bool data_has_errors(const StressStrainData& data);
/// Throws pnc::InputError for cases the model does not have or needs.
void check_cases(const StressStrainData& data, Model m);

/// The leading rows of every curve within the fit range (decisions D12h, D12m); counts the
/// others in `dropped`. Throws pnc::InputError when a case keeps fewer than 3 rows.
StressStrainData within_fit_range(const StressStrainData& all, double strain_max,
                                  double stretch_max, int& dropped);
/// Refuses fitted diagonal stiffnesses outside opt's plausible range (D12e), naming `src`.
void check_stiffness_units(const FitReport& rep, const FitOptions& opt, const std::string& src);

struct LabelPair {
  const char* lin;
  const char* dam;
};
LabelPair regression_labels(Model m, int case_id, int comp);
double r_squared(const Eigen::VectorXd& y, const Eigen::VectorXd& yhat);

} // namespace pnc::damage::fitmodel

namespace pnc::damage::detail {
/// constants_from_theta() and dconstants_dtheta() (pnc/damage/fit.hpp) with the tie matrix
/// formed once by the caller: T = tie_matrix(m, tied), or an empty matrix when nothing is tied
/// (what the cost function evaluates at every residual).
std::vector<double> constants_from_theta(Model m, const std::vector<double>& th,
                                         const Eigen::MatrixXd& T);
Eigen::MatrixXd dconstants_dtheta(Model m, const std::vector<double>& th, const Eigen::MatrixXd& T);
} // namespace pnc::damage::detail
