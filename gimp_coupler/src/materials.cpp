// Constitutive laws of the GIMP solver (materials.hpp). SI units.
#include "pnc/gimp_coupler/materials.hpp"

#include "pnc/fe_material/material.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace pnc::gimp {

namespace {
void check_jacobian(double J, const char* law) {
  if (!(J > 0.0) || !std::isfinite(J)) {
    std::ostringstream s;
    s << law << ": det F = " << J << ": the deformation gradient must have det F > 0";
    throw std::runtime_error(s.str());
  }
}
} // namespace

// ---------------------------------------------------------------- St Venant-Kirchhoff
LinearElastic::LinearElastic(double rho0, double E, double nu)
    : Material(rho0), E_(E), nu_(nu), lambda_(E * nu / ((1 + nu) * (1 - 2 * nu))),
      mu_(E / (2 * (1 + nu))) {}

void LinearElastic::update(const Mat3& /*F0*/, const Mat3& F1, const double* /*s0*/, double* /*s1*/,
                           Mat3& sigma, double& W) const {
  const double J = F1.determinant();
  check_jacobian(J, "linear_elastic");
  const Mat3 E = 0.5 * (F1.transpose() * F1 - Mat3::Identity());
  const double tr = E.trace();
  const Mat3 S = lambda_ * tr * Mat3::Identity() + 2.0 * mu_ * E;
  sigma = F1 * S * F1.transpose() / J;
  W = 0.5 * lambda_ * tr * tr + mu_ * E.squaredNorm();
}

double LinearElastic::wave_speed() const {
  return std::sqrt((lambda_ + 2 * mu_) / rho0_);
}

// ---------------------------------------------------------------- hyperelastic polymer
HyperelasticPolymer::HyperelasticPolymer(double rho0, double c1, double c2)
    : Material(rho0), c1_(c1), c2_(c2) {}

std::pair<double, double> HyperelasticPolymer::calibrate(double E, double nu) {
  const double K = E / (3 * (1 - 2 * nu));
  const double mu = E / (2 * (1 + nu));
  return {K / 8.0, mu / 38.0};
}

double HyperelasticPolymer::youngs_modulus() const {
  const double K = 8 * c1_, mu = 38 * c2_;
  return 9 * K * mu / (3 * K + mu);
}
double HyperelasticPolymer::poisson_ratio() const {
  const double K = 8 * c1_, mu = 38 * c2_;
  return (3 * K - 2 * mu) / (2 * (3 * K + mu));
}
double HyperelasticPolymer::wave_speed() const {
  const double K = 8 * c1_, mu = 38 * c2_;
  return std::sqrt((K + 4.0 * mu / 3.0) / rho0_);
}

double HyperelasticPolymer::energy(const Mat3& C) const {
  const double I1 = C.trace();
  const double I2 = 0.5 * (I1 * I1 - (C * C).trace());
  const double I3 = C.determinant();
  return c1_ * (I3 - 1) * (I3 - 1) +
         c2_ * (I1 / std::cbrt(I3) + 3 * I2 * I2 / std::pow(I3, 4.0 / 3.0) - 30.0);
}

Mat3 HyperelasticPolymer::pk2(const Mat3& C) const {
  const Mat3 I = Mat3::Identity();
  const Mat3 Ci = C.inverse();
  const double I1 = C.trace();
  const double I2 = 0.5 * (I1 * I1 - (C * C).trace());
  const double I3 = C.determinant();
  const double r1 = 1.0 / std::cbrt(I3); // I3^(-1/3)
  const double I2b = I2 * r1 * r1;       // I2 / I3^(2/3)
  const Mat3 dW = 2 * c1_ * (I3 - 1) * I3 * Ci + c2_ * r1 * (I - I1 / 3.0 * Ci) +
                  6 * c2_ * I2b * r1 * r1 * (I1 * I - C - 2.0 / 3.0 * I2 * Ci);
  return 2.0 * dW;
}

void HyperelasticPolymer::update(const Mat3& /*F0*/, const Mat3& F1, const double* /*s0*/,
                                 double* /*s1*/, Mat3& sigma, double& W) const {
  const double J = F1.determinant();
  check_jacobian(J, "hyperelastic_polymer");
  // sigma = J^-1 F S F^T written with b = F F^T (F C^-1 F^T = I, F C F^T = b^2).
  const Mat3 b = F1 * F1.transpose();
  const Mat3 b2 = b * b;
  const double I1 = b.trace();
  const double I2 = 0.5 * (I1 * I1 - b2.trace());
  const double I3 = J * J;
  const double cj = std::cbrt(J);
  const double r1 = 1.0 / (cj * cj); // I3^(-1/3) = J^(-2/3)
  const double I2b = I2 * r1 * r1;
  const Mat3 I = Mat3::Identity();
  sigma = (2.0 / J) * (2 * c1_ * (I3 - 1) * I3 * I + c2_ * r1 * (b - I1 / 3.0 * I) +
                       6 * c2_ * I2b * r1 * r1 * (I1 * b - b2 - 2.0 / 3.0 * I2 * I));
  W = c1_ * (I3 - 1) * (I3 - 1) + c2_ * (I1 * r1 + 3 * I2b * I2b - 30.0);
}

// ---------------------------------------------------------------- polar decomposition
void polar_decomposition(const Mat3& F, Mat3& R, Mat3& U) {
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.compute(F.transpose() * F); // QR iterations: accurate to round-off (computeDirect is not)
  const Eigen::Vector3d lam = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  const Mat3& Q = es.eigenvectors();
  U = Q * lam.asDiagonal() * Q.transpose();
  R = F * (Q * lam.cwiseInverse().asDiagonal() * Q.transpose());
}

std::array<double, 6> to_voigt_strain(const Mat3& e) {
  return {e(0, 0), e(1, 1), e(2, 2), e(1, 2) + e(2, 1), e(0, 2) + e(2, 0), e(0, 1) + e(1, 0)};
}

Mat3 from_voigt_stress(const std::array<double, 6>& s) {
  Mat3 m;
  m << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
  return m;
}

// ---------------------------------------------------------------- damage law (plugin)
// Everything the solver needs of the law comes from the plugin's queries (ABI 1.1, D214): the
// undamaged stiffness for the CFL wave speed, the moduli by compliance inversion, the state
// names; the energy of a step from the integration itself.
DamageLaw::DamageLaw(double rho0, std::shared_ptr<const pnc::fe_material::Material> law)
    : Material(rho0), law_(std::move(law)), n_state_(law_->n_state()), names_(law_->state_names()) {
  // M: the largest normal entry of [C0] (global frame), the longitudinal modulus along the
  // stiffest axis (materials.hpp wave_speed()).
  const pnc::fe_material::Tangent36 C0 = law_->elastic_stiffness();
  const double M = std::max(C0[0], std::max(C0[7], C0[14]));
  c_ = std::sqrt(M / rho0_);
}

void DamageLaw::init_state(double* s) const {
  law_->init_state(s);
}

double DamageLaw::youngs_modulus() const {
  return law_->property("youngs_modulus_1");
}
double DamageLaw::poisson_ratio() const {
  return law_->property("poisson_ratio_12");
}

void DamageLaw::update(const Mat3& F0, const Mat3& F1, const double* s0, double* s1, Mat3& sigma,
                       double& W) const {
  check_jacobian(F1.determinant(), "damage_card");
  // Small strain eps = U - I of F = R U (decision D32).
  Mat3 R0, U0, R1, U1;
  polar_decomposition(F0, R0, U0);
  polar_decomposition(F1, R1, U1);
  const auto e0 = to_voigt_strain(U0 - Mat3::Identity());
  const auto e1 = to_voigt_strain(U1 - Mat3::Identity());
  std::array<double, 6> de{}, sig{};
  for (int i = 0; i < 6; ++i)
    de[i] = e1[i] - e0[i];
  // W = 1/2 T . eps: the plugin's stored energy of the secant law (decision D32).
  W = law_->integrate2(s0, s1, e0.data(), de.data(), sig.data(), nullptr, PNC_MATERIAL_TANGENT_NONE)
          .stored;
  // The plugin's stress T is read as the Biot stress, work-conjugate to U (decision D32):
  // P = R T, sigma = J^-1 P F^T = J^-1 R sym(T U) R^T (sym: exact for coaxial T, U).
  const Mat3 T = from_voigt_stress(sig);
  const Mat3 TU = T * U1;
  sigma = R1 * (0.5 * (TU + TU.transpose())) * R1.transpose() / F1.determinant();
}

} // namespace pnc::gimp
