// The NDM parameters outside the integration: model and constant names, the state layout,
// [C0] from the dissertation's c constants or from engineering constants, and the validation
// of user-supplied parameters (pnc/damage/ndm.hpp; docs/decisions.md D1, D1b, D8).
#include "pnc/damage/ndm.hpp"

#include "pnc/core/error.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <sstream>

namespace pnc::damage {

const char* model_name(Model m) {
  return m == Model::pnc ? "pnc" : "pp";
}

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

std::string constant_unit(const std::string& name) {
  return name == "alpha" ? "1" : "Pa";
}

int constant_index(Model m, const std::string& name) {
  const auto& n = constant_names(m);
  for (std::size_t i = 0; i < n.size(); ++i)
    if (n[i] == name) return static_cast<int>(i);
  return -1;
}

double& NdmParameters::operator[](const std::string& name) {
  const int i = constant_index(model, name);
  if (i < 0)
    fail("<parameters>", name, "", std::string("not a constant of model ") + model_name(model));
  return k[static_cast<std::size_t>(i)];
}
double NdmParameters::operator[](const std::string& name) const {
  return const_cast<NdmParameters&>(*this)[name];
}

// ---------------------------------------------------------------- state
const std::vector<std::string>& state_names(Model m) {
  static const std::vector<std::string> pnc = {"kappa1", "kappa2", "kappa3", "D1", "D2", "D3"};
  static const std::vector<std::string> pp = {"kappa", "D"};
  return m == Model::pnc ? pnc : pp;
}
std::size_t state_size(Model m) {
  return state_names(m).size();
}

Matrix6 c0_from_c_constants(const std::array<double, 9>& c) {
  Matrix6 C = Matrix6::Zero();
  C(0, 0) = 2 * c[0];
  C(1, 1) = 2 * c[1];
  C(2, 2) = 2 * c[2];
  C(0, 1) = C(1, 0) = c[3];
  C(0, 2) = C(2, 0) = c[4];
  C(1, 2) = C(2, 1) = c[5];
  // The source's c-constant stiffness puts 2 c7 on the diagonal for the TENSORIAL shear strain;
  // on engineering shear (gamma = 2 eps) the same energy c7 eps4^2 gives C44 = c7 = C0_44 (D1).
  C(3, 3) = c[6];
  C(4, 4) = c[7];
  C(5, 5) = c[8];
  return C;
}

Matrix6 c0_from_engineering(double E1, double E2, double E3, double nu12, double nu13, double nu23,
                            double mu12, double mu13, double mu23) {
  const double nu21 = nu12 * E2 / E1, nu31 = nu13 * E3 / E1, nu32 = nu23 * E3 / E2;
  const double Y = 1.0 / (1 - nu12 * nu21 - nu23 * nu32 - nu13 * nu31 - 2 * nu21 * nu32 * nu13);
  Matrix6 C = Matrix6::Zero();
  C(0, 0) = E1 * (1 - nu23 * nu32) * Y;
  C(1, 1) = E2 * (1 - nu13 * nu31) * Y;
  C(2, 2) = E3 * (1 - nu12 * nu21) * Y;
  C(1, 2) = C(2, 1) = E2 * (nu32 + nu12 * nu31) * Y;
  C(0, 2) = C(2, 0) = E3 * (nu13 + nu12 * nu23) * Y;
  // The printed C12 formula from engineering constants (and the repair E1 (nu21 + nu31*nu32)) is
  // not the orthotropic inverse, which requires nu31*nu23 (decision D1b; tested against the
  // compliance matrix).
  C(0, 1) = C(1, 0) = E1 * (nu21 + nu31 * nu23) * Y;
  C(3, 3) = mu23;
  C(4, 4) = mu13;
  C(5, 5) = mu12;
  return C;
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
