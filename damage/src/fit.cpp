// Joint NDM fit with Ceres: see pnc/damage/fit.hpp and docs/decisions.md D10-D12e.
#include "pnc/damage/fit.hpp"

#include "fit_model.hpp"
#include "fit_statistics.hpp"
#include "pnc/core/error.hpp"
#include "pnc/damage/reference.hpp"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

namespace pnc::damage {

using namespace fitmodel;

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();

class PointCost final : public ceres::CostFunction {
public:
  /// T: the tie matrix of the derived constants (D396; empty: none), formed once per solve
  PointCost(const PointTerm* t, const Eigen::MatrixXd* T) : t_(t), T_(T) {
    set_num_residuals(static_cast<int>(t->comps.size()));
    for (int s : block_sizes(t->model))
      mutable_parameter_block_sizes()->push_back(s);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const auto sizes = block_sizes(t_->model);
    std::vector<double> theta;
    for (std::size_t b = 0; b < sizes.size(); ++b)
      theta.insert(theta.end(), parameters[b], parameters[b] + sizes[b]);
    const std::vector<double> k = detail::constants_from_theta(t_->model, theta, *T_);
    Eigen::MatrixXd drdk;
    const bool want = jacobians != nullptr;
    try {
      point_residual(*t_, k, residuals, want ? &drdk : nullptr);
    } catch (const std::exception&) {
      return false;
    }
    if (!want) return true;
    const Eigen::MatrixXd J = drdk * detail::dconstants_dtheta(t_->model, theta, *T_);
    int col0 = 0;
    for (std::size_t b = 0; b < sizes.size(); ++b) {
      if (jacobians[b]) {
        for (Eigen::Index r = 0; r < J.rows(); ++r)
          for (int c = 0; c < sizes[b]; ++c)
            jacobians[b][r * sizes[b] + c] = J(r, col0 + c);
      }
      col0 += sizes[b];
    }
    return true;
  }

private:
  const PointTerm* t_;
  const Eigen::MatrixXd* T_;
};

// The fitted alpha's lower bound (decision D12i): 1/lambda_c, the onset at zero strain, so
// that the virgin state (kappa = 1) is undamaged and C0 is the material's initial stiffness.
double alpha_lower_bound() {
  return std::max(0.5, 1.0 / critical_stretch());
}

struct SolveResult {
  ceres::Solver::Summary summary;
  double seconds = 0;
};

// One Ceres solve from `theta` with the constants whose `fitted` flag is false held.
SolveResult solve(const std::vector<PointTerm>& terms, Model m, const FitOptions& opt,
                  const std::vector<int>& tied, const std::vector<bool>& fitted, bool fit_alpha,
                  std::vector<double>& theta) {
  const auto sizes = block_sizes(m);
  std::vector<std::vector<double>> blocks;
  int off = 0;
  for (int s : sizes) {
    blocks.emplace_back(theta.begin() + off, theta.begin() + off + s);
    off += s;
  }
  // decision D12i: a fitted alpha starts inside its bounds
  if (fit_alpha) blocks[3][0] = std::clamp(blocks[3][0], alpha_lower_bound(), 1.5);
  const Eigen::MatrixXd T = tied.empty() ? Eigen::MatrixXd() : tie_matrix(m, tied); // D396
  ceres::Problem problem;
  std::vector<double*> ptrs;
  for (auto& b : blocks)
    ptrs.push_back(b.data());
  for (const auto& t : terms) {
    ceres::LossFunction* loss = nullptr;
    if (opt.loss == "huber") loss = new ceres::HuberLoss(opt.loss_scale);
    if (opt.loss == "cauchy") loss = new ceres::CauchyLoss(opt.loss_scale);
    problem.AddResidualBlock(new PointCost(&t, &T), loss, ptrs);
  }
  // Held coordinates: every block other than the normal block maps 1:1 to constants.
  off = 0;
  for (std::size_t b = 0; b < sizes.size(); ++b) {
    std::vector<int> held;
    for (int c = 0; c < sizes[b]; ++c)
      if (!fitted[static_cast<std::size_t>(off + c)]) held.push_back(c);
    if (static_cast<int>(held.size()) == sizes[b])
      problem.SetParameterBlockConstant(ptrs[b]);
    else if (!held.empty())
      problem.SetManifold(ptrs[b], new ceres::SubsetManifold(sizes[b], held));
    off += sizes[b];
  }
  // Bounds (decision D10).
  if (m == Model::pnc) {
    for (int d : {0, 2, 5})
      problem.SetParameterLowerBound(ptrs[0], d, 1e-3);
    for (int c = 0; c < 3; ++c)
      problem.SetParameterLowerBound(ptrs[1], c, 1e-6);
  } else {
    for (int d : {0, 1})
      problem.SetParameterLowerBound(ptrs[0], d, 1e-3);
    problem.SetParameterLowerBound(ptrs[1], 0, 1e-6);
  }
  if (fit_alpha) {
    problem.SetParameterLowerBound(ptrs[3], 0, alpha_lower_bound()); // D12i
    problem.SetParameterUpperBound(ptrs[3], 0, 1.5);
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = opt.max_iterations;
  so.function_tolerance = opt.function_tolerance;
  so.gradient_tolerance = 1e-14;
  so.parameter_tolerance = 1e-12;
  so.num_threads = 1;
  SolveResult out;
  const auto t0 = std::chrono::steady_clock::now();
  ceres::Solve(so, &problem, &out.summary);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  theta.clear();
  for (const auto& b : blocks)
    theta.insert(theta.end(), b.begin(), b.end());
  return out;
}

// Initial constants (MPa): the per-case regression where it informs a constant, the prior
// elsewhere; alpha = alpha0.
std::vector<double> initial_constants(const FitReport& rep, Model m, const NdmParameters& prior,
                                      double alpha0) {
  const int n = n_theta(m);
  std::vector<double> k0(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j)
    k0[static_cast<std::size_t>(j)] = prior.k[static_cast<std::size_t>(j)] / kMPa;
  k0.back() = alpha0;
  std::map<std::string, std::vector<double>> est;
  for (const auto& l : rep.regression) {
    est[l.linear_label].push_back(l.a / kMPa);
    if (std::isfinite(l.b)) {
      const bool twice = l.damage_label[0] == '2';
      est[twice ? l.damage_label.substr(1) : l.damage_label].push_back((twice ? 0.5 : 1.0) * l.b /
                                                                       kMPa);
    }
  }
  for (const auto& [name, v] : est) {
    const int j = constant_index(m, name);
    if (j < 0 || v.empty()) continue;
    double s = 0;
    for (double x : v)
      s += x;
    k0[static_cast<std::size_t>(j)] = s / static_cast<double>(v.size());
  }
  return k0;
}

// Squared column norms of d r / d k at constants k (structural identifiability); with ties
// (D396) of d r / d k T: a derived constant's column is zero, its sources' carry its data.
Eigen::VectorXd column_norms(const std::vector<PointTerm>& terms, const std::vector<double>& k,
                             int n, Model m, const std::vector<int>& tied) {
  Eigen::VectorXd colnorm = Eigen::VectorXd::Zero(n);
  const Eigen::MatrixXd T = tie_matrix(m, tied);
  for (const auto& t : terms) {
    Eigen::MatrixXd drdk;
    std::vector<double> r(t.comps.size());
    point_residual(t, k, r.data(), &drdk);
    colnorm += (drdk * T).colwise().squaredNorm().transpose();
  }
  return colnorm;
}

// Standard errors of the constants from the covariance of the free theta (D11); a derived
// constant's (D396) through its row of G.
void standard_errors(FitReport& rep, Model m, const std::vector<double>& theta,
                     const std::vector<int>& tied, const std::vector<int>& free,
                     const Eigen::MatrixXd& cov_theta) {
  const int n = n_theta(m);
  const Eigen::MatrixXd G = detail::dconstants_dtheta(m, theta, tied);
  Eigen::MatrixXd Gf(n, static_cast<Eigen::Index>(free.size()));
  for (std::size_t c = 0; c < free.size(); ++c)
    Gf.col(static_cast<Eigen::Index>(c)) = G.col(free[c]);
  const Eigen::MatrixXd cov_k = Gf * cov_theta * Gf.transpose();
  for (int j = 0; j < n; ++j) {
    if (!rep.fitted[static_cast<std::size_t>(j)]) continue;
    const double scale = j == n - 1 ? 1.0 : kMPa;
    rep.std_error[static_cast<std::size_t>(j)] = std::sqrt(std::max(0.0, cov_k(j, j))) * scale;
  }
}

// R^2 per curve through the kernel, chi^2 per curve, and the runs test of its residuals (in
// loading order, as the terms are built).
void curve_statistics(FitReport& rep, const StressStrainData& data,
                      const std::vector<PointTerm>& terms, const Eigen::VectorXd& r,
                      bool data_errors) {
  std::map<std::pair<int, int>, std::vector<double>> series;
  Eigen::Index row = 0;
  for (const auto& t : terms)
    for (int comp : t.comps)
      series[{t.case_id, comp}].push_back(r[row++]);
  for (const CaseCurve& c : data.cases) {
    const auto model_stress = stress_path(rep.params, c.strain);
    for (int comp : deformation_case(c.id).active) {
      const Eigen::VectorXd y = c.stress.col(comp), yh = model_stress.col(comp);
      ComponentFit f{c.id, comp, static_cast<int>(y.size()), r_squared(y, yh),
                     std::sqrt((y - yh).squaredNorm() / static_cast<double>(y.size()))};
      const auto& s = series[{c.id, comp}];
      if (data_errors) {
        f.chi2 = 0;
        for (double v : s)
          f.chi2 += v * v;
      }
      const stats::RunsTest rt = stats::runs_test(s);
      f.runs = rt.runs;
      f.runs_expected = rt.expected;
      f.runs_p = rt.p_too_few;
      f.lag1 = rt.lag1;
      rep.components.push_back(f);
    }
  }
}

} // namespace

// ------------------------------------------------------------------ the fit

namespace {
// What every stage of one fit reads: the model, the start alpha, the prior and the terms.
struct FitContext {
  const StressStrainData& data;
  const FitOptions& opt;
  Model m;
  int n;
  std::size_t ns;
  const std::vector<std::string>& names;
  double alpha0;
  std::string held_note;
  std::vector<double> theta_prior;
  std::vector<PointTerm> terms;
  std::vector<int> tied; ///< constants derived from others (isotropy, D396)
};

// What the solve rounds leave: the last solve, the residuals and Jacobian at its solution,
// the free constants and the Jacobian's columns of those.
struct SolveState {
  SolveResult sr;
  Eigen::VectorXd r;
  Eigen::MatrixXd J, Jf;
  std::vector<int> free;
};

FitContext make_context(const StressStrainData& data, const FitOptions& opt,
                        const NdmParameters& prior, double alpha0) {
  const Model m = opt.model;
  const int n = n_theta(m);
  const auto ns = static_cast<std::size_t>(n);
  std::vector<double> k_prior(ns);
  for (std::size_t j = 0; j < ns; ++j)
    k_prior[j] = j + 1 == ns ? alpha0 : prior.k[j] / kMPa;
  std::vector<double> theta_prior = detail::theta_from_constants(m, k_prior);
  return FitContext{data,
                    opt,
                    m,
                    n,
                    ns,
                    constant_names(m),
                    alpha0,
                    "held at the prior (" + opt.prior_source + ")",
                    std::move(theta_prior),
                    build_terms(data, m, alpha0),
                    applicable_ties(m, opt)};
}

// The columns of J of the free constants.
Eigen::MatrixXd free_columns(const Eigen::MatrixXd& J, const std::vector<int>& free) {
  Eigen::MatrixXd Jf(J.rows(), static_cast<Eigen::Index>(free.size()));
  for (std::size_t c = 0; c < free.size(); ++c)
    Jf.col(static_cast<Eigen::Index>(c)) = J.col(free[c]);
  return Jf;
}

// Structural identifiability at the start: zero columns of d r / d k are held (D11). Returns
// the damage constants held because their mode never reaches the onset of the start alpha;
// a fitted alpha may move the onset into the data (D12g): they are re-examined after a solve.
std::vector<int> hold_unidentified_at_start(const FitContext& cx, const Eigen::VectorXd& colnorm,
                                            FitReport& rep, std::vector<double>& theta) {
  rep.fitted.assign(cx.ns, true);
  rep.status.assign(cx.ns, "fitted");
  rep.note.assign(cx.ns, "");
  std::vector<int> held_at_onset;
  for (int j = 0; j + 1 < cx.n; ++j) {
    const auto js = static_cast<std::size_t>(j);
    if (colnorm[j] != 0.0) continue;
    if (cx.names[js][0] != 'C') held_at_onset.push_back(j);
    rep.fitted[js] = false;
    rep.status[js] = "not identified";
    rep.note[js] = std::string(cx.names[js][0] == 'C' ? "no data for the case that determines it"
                                                      : "the data never reach damage onset for "
                                                        "its mode") +
                   "; " + cx.held_note;
    theta[js] = cx.theta_prior[js];
  }
  return held_at_onset;
}

// alpha (D12b): fitted when the data pass the onset of alpha0 somewhere, unless told.
bool choose_alpha(const FitContext& cx, bool past_onset, FitReport& rep) {
  const FitOptions& opt = cx.opt;
  const bool alpha_undefined =
      std::any_of(opt.undefined.begin(), opt.undefined.end(),
                  [&](const UndefinedConstant& u) { return u.name == cx.names[cx.ns - 1]; });
  const bool fit_alpha =
      !alpha_undefined &&
      (opt.alpha_mode == AlphaMode::fit || (opt.alpha_mode == AlphaMode::automatic && past_onset));
  {
    std::ostringstream a;
    a << (fit_alpha ? "fitted" : "held at " + std::to_string(cx.alpha0)) << " ("
      << alpha_mode_name(opt.alpha_mode) << "; the data " << (past_onset ? "pass" : "do not reach")
      << " the damage onset at alpha = " << cx.alpha0 << ")";
    rep.alpha_choice = a.str();
  }
  if (!fit_alpha) {
    rep.fitted[cx.ns - 1] = false;
    rep.status[cx.ns - 1] = "held";
    rep.note[cx.ns - 1] =
        opt.alpha_mode == AlphaMode::hold
            ? (opt.alpha ? "held by option" : "held by option; " + cx.held_note)
            : "the data never reach damage onset; held at " + std::to_string(cx.alpha0);
  }
  return fit_alpha;
}

// Constants the caller declares undefined by the data (e.g. the phase check of pnc
// characterize: shear and damage constants of a material that relaxes within a hold).
void hold_declared_undefined(const FitContext& cx, FitReport& rep, std::vector<double>& theta) {
  rep.declared_undefined = cx.opt.undefined;
  for (const auto& u : cx.opt.undefined) {
    const auto js = static_cast<std::size_t>(constant_index(cx.m, u.name));
    rep.fitted[js] = false;
    rep.status[js] = "not identified";
    rep.note[js] =
        u.reason + "; " + (js + 1 == cx.ns ? "held at " + std::to_string(cx.alpha0) : cx.held_note);
    theta[js] = cx.theta_prior[js];
    if (js + 1 == cx.ns) rep.alpha_choice += "; declared undefined by the caller: " + u.reason;
  }
}

// Decision D12g: frees the damage constants held at the start whose mode passes the onset of
// the fitted alpha at `theta` (unless declared undefined). True when one was freed.
bool free_reached_onset(const FitContext& cx, const std::vector<int>& held_at_onset,
                        const std::vector<double>& theta, FitReport& rep) {
  const Eigen::VectorXd cn = column_norms(
      cx.terms, detail::constants_from_theta(cx.m, theta, cx.tied), cx.n, cx.m, cx.tied);
  bool freed = false;
  for (int j : held_at_onset) {
    const auto js = static_cast<std::size_t>(j);
    const bool declared =
        std::any_of(cx.opt.undefined.begin(), cx.opt.undefined.end(),
                    [&](const UndefinedConstant& u) { return u.name == cx.names[js]; });
    if (declared || !(cn[j] != 0.0)) continue;
    rep.fitted[js] = true;
    rep.status[js] = "fitted";
    rep.note[js] = "";
    freed = true;
  }
  return freed;
}

// The residuals and Jacobian at `theta`, the free constants, and the free constants the data
// do not determine there held at the prior (D11). True when one was held.
bool hold_unidentified_at_solution(const FitContext& cx, SolveState& st, FitReport& rep,
                                   std::vector<double>& theta) {
  detail::residuals_and_jacobian(cx.data, cx.m, theta, st.r, &st.J, cx.tied);
  st.free.clear();
  std::vector<std::string> free_names;
  for (int j = 0; j < cx.n; ++j)
    if (rep.fitted[static_cast<std::size_t>(j)]) {
      st.free.push_back(j);
      free_names.push_back(cx.names[static_cast<std::size_t>(j)]);
    }
  st.Jf = free_columns(st.J, st.free);
  std::vector<std::string> why;
  const std::vector<bool> bad = stats::not_identified(st.Jf, why, free_names);
  bool changed = false;
  for (std::size_t c = 0; c < st.free.size(); ++c) {
    if (!bad[c]) continue;
    const auto js = static_cast<std::size_t>(st.free[c]);
    rep.fitted[js] = false;
    rep.status[js] = "not identified";
    rep.note[js] =
        why[c] + "; " + (js + 1 == cx.ns ? "held at " + std::to_string(cx.alpha0) : cx.held_note);
    theta[js] = cx.theta_prior[js];
    changed = true;
  }
  return changed;
}

// Solve; constants the data do not determine at the solution are held at the prior and
// the fit repeated (at most three rounds that add held constants). Before that, once per
// fit: when alpha is fitted, a damage constant held because its mode never reached the
// onset of the start alpha is freed if the fitted alpha's onset lies inside the data
// (D12g), and the fit repeated from the solution.
SolveState solve_rounds(const FitContext& cx, bool fit_alpha, const std::vector<int>& held_at_onset,
                        FitReport& rep, std::vector<double>& theta) {
  SolveState st;
  bool reexamined = !(fit_alpha && rep.fitted[cx.ns - 1]) || held_at_onset.empty();
  for (int round = 0; round < 3; ++round) {
    st.sr = solve(cx.terms, cx.m, cx.opt, cx.tied, rep.fitted, fit_alpha && rep.fitted[cx.ns - 1],
                  theta);
    if (!reexamined) { // decision D12g
      reexamined = true;
      if (free_reached_onset(cx, held_at_onset, theta, rep)) {
        --round;
        continue;
      }
    }
    if (!hold_unidentified_at_solution(cx, st, rep, theta)) break;
  }
  return st;
}

// decision D12i: an alpha that ends on its lower bound (damage onset at zero strain) is the
// constrained optimum, not a fitted value with a standard error: it is reported at the bound
void report_alpha_at_bound(const FitContext& cx, SolveState& st, FitReport& rep) {
  rep.fitted[cx.ns - 1] = false;
  rep.status[cx.ns - 1] = "at bound";
  rep.note[cx.ns - 1] = fmt::format("the fit ended on the lower bound 1/lambda_c = {:.5g}: the "
                                    "damage onset is at zero strain (the data bend from their "
                                    "start); no standard error",
                                    alpha_lower_bound());
  rep.alpha_choice += "; ended on its lower bound 1/lambda_c (damage onset at zero strain, D12i)";
  st.free.erase(std::remove(st.free.begin(), st.free.end(), cx.n - 1), st.free.end());
  st.Jf = free_columns(st.J, st.free);
}

// The solver's summary and the fitted constants (Pa; alpha: 1) into the report.
void report_solution(const FitContext& cx, const SolveResult& sr, const std::vector<double>& theta,
                     FitReport& rep) {
  const auto& summary = sr.summary;
  rep.seconds = sr.seconds;
  rep.converged = summary.termination_type == ceres::CONVERGENCE;
  rep.termination = ceres::TerminationTypeToString(summary.termination_type);
  rep.message = summary.message;
  rep.brief_report = summary.BriefReport();
  rep.full_report = summary.FullReport();
  rep.iterations = static_cast<int>(summary.iterations.size()) - 1;
  rep.initial_cost = summary.initial_cost;
  rep.final_cost = summary.final_cost;
  rep.residuals = summary.num_residuals;
  const std::vector<double> kf = detail::constants_from_theta(cx.m, theta, cx.tied);
  rep.params = params_from_constants(cx.m, kf);
  for (int j = 0; j < cx.n - 1; ++j)
    rep.params.k[static_cast<std::size_t>(j)] *= kMPa;
}

// Standard errors (D11): from the data's errors when every fitted point has one (scaled up
// by chi^2/dof when that exceeds 1, never down), else the sandwich estimate. Returns whether
// the data carry errors.
bool report_standard_errors(const FitContext& cx, const SolveState& st,
                            const std::vector<double>& theta, FitReport& rep) {
  rep.free_parameters = static_cast<int>(st.free.size());
  rep.std_error.assign(cx.ns, kNaN);
  rep.dof = static_cast<int>(st.r.size()) - rep.free_parameters;
  const bool data_errors = data_has_errors(cx.data);
  rep.error_model = data_errors ? "data standard errors" : "sandwich (HC3)";
  if (cx.opt.loss != "none") rep.error_model += ", robust loss: indicative";
  if (data_errors && rep.dof > 0) {
    rep.chi2 = st.r.squaredNorm();
    rep.chi2_p = stats::chi2_upper_tail(rep.chi2, rep.dof);
  }
  if (rep.dof > 0) {
    Eigen::MatrixXd cov;
    const bool ok = data_errors ? stats::covariance_known_errors(st.Jf, cov)
                                : stats::covariance_sandwich(st.Jf, st.r, cov);
    if (!ok) {
      rep.warnings += "covariance is singular (some constants are not determined by the data); "
                      "standard errors not reported. ";
    } else {
      if (data_errors) cov *= std::max(1.0, rep.chi2 / rep.dof);
      standard_errors(rep, cx.m, theta, cx.tied, st.free, cov);
    }
  } else {
    rep.warnings += "no degrees of freedom left for standard errors. ";
  }
  return data_errors;
}
} // namespace

FitReport fit_ndm(const StressStrainData& all_rows, const FitOptions& opt) {
  opt.validate();
  const Model m = opt.model;
  check_cases(all_rows, m);
  int dropped = 0;
  const StressStrainData data =
      within_fit_range(all_rows, opt.strain_max, opt.stretch_max, dropped);
  const NdmParameters prior = opt.prior ? *opt.prior : dissertation_parameters(m);
  const double alpha0 = opt.alpha ? *opt.alpha : prior.alpha();

  FitReport rep;
  rep.strain_max = opt.strain_max;
  rep.rows_beyond_strain_max = dropped;
  rep.stretch_max = opt.stretch_max;
  rep.regression = regress_cases(data, m, alpha0);
  std::vector<double> k0 = initial_constants(rep, m, prior, alpha0);
  std::vector<double> theta = detail::theta_from_constants(m, k0);
  const FitContext cx = make_context(data, opt, prior, alpha0);
  k0 = detail::constants_from_theta(m, theta, cx.tied); // after a possible positive-definite clip
  const std::size_t ns = cx.ns;

  const Eigen::VectorXd colnorm = column_norms(cx.terms, k0, cx.n, m, cx.tied);
  std::vector<int> held_at_onset = hold_unidentified_at_start(cx, colnorm, rep, theta);
  const bool fit_alpha = choose_alpha(cx, colnorm[cx.n - 1] != 0.0, rep);
  hold_declared_undefined(cx, rep, theta);
  mark_derived(cx.tied, rep, held_at_onset); // D396

  SolveState st = solve_rounds(cx, fit_alpha, held_at_onset, rep, theta);
  if (fit_alpha && rep.fitted[ns - 1] &&
      detail::constants_from_theta(m, theta).back() <= alpha_lower_bound() * (1 + 1e-9))
    report_alpha_at_bound(cx, st, rep); // D12i
  report_solution(cx, st.sr, theta, rep);
  rep.isotropic = opt.isotropic;
  finish_derived(m, cx.tied, rep); // D396: errors where every source is fitted
  const bool data_errors = report_standard_errors(cx, st, theta, rep);
  if (!rep.converged) rep.warnings += "the solver did not report convergence: " + rep.message + " ";

  curve_statistics(rep, data, cx.terms, st.r, data_errors);
  if (opt.check_units) check_stiffness_units(rep, opt, data.source);
  rep.verdict = judge_fit(rep);
  return rep;
}

} // namespace pnc::damage
