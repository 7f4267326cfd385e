// NDM kernel: see pnc/damage/ndm.hpp and docs/decisions.md (D1-D8).
#include "pnc/damage/ndm.hpp"

#include "pnc/core/error.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace pnc::damage {

const char* model_name(Model m) { return m == Model::pnc ? "pnc" : "pp"; }

Model parse_model(const std::string& name, const std::string& source) {
  if (name == "pnc") return Model::pnc;
  if (name == "pp") return Model::pp;
  fail(source, "model", name, "must be 'pnc' (nanocomposite) or 'pp' (pure polymer)");
}

const std::vector<std::string>& constant_names(Model m) {
  static const std::vector<std::string> pnc = {
      "C11", "C22", "C33", "C12", "C13", "C23", "C44", "C55", "C66", "A1",  "A5",
      "A9",  "A10", "A11", "A13", "A15", "A17", "A18", "A22", "A24", "A26", "alpha"};
  static const std::vector<std::string> pp = {"C11", "C12", "C44", "B1", "B2", "B4", "alpha"};
  return m == Model::pnc ? pnc : pp;
}

int constant_index(Model m, const std::string& name) {
  const auto& n = constant_names(m);
  for (std::size_t i = 0; i < n.size(); ++i)
    if (n[i] == name) return static_cast<int>(i);
  return -1;
}

double& NdmParameters::operator[](const std::string& name) {
  const int i = constant_index(model, name);
  if (i < 0) fail("<parameters>", name, "", std::string("not a constant of model ") + model_name(model));
  return k[static_cast<std::size_t>(i)];
}
double NdmParameters::operator[](const std::string& name) const {
  return const_cast<NdmParameters&>(*this)[name];
}

// ---------------------------------------------------------------- stiffness
namespace {
enum PncIdx {
  iC11, iC22, iC33, iC12, iC13, iC23, iC44, iC55, iC66,
  iA1, iA5, iA9, iA10, iA11, iA13, iA15, iA17, iA18, iA22, iA24, iA26, iAlphaPnc
};
enum PpIdx { jC11, jC12, jC44, jB1, jB2, jB4, jAlphaPp };
} // namespace

Matrix6 stiffness_c0(const NdmParameters& p) {
  Matrix6 C = Matrix6::Zero();
  const auto& k = p.k;
  if (p.model == Model::pnc) {
    C(0, 0) = k[iC11]; C(1, 1) = k[iC22]; C(2, 2) = k[iC33];
    C(0, 1) = C(1, 0) = k[iC12];
    C(0, 2) = C(2, 0) = k[iC13];
    C(1, 2) = C(2, 1) = k[iC23];
    C(3, 3) = k[iC44]; C(4, 4) = k[iC55]; C(5, 5) = k[iC66];
  } else {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) C(i, j) = (i == j) ? k[jC11] : k[jC12];
      C(3 + i, 3 + i) = k[jC44];
    }
  }
  return C;
}

Matrix6 stiffness_c1_dD(const NdmParameters& p, int mode) {
  Matrix6 C = Matrix6::Zero();
  const auto& k = p.k;
  if (p.model == Model::pnc) {
    switch (mode) {
    case 0: // D1: voids normal to x1 (eqs. 5.58, 5.61, 5.62)
      C(0, 0) = 2 * k[iA1];
      C(0, 1) = C(1, 0) = k[iA10];
      C(0, 2) = C(2, 0) = k[iA13];
      break;
    case 1: // D2: interface debond (eqs. 5.59, 5.61, 5.63, 5.64, 5.66)
      C(1, 1) = 2 * k[iA5];
      C(0, 1) = C(1, 0) = k[iA11];
      C(1, 2) = C(2, 1) = k[iA17];
      C(3, 3) = k[iA22]; // engineering form of 2 A22 D2 (decision D2)
      C(5, 5) = k[iA24];
      break;
    case 2: // D3: voids normal to x3 (eqs. 5.60, 5.62, 5.63, 5.65)
      C(2, 2) = 2 * k[iA9];
      C(0, 2) = C(2, 0) = k[iA15];
      C(1, 2) = C(2, 1) = k[iA18];
      C(4, 4) = k[iA26];
      break;
    default: break;
    }
  } else if (mode == 0) { // isotropic reading of eqs. 6.42-6.45 (decision D3)
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) C(i, j) = (i == j) ? 2 * k[jB1] : k[jB2];
      C(3 + i, 3 + i) = k[jB4];
    }
  }
  return C;
}

Matrix6 stiffness_c1(const NdmParameters& p, const std::array<double, 3>& D) {
  Matrix6 C = Matrix6::Zero();
  const int n = p.model == Model::pnc ? 3 : 1;
  for (int m = 0; m < n; ++m)
    if (D[m] != 0.0) C += D[m] * stiffness_c1_dD(p, m);
  return C;
}

Matrix6 c0_from_c_constants(const std::array<double, 9>& c) {
  Matrix6 C = Matrix6::Zero();
  C(0, 0) = 2 * c[0]; C(1, 1) = 2 * c[1]; C(2, 2) = 2 * c[2];
  C(0, 1) = C(1, 0) = c[3];
  C(0, 2) = C(2, 0) = c[4];
  C(1, 2) = C(2, 1) = c[5];
  // eq. 5.37 puts 2 c7 on the diagonal for the TENSORIAL shear strain; on engineering shear
  // (gamma = 2 eps) the same energy c7 eps4^2 gives C44 = c7 (eq. 5.38: c7 = C0_44).
  C(3, 3) = c[6]; C(4, 4) = c[7]; C(5, 5) = c[8];
  return C;
}

Matrix6 c0_from_engineering(double E1, double E2, double E3, double nu12, double nu13,
                            double nu23, double mu12, double mu13, double mu23) {
  const double nu21 = nu12 * E2 / E1, nu31 = nu13 * E3 / E1, nu32 = nu23 * E3 / E2;
  const double Y = 1.0 / (1 - nu12 * nu21 - nu23 * nu32 - nu13 * nu31 - 2 * nu21 * nu32 * nu13);
  Matrix6 C = Matrix6::Zero();
  C(0, 0) = E1 * (1 - nu23 * nu32) * Y;
  C(1, 1) = E2 * (1 - nu13 * nu31) * Y;
  C(2, 2) = E3 * (1 - nu12 * nu21) * Y;
  C(1, 2) = C(2, 1) = E2 * (nu32 + nu12 * nu31) * Y;
  C(0, 2) = C(2, 0) = E3 * (nu13 + nu12 * nu23) * Y;
  // Printed eq. 5.44 (and its EQUATIONS.md restatement) has nu31*nu32; the orthotropic
  // inverse requires nu31*nu23 (decision D1b; tested against the compliance matrix).
  C(0, 1) = C(1, 0) = E1 * (nu21 + nu31 * nu23) * Y;
  C(3, 3) = mu23; C(4, 4) = mu13; C(5, 5) = mu12;
  return C;
}

// ---------------------------------------------------------------- damage function
namespace {
const double kLambdaC = std::pow(26.0 / 7.0, 1.0 / 6.0);
// k = 1 / |2 lc^-13 - lc^-7|: makes D(lambda_c) = 0 exactly (decision D4).
const double kDamageScale = 1.0 / std::abs(2 * std::pow(kLambdaC, -13) - std::pow(kLambdaC, -7));
} // namespace

double critical_stretch() { return kLambdaC; }

double damage_function(double x) {
  if (!(x > kLambdaC)) return 0.0;
  const double x6 = 1.0 / (x * x * x * x * x * x);
  const double x7 = x6 / x;
  return 1.0 + kDamageScale * (2 * x7 * x6 - x7);
}

double damage_function_derivative(double x) {
  if (!(x > kLambdaC)) return 0.0;
  const double x6 = 1.0 / (x * x * x * x * x * x);
  const double x8 = x6 / (x * x);
  return kDamageScale * (-26 * x8 * x6 + 7 * x8);
}

// ---------------------------------------------------------------- state
const std::vector<std::string>& state_names(Model m) {
  static const std::vector<std::string> pnc = {"kappa1", "kappa2", "kappa3", "D1", "D2", "D3"};
  static const std::vector<std::string> pp = {"kappa", "D"};
  return m == Model::pnc ? pnc : pp;
}
std::size_t state_size(Model m) { return state_names(m).size(); }

void state_to_array(Model m, const NdmState& s, double* out) {
  const int n = m == Model::pnc ? 3 : 1;
  for (int i = 0; i < n; ++i) {
    out[i] = s.kappa[i];
    out[n + i] = s.D[i];
  }
}

NdmState state_from_array(Model m, const double* in) {
  NdmState s;
  const int n = m == Model::pnc ? 3 : 1;
  for (int i = 0; i < n; ++i) {
    s.kappa[i] = in[i];
    s.D[i] = in[n + i];
  }
  return s;
}

// ---------------------------------------------------------------- kinematics
ModeStretch mode_stretches(Model m, const Voigt& v, bool with_derivative) {
  ModeStretch out;
  Eigen::Matrix3d e;
  e << v[0], 0.5 * v[5], 0.5 * v[4], //
      0.5 * v[5], v[1], 0.5 * v[3],  //
      0.5 * v[4], 0.5 * v[3], v[2];
  // Principal stretches of U = I + e by eigen-decomposition (closed form for 3x3).
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(e, with_derivative ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
  out.lambda_max = 1.0 + es.eigenvalues()[2];
  Eigen::Matrix<double, 1, 6> dmax = Eigen::Matrix<double, 1, 6>::Zero();
  if (with_derivative) {
    const Eigen::Vector3d N = es.eigenvectors().col(2);
    dmax << N[0] * N[0], N[1] * N[1], N[2] * N[2], N[1] * N[2], N[0] * N[2], N[0] * N[1];
  }
  if (m == Model::pp) {
    out.lambda[0] = out.lambda_max;
    if (with_derivative) out.dlambda.row(0) = dmax;
    return out;
  }
  // Voigt index of the shear pair (k, j): (1,2)->3, (0,2)->4, (0,1)->5.
  static const int pair_index[3][3] = {{-1, 5, 4}, {5, -1, 3}, {4, 3, -1}};
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    const double s = std::sqrt(e(k, a) * e(k, a) + e(k, b) * e(k, b));
    const double raw = 1.0 + e(k, k) + s;
    if (raw <= out.lambda_max) {
      out.lambda[k] = raw;
      if (with_derivative) {
        out.dlambda(k, k) = 1.0;
        if (s > 0) {
          out.dlambda(k, pair_index[k][a]) = e(k, a) / (2 * s);
          out.dlambda(k, pair_index[k][b]) = e(k, b) / (2 * s);
        }
      }
    } else {
      out.lambda[k] = out.lambda_max;
      if (with_derivative) out.dlambda.row(k) = dmax;
    }
  }
  return out;
}

Matrix6 strain_rotation(const Eigen::Matrix3d& R) {
  Matrix6 T;
  for (int J = 0; J < 6; ++J) {
    Voigt unit = Voigt::Zero();
    unit[J] = 1.0;
    Eigen::Matrix3d e;
    e << unit[0], 0.5 * unit[5], 0.5 * unit[4], 0.5 * unit[5], unit[1], 0.5 * unit[3],
        0.5 * unit[4], 0.5 * unit[3], unit[2];
    const Eigen::Matrix3d el = R * e * R.transpose();
    T(0, J) = el(0, 0);
    T(1, J) = el(1, 1);
    T(2, J) = el(2, 2);
    T(3, J) = 2 * el(1, 2);
    T(4, J) = 2 * el(0, 2);
    T(5, J) = 2 * el(0, 1);
  }
  return T;
}

void ErrorBuffer::set(const char* text) {
  std::strncpy(msg, text, sizeof msg - 1);
  msg[sizeof msg - 1] = '\0';
}

// ---------------------------------------------------------------- integration
Status integrate(const NdmParameters& p, const NdmState& s0, NdmState& s1, const Voigt& eps0,
                 const Voigt& deps, Voigt& sigma, Matrix6* K, ErrorBuffer& err) {
  const Voigt eps = eps0 + deps;
  if (!eps.allFinite()) {
    err.set("ndm: strain is not finite");
    return Status::bad_input;
  }
  const bool rotated = !p.R.isIdentity(0.0);
  Matrix6 T;
  Voigt el = eps;
  if (rotated) {
    T = strain_rotation(p.R);
    el = T * eps;
  }
  const ModeStretch ms = mode_stretches(p.model, el, K != nullptr);
  const int n = p.model == Model::pnc ? 3 : 1;
  const double alpha = p.alpha();
  NdmState out = s0;
  std::array<bool, 3> loading{false, false, false};
  for (int m = 0; m < n; ++m) {
    loading[m] = ms.lambda[m] > s0.kappa[m];
    out.kappa[m] = loading[m] ? ms.lambda[m] : s0.kappa[m];
    out.D[m] = damage_function(out.kappa[m] / alpha);
  }
  const Matrix6 C = stiffness_c0(p) + stiffness_c1(p, out.D);
  const Voigt sl = C * el;
  if (K) {
    Matrix6 Kl = C;
    for (int m = 0; m < n; ++m) {
      if (!loading[m]) continue;
      const double dD = damage_function_derivative(out.kappa[m] / alpha) / alpha;
      if (dD == 0.0) continue;
      Kl.noalias() += (stiffness_c1_dD(p, m) * el) * (dD * ms.dlambda.row(m));
    }
    *K = rotated ? Matrix6(T.transpose() * Kl * T) : Kl;
  }
  sigma = rotated ? Voigt(T.transpose() * sl) : sl;
  s1 = out;
  return Status::ok;
}

Eigen::Matrix<double, Eigen::Dynamic, 6>
stress_path(const NdmParameters& p, const Eigen::Matrix<double, Eigen::Dynamic, 6>& strain,
            std::vector<NdmState>* states) {
  Eigen::Matrix<double, Eigen::Dynamic, 6> out(strain.rows(), 6);
  NdmState s0, s1;
  Voigt prev = Voigt::Zero(), sig;
  ErrorBuffer err;
  if (states) states->resize(static_cast<std::size_t>(strain.rows()));
  for (Eigen::Index i = 0; i < strain.rows(); ++i) {
    const Voigt e = strain.row(i).transpose();
    if (integrate(p, s0, s1, prev, e - prev, sig, nullptr, err) != Status::ok)
      fail("<strain path>", "row " + std::to_string(i), "", err.msg);
    out.row(i) = sig.transpose();
    if (states) (*states)[static_cast<std::size_t>(i)] = s1;
    s0 = s1;
    prev = e;
  }
  return out;
}

// ---------------------------------------------------------------- validation
void validate(const NdmParameters& p, const std::string& source) {
  const auto& names = constant_names(p.model);
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (!std::isfinite(p.k[i])) fail(source, names[i], std::to_string(p.k[i]), "must be finite");
  }
  if (!(p.alpha() > 0.0))
    fail(source, "alpha", std::to_string(p.alpha()),
         "the critical-stretch correction factor must be > 0");
  const Matrix6 C0 = stiffness_c0(p);
  Eigen::LLT<Eigen::Matrix3d> llt(C0.topLeftCorner<3, 3>());
  if (llt.info() != Eigen::Success) {
    std::ostringstream v;
    v << "eigenvalues of the normal block: "
      << Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C0.topLeftCorner<3, 3>())
             .eigenvalues()
             .transpose();
    fail(source, "C0 (C11..C33, C12, C13, C23)", v.str(),
         "the undamaged stiffness must be positive definite");
  }
  for (int i = 3; i < 6; ++i) {
    if (!(C0(i, i) > 0)) {
      static const char* shear[3] = {"C44", "C55", "C66"};
      fail(source, p.model == Model::pnc ? shear[i - 3] : "C44", std::to_string(C0(i, i)),
           "shear stiffness must be > 0 (C0 positive definite)");
    }
  }
  const Eigen::Matrix3d RtR = p.R.transpose() * p.R;
  if (!RtR.isIdentity(1e-9) || std::abs(p.R.determinant() - 1.0) > 1e-9)
    fail(source, "platelet_rotation", "", "must be a proper rotation (R^T R = I, det R = 1)");
}

} // namespace pnc::damage
