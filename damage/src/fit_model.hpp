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

struct LabelPair {
  const char* lin;
  const char* dam;
};
LabelPair regression_labels(Model m, int case_id, int comp);
double r_squared(const Eigen::VectorXd& y, const Eigen::VectorXd& yhat);

} // namespace pnc::damage::fitmodel
