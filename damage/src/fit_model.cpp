// The NDM fit's model side: see fit_model.hpp and docs/decisions.md D10-D12.
#include "fit_model.hpp"

#include "pnc/core/error.hpp"
#include "pnc/damage/reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace pnc::damage {

namespace fitmodel {

// Parameter blocks of theta (decision D10).
std::vector<int> block_sizes(Model m) {
  return m == Model::pnc ? std::vector<int>{6, 3, 12, 1} : std::vector<int>{2, 1, 3, 1};
}
int n_theta(Model m) {
  return static_cast<int>(constant_names(m).size());
}

// Decision D396: an isotropic C0 + D C1 needs C44 = (C11 - C12) / 2 and B4 = B1 - B2 / 2 (the
// indices of the pp constants the ties use, looked up once).
namespace {
struct PpIndex {
  int c11 = constant_index(Model::pp, "C11"), c12 = constant_index(Model::pp, "C12");
  int c44 = constant_index(Model::pp, "C44"), b1 = constant_index(Model::pp, "B1");
  int b2 = constant_index(Model::pp, "B2"), b4 = constant_index(Model::pp, "B4");
};
const PpIndex& pp_index() {
  static const PpIndex i;
  return i;
}
} // namespace

std::vector<int> isotropy_ties(Model m, bool isotropic) {
  if (m != Model::pp || !isotropic) return {};
  return {pp_index().c44, pp_index().b4};
}

Eigen::MatrixXd tie_matrix(Model m, const std::vector<int>& tied) {
  const int n = n_theta(m);
  Eigen::MatrixXd T = Eigen::MatrixXd::Identity(n, n);
  const PpIndex& ix = pp_index();
  for (int j : tied) {
    T.row(j).setZero();
    if (m == Model::pp && j == ix.c44) {
      T(j, ix.c11) = 0.5;
      T(j, ix.c12) = -0.5;
    } else if (m == Model::pp && j == ix.b4) {
      T(j, ix.b1) = 1.0;
      T(j, ix.b2) = -0.5;
    } else {
      throw std::logic_error("tie_matrix: no tie for constant " +
                             constant_names(m)[static_cast<std::size_t>(j)]);
    }
  }
  return T;
}

std::vector<int> applicable_ties(Model m, const FitOptions& opt) {
  std::vector<int> out;
  for (int j : isotropy_ties(m, opt.isotropic)) {
    const std::string& name = constant_names(m)[static_cast<std::size_t>(j)];
    if (std::none_of(opt.undefined.begin(), opt.undefined.end(),
                     [&](const UndefinedConstant& u) { return u.name == name; }))
      out.push_back(j);
  }
  return out;
}

namespace {
std::string tie_formula(int j) {
  return j == pp_index().c44 ? "C44 = (C11 - C12) / 2" : "B4 = B1 - B2 / 2";
}
} // namespace

void mark_derived(const std::vector<int>& tied, FitReport& rep, std::vector<int>& held_at_onset) {
  for (int j : tied) {
    const auto js = static_cast<std::size_t>(j);
    rep.fitted[js] = false;
    rep.status[js] = "derived";
    rep.note[js] = "isotropy: " + tie_formula(j) + " (fit option isotropic, D396)";
    held_at_onset.erase(std::remove(held_at_onset.begin(), held_at_onset.end(), j),
                        held_at_onset.end());
  }
}

void finish_derived(Model m, const std::vector<int>& tied, FitReport& rep) {
  const Eigen::MatrixXd T = tie_matrix(m, tied);
  for (int j : tied) {
    bool all = true;
    for (Eigen::Index c = 0; c < T.cols(); ++c)
      if (c != j && T(j, c) != 0.0) all = all && rep.fitted[static_cast<std::size_t>(c)];
    rep.fitted[static_cast<std::size_t>(j)] = all;
    if (!all)
      rep.note[static_cast<std::size_t>(j)] +=
          "; from constants held at the prior: no standard error";
  }
}

NdmParameters params_from_constants(Model m, const std::vector<double>& k) {
  NdmParameters p;
  p.model = m;
  for (std::size_t i = 0; i < k.size(); ++i)
    p.k[i] = k[i];
  return p;
}

// d sigma / d k for stiffness and damage constants is (C0(u_j) + C1(u_j, D)) eps, with u_j the
// unit parameter set: C0 and C1 are linear in every constant but alpha (decision D11).
struct UnitMatrices {
  std::vector<Matrix6> c0;
  std::vector<std::array<Matrix6, 3>> c1;
};
const UnitMatrices& unit_matrices(Model m) {
  static std::map<Model, UnitMatrices> cache = [] {
    std::map<Model, UnitMatrices> c;
    for (Model mm : {Model::pnc, Model::pp}) {
      UnitMatrices u;
      const int n = n_theta(mm);
      for (int j = 0; j < n; ++j) {
        NdmParameters p;
        p.model = mm;
        p.k[static_cast<std::size_t>(j)] = 1.0;
        u.c0.push_back(stiffness_c0(p));
        u.c1.push_back({stiffness_c1_dD(p, 0), stiffness_c1_dD(p, 1), stiffness_c1_dD(p, 2)});
      }
      c[mm] = u;
    }
    return c;
  }();
  return cache.at(m);
}

// Residuals of one point and d r / d constants (rows x n).
void point_residual(const PointTerm& t, const std::vector<double>& k, double* r,
                    Eigen::MatrixXd* dr_dk) {
  const NdmParameters p = params_from_constants(t.model, k);
  NdmState s1;
  Voigt sigma;
  ErrorBuffer err;
  if (integrate(p, t.s0, s1, t.eps0, t.deps, sigma, nullptr, err) != Status::ok)
    throw std::runtime_error(err.msg);
  for (std::size_t c = 0; c < t.comps.size(); ++c) {
    const int i = t.comps[c];
    r[c] = (sigma[i] - t.data[i]) / t.scale[i];
  }
  if (!dr_dk) return;
  const Voigt eps = t.eps0 + t.deps;
  const UnitMatrices& u = unit_matrices(t.model);
  const int n = n_theta(t.model);
  const int nm = t.model == Model::pnc ? 3 : 1;
  dr_dk->setZero(static_cast<Eigen::Index>(t.comps.size()), n);
  for (int j = 0; j < n - 1; ++j) {
    Matrix6 M = u.c0[static_cast<std::size_t>(j)];
    for (int m = 0; m < nm; ++m)
      if (s1.D[m] != 0.0) M += s1.D[m] * u.c1[static_cast<std::size_t>(j)][m];
    const Voigt col = M * eps;
    for (std::size_t c = 0; c < t.comps.size(); ++c)
      (*dr_dk)(static_cast<Eigen::Index>(c), j) = col[t.comps[c]] / t.scale[t.comps[c]];
  }
  // alpha: D_m = D(kappa_m / alpha), kappa independent of every constant.
  const double a = p.alpha();
  Voigt dsig = Voigt::Zero();
  for (int m = 0; m < nm; ++m) {
    const double dD = damage_function_derivative(s1.kappa[m] / a) * (-s1.kappa[m] / (a * a));
    if (dD != 0.0) dsig += dD * (stiffness_c1_dD(p, m) * eps);
  }
  for (std::size_t c = 0; c < t.comps.size(); ++c)
    (*dr_dk)(static_cast<Eigen::Index>(c), n - 1) = dsig[t.comps[c]] / t.scale[t.comps[c]];
}

std::vector<PointTerm> build_terms(const StressStrainData& data, Model m, double alpha_for_states) {
  std::vector<PointTerm> terms;
  NdmParameters pstate = dissertation_parameters(m);
  pstate["alpha"] = alpha_for_states; // kappa does not depend on constants; D recomputed
  for (const CaseCurve& c : data.cases) {
    const DeformationCase& dc = deformation_case(c.id, data.source);
    std::vector<NdmState> states;
    stress_path(pstate, c.strain, &states);
    // Weights: the data's standard errors where positive; else their median; else 1 MPa.
    Voigt fallback = Voigt::Ones();
    if (c.stress_stderr.rows() == c.stress.rows()) {
      for (int i = 0; i < 6; ++i) {
        std::vector<double> pos;
        for (Eigen::Index k = 0; k < c.stress_stderr.rows(); ++k)
          if (c.stress_stderr(k, i) > 0) pos.push_back(c.stress_stderr(k, i) / kMPa);
        if (!pos.empty()) {
          std::nth_element(pos.begin(), pos.begin() + static_cast<long>(pos.size() / 2), pos.end());
          fallback[i] = pos[pos.size() / 2];
        }
      }
    }
    NdmState prev;
    Voigt eprev = Voigt::Zero();
    for (Eigen::Index k = 0; k < c.strain.rows(); ++k) {
      PointTerm t;
      t.model = m;
      t.case_id = c.id;
      t.comps = dc.active;
      t.s0 = prev;
      t.eps0 = eprev;
      t.deps = c.strain.row(k).transpose() - eprev;
      t.data = c.stress.row(k).transpose() / kMPa;
      for (int i = 0; i < 6; ++i) {
        const bool has = c.stress_stderr.rows() == c.stress.rows() && c.stress_stderr(k, i) > 0;
        t.scale[i] = has ? c.stress_stderr(k, i) / kMPa : fallback[i];
      }
      terms.push_back(t);
      prev = states[static_cast<std::size_t>(k)];
      eprev = c.strain.row(k).transpose();
    }
  }
  return terms;
}

void check_cases(const StressStrainData& data, Model m) {
  // Both models take any of cases 1-9 (D12l: the pure polymer's isotropy pools them); a
  // case driving several components (an equibiaxial one) is refused by name (D360).
  for (const auto& c : data.cases) {
    single_driven(deformation_case(c.id, data.source), "the NDM fit");
    if (c.strain.rows() < 3)
      fail(data.source, "case " + std::to_string(c.id), std::to_string(c.strain.rows()) + " points",
           "each case needs at least 3 points");
  }
  if (m == Model::pnc) {
    // every uniaxial extension row of the registry (one driven normal component, D362)
    for (const DeformationCase& dc : deformation_cases())
      if (is_uniaxial_extension(dc) && !data.find(dc.id))
        fail(data.source, "case", std::to_string(dc.id),
             "is required: the pnc normal stiffness block cannot be determined without it");
    return;
  }
  // an extension case: one whose row drives a normal component (D362)
  const bool extension = std::any_of(data.cases.begin(), data.cases.end(), [](const CaseCurve& c) {
    return is_uniaxial_extension(deformation_case(c.id));
  });
  if (!extension)
    fail(data.source, "cases", "no extension case",
         "the pp model needs at least one of cases 1-3 (extension): C11 and C12 cannot be "
         "determined without it");
}

LabelPair regression_labels(Model m, int case_id, int comp) {
  // Which constants a case's stress component informs follows from the component the case's
  // registry row drives (D362, docs/decisions/damage.md): an extension along a gives C_ab in
  // component b, a shear (Voigt 3..5) its own shear modulus; no case-id ranges.
  const int d = single_driven(deformation_case(case_id), "the start regression");
  if (m == Model::pp) { // isotropic reading (D3): every extension gives C11/2B1 and C12/B2
    if (d < 3) return comp == d ? LabelPair{"C11", "2B1"} : LabelPair{"C12", "B2"};
    return {"C44", "B4"};
  }
  static const LabelPair ext[3][3] = {{{"C11", "2A1"}, {"C12", "A10"}, {"C13", "A13"}},
                                      {{"C12", "A11"}, {"C22", "2A5"}, {"C23", "A17"}},
                                      {{"C13", "A15"}, {"C23", "A18"}, {"C33", "2A9"}}};
  if (d < 3) return ext[d][comp];
  static const LabelPair sh[3] = {{"C44", "A22"}, {"C55", "A26"}, {"C66", "A24"}};
  return sh[d - 3];
}

double r_squared(const Eigen::VectorXd& y, const Eigen::VectorXd& yhat) {
  const double mean = y.mean();
  const double ss_tot = (y.array() - mean).square().sum();
  const double ss_res = (y - yhat).squaredNorm();
  return ss_tot > 0 ? 1.0 - ss_res / ss_tot : std::numeric_limits<double>::quiet_NaN();
}

bool data_has_errors(const StressStrainData& data) {
  for (const CaseCurve& c : data.cases) {
    if (c.stress_stderr.rows() != c.stress.rows()) return false;
    for (int comp : deformation_case(c.id).active)
      if (!(c.stress_stderr.col(comp).array() > 0).all()) return false;
  }
  return !data.cases.empty();
}
} // namespace fitmodel

// ------------------------------------------------------------------ theta map
namespace detail {
using namespace fitmodel;
namespace {
// Positions of the 6 Cholesky parameters in L, and of C11 C22 C33 C12 C13 C23 in C_n.
constexpr int kLPos[6][2] = {{0, 0}, {1, 0}, {1, 1}, {2, 0}, {2, 1}, {2, 2}};
constexpr int kCPos[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
Eigen::Matrix3d lower_from_theta(const std::vector<double>& th) {
  Eigen::Matrix3d L = Eigen::Matrix3d::Zero();
  for (int q = 0; q < 6; ++q)
    L(kLPos[q][0], kLPos[q][1]) = th[static_cast<std::size_t>(q)];
  return L;
}
} // namespace

std::vector<double> theta_from_constants(Model m, const std::vector<double>& k) {
  std::vector<double> th(k);
  if (m == Model::pp) {
    th[0] = k[0] - k[1];     // u = C11 - C12
    th[1] = k[0] + 2 * k[1]; // v = C11 + 2 C12
    return th;
  }
  Eigen::Matrix3d Cn;
  Cn << k[0], k[3], k[4], k[3], k[1], k[5], k[4], k[5], k[2];
  Eigen::LLT<Eigen::Matrix3d> llt(Cn);
  if (llt.info() != Eigen::Success) { // clip to the nearest positive definite matrix
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Cn);
    Eigen::Vector3d ev = es.eigenvalues();
    const double floor = 1e-3 * std::max(1.0, ev.maxCoeff());
    for (int i = 0; i < 3; ++i)
      ev[i] = std::max(ev[i], floor);
    Cn = es.eigenvectors() * ev.asDiagonal() * es.eigenvectors().transpose();
    llt.compute(Cn);
  }
  const Eigen::Matrix3d L = llt.matrixL();
  for (int q = 0; q < 6; ++q)
    th[static_cast<std::size_t>(q)] = L(kLPos[q][0], kLPos[q][1]);
  return th;
}

namespace {
std::vector<double> untied_constants(Model m, const std::vector<double>& th) {
  std::vector<double> k(th);
  if (m == Model::pp) {
    k[0] = (2 * th[0] + th[1]) / 3;
    k[1] = (th[1] - th[0]) / 3;
    return k;
  }
  const Eigen::Matrix3d L = lower_from_theta(th);
  const Eigen::Matrix3d C = L * L.transpose();
  for (int c = 0; c < 6; ++c)
    k[static_cast<std::size_t>(c)] = C(kCPos[c][0], kCPos[c][1]);
  return k;
}
Eigen::MatrixXd untied_jacobian(Model m, const std::vector<double>& th);
} // namespace

std::vector<double> constants_from_theta(Model m, const std::vector<double>& th,
                                         const std::vector<int>& tied) {
  return constants_from_theta(m, th, tied.empty() ? Eigen::MatrixXd() : tie_matrix(m, tied));
}

Eigen::MatrixXd dconstants_dtheta(Model m, const std::vector<double>& th,
                                  const std::vector<int>& tied) {
  return dconstants_dtheta(m, th, tied.empty() ? Eigen::MatrixXd() : tie_matrix(m, tied));
}

std::vector<double> constants_from_theta(Model m, const std::vector<double>& th,
                                         const Eigen::MatrixXd& T) {
  std::vector<double> k = untied_constants(m, th);
  if (T.size() == 0) return k;
  const Eigen::Map<const Eigen::VectorXd> kv(k.data(), static_cast<Eigen::Index>(k.size()));
  const Eigen::VectorXd kt = T * kv;
  return {kt.data(), kt.data() + kt.size()};
}

Eigen::MatrixXd dconstants_dtheta(Model m, const std::vector<double>& th,
                                  const Eigen::MatrixXd& T) {
  if (T.size() == 0) return untied_jacobian(m, th);
  return T * untied_jacobian(m, th);
}

namespace {
Eigen::MatrixXd untied_jacobian(Model m, const std::vector<double>& th) {
  const int n = n_theta(m);
  Eigen::MatrixXd G = Eigen::MatrixXd::Identity(n, n);
  if (m == Model::pp) {
    G(0, 0) = 2.0 / 3;
    G(0, 1) = 1.0 / 3;
    G(1, 0) = -1.0 / 3;
    G(1, 1) = 1.0 / 3;
    return G;
  }
  const Eigen::Matrix3d L = lower_from_theta(th);
  for (int q = 0; q < 6; ++q) {
    Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
    E(kLPos[q][0], kLPos[q][1]) = 1.0;
    const Eigen::Matrix3d dC = E * L.transpose() + L * E.transpose();
    for (int c = 0; c < 6; ++c)
      G(c, q) = dC(kCPos[c][0], kCPos[c][1]);
  }
  return G;
}
} // namespace

void residuals_and_jacobian(const StressStrainData& data, Model m, const std::vector<double>& theta,
                            Eigen::VectorXd& r, Eigen::MatrixXd* J, const std::vector<int>& tied) {
  const std::vector<double> k = constants_from_theta(m, theta, tied);
  const auto terms = build_terms(data, m, k.back());
  Eigen::Index rows = 0;
  for (const auto& t : terms)
    rows += static_cast<Eigen::Index>(t.comps.size());
  r.resize(rows);
  if (J) J->resize(rows, n_theta(m));
  const Eigen::MatrixXd G = dconstants_dtheta(m, theta, tied);
  Eigen::Index row = 0;
  for (const auto& t : terms) {
    Eigen::MatrixXd drdk;
    point_residual(t, k, r.data() + row, J ? &drdk : nullptr);
    const auto nr = static_cast<Eigen::Index>(t.comps.size());
    if (J) J->middleRows(row, nr) = drdk * G;
    row += nr;
  }
}
} // namespace detail

// ------------------------------------------------------------------ regression
std::vector<RegressionLine> regress_cases(const StressStrainData& data, Model m, double alpha) {
  using namespace fitmodel;
  const double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<RegressionLine> out;
  NdmParameters pstate = dissertation_parameters(m);
  pstate["alpha"] = alpha;
  for (const CaseCurve& c : data.cases) {
    const DeformationCase& dc = deformation_case(c.id, data.source);
    std::vector<NdmState> states;
    stress_path(pstate, c.strain, &states);
    const Eigen::Index n = c.strain.rows();
    Eigen::VectorXd x = c.strain.col(single_driven(dc, "the NDM fit")), Dx(n);
    const int mode = m == Model::pnc ? dc.damage_mode : 0;
    for (Eigen::Index i = 0; i < n; ++i)
      Dx[i] = states[static_cast<std::size_t>(i)].D[mode] * x[i];
    const bool damaged = Dx.cwiseAbs().maxCoeff() > 0;
    for (int comp : dc.active) {
      const Eigen::VectorXd y = c.stress.col(comp) / kMPa;
      Eigen::MatrixXd X(n, damaged ? 2 : 1);
      X.col(0) = x;
      if (damaged) X.col(1) = Dx;
      const Eigen::VectorXd coef = X.colPivHouseholderQr().solve(y);
      const LabelPair lab = regression_labels(m, c.id, comp);
      out.push_back({c.id, comp, lab.lin, lab.dam, coef[0] * kMPa, damaged ? coef[1] * kMPa : kNaN,
                     r_squared(y, X * coef)});
    }
  }
  return out;
}

} // namespace pnc::damage
