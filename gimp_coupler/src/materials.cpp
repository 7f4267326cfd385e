// Constitutive laws of the GIMP solver (materials.hpp). SI units.
#include "pnc/gimp_coupler/materials.hpp"

#include "pnc/core/error.hpp"
#include "pnc/fe_material/material.hpp"

#include "material_checks.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace pnc::gimp {

void detail::check_jacobian(double J, const char* law) {
  if (!(J > 0.0) || !std::isfinite(J)) {
    std::ostringstream s;
    s << law << ": det F = " << J << ": the deformation gradient must have det F > 0";
    throw std::runtime_error(s.str());
  }
}

// ---------------------------------------------------------------- many particles (D264)
void Material::update_many(std::size_t n, const Mat3* F0, const Mat3* F1, double* state,
                           std::size_t stride, Mat3* sigma, double* W) const {
  std::vector<double> s1(std::max<std::size_t>(stride, 1));
  for (std::size_t i = 0; i < n; ++i) {
    double* s = state + i * stride;
    try {
      update(F0[i], F1[i], s, s1.data(), sigma[i], W[i]);
    } catch (const pnc::InputError&) {
      throw;
    } catch (const std::exception& ex) {
      throw PointFailure(i, ex.what());
    }
    std::copy(s1.begin(), s1.begin() + static_cast<std::ptrdiff_t>(stride), s);
  }
}

// ---------------------------------------------------------------- St Venant-Kirchhoff
LinearElastic::LinearElastic(double rho0, double E, double nu)
    : Material(rho0), E_(E), nu_(nu), lambda_(E * nu / ((1 + nu) * (1 - 2 * nu))),
      mu_(E / (2 * (1 + nu))) {}

void LinearElastic::update(const Mat3& /*F0*/, const Mat3& F1, const double* /*s0*/, double* /*s1*/,
                           Mat3& sigma, double& W) const {
  const double J = F1.determinant();
  detail::check_jacobian(J, "linear_elastic");
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

// HyperelasticPolymer::update, update_many: hyperelastic.cpp (D405).

// ---------------------------------------------------------------- polar decomposition
namespace {
/// F = R U for F = [F2 0; 0 F33] with det F2 > 0 and F33 > 0 (plane strain: F33 = 1), in closed
/// form (D408): R2 is the rotation by theta with (cos, sin) = (a + d, c - b) / rho,
/// rho = |(a + d, c - b)| = sqrt(|F2|^2 + 2 det F2) > 0, the one that makes R2^T F2 symmetric;
/// U2 = R2^T F2 (trace rho, det = det F2 > 0: positive definite), its two off-diagonal values
/// averaged (equal but for rounding). False if F is not of that form.
bool polar_decomposition_plane(const Mat3& F, Mat3& R, Mat3& U) {
  if (F(0, 2) != 0.0 || F(1, 2) != 0.0 || F(2, 0) != 0.0 || F(2, 1) != 0.0 || !(F(2, 2) > 0.0))
    return false;
  const double a = F(0, 0), b = F(0, 1), c = F(1, 0), d = F(1, 1);
  if (!(a * d - b * c > 0.0)) return false;
  const double rho = std::hypot(a + d, c - b);
  if (!(rho > 0.0) || !std::isfinite(rho)) return false;
  const double co = (a + d) / rho, si = (c - b) / rho;
  R << co, -si, 0.0, si, co, 0.0, 0.0, 0.0, 1.0;
  const double u01 = 0.5 * ((co * b + si * d) + (co * c - si * a));
  U << co * a + si * c, u01, 0.0, u01, co * d - si * b, 0.0, 0.0, 0.0, F(2, 2);
  return true;
}

/// F = R U for det F > 0 by Higham's Newton iteration on the rotation (D412): X <- (g X +
/// X^-T / g) / 2 from X = F, with the Frobenius-norm scaling g = (|X^-1| / |X|)^(1/2) while the
/// step is large, unscaled once it is below 1e-2 |X|, stopping when a step is below 1e-9 |X|:
/// that step is the error of the iterate it started from, and the quadratic convergence
/// (error <= |X^-1| e^2 / 2) leaves the new iterate at a rounding-level error for |X^-1| up to
/// 10^6.
/// U = R^T F, symmetrised. Every iterate has a positive determinant, so R is a rotation.
/// False (the caller takes the eigen solver) if det F is not positive and finite or the
/// iteration has not converged within 40 steps.
bool polar_decomposition_newton(const Mat3& F, Mat3& R, Mat3& U) {
  const double det = F.determinant();
  if (!(det > 0.0) || !std::isfinite(det)) return false;
  Mat3 X = F;
  bool scaled = true;
  for (int k = 0; k < 40; ++k) {
    const Mat3 Xi = X.inverse();
    const double g = scaled ? std::sqrt(std::sqrt(Xi.squaredNorm() / X.squaredNorm())) : 1.0;
    const Mat3 Xn = 0.5 * (g * X + Xi.transpose() / g);
    const double step = (Xn - X).norm(), size = Xn.norm();
    X = Xn;
    if (!std::isfinite(step)) return false;
    if (step < 1e-9 * size) {
      R = X;
      const Mat3 Ur = X.transpose() * F;
      U = 0.5 * (Ur + Ur.transpose());
      return true;
    }
    if (step < 1e-2 * size) scaled = false;
  }
  return false;
}
} // namespace

void polar_decomposition(const Mat3& F, Mat3& R, Mat3& U) {
  if (polar_decomposition_plane(F, R, U)) return;
  if (polar_decomposition_newton(F, R, U)) return;
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
  detail::check_jacobian(F1.determinant(), "damage_card");
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

namespace {
// Scratch of DamageLaw::update_many, one per thread, grown to the largest batch seen: no
// allocation per particle and none per call once grown.
struct BatchScratch {
  std::vector<double> e0, de, st, sig, W;
  std::vector<int> status;
  std::vector<Mat3> R1, U1;
  void resize(std::size_t n, std::size_t ns) {
    if (e0.size() >= 6 * n && st.size() >= ns * n) return;
    e0.resize(6 * n);
    de.resize(6 * n);
    st.resize(std::max<std::size_t>(ns * n, 1));
    sig.resize(6 * n);
    W.resize(n);
    status.resize(n);
    R1.resize(n);
    U1.resize(n);
  }
};
} // namespace

void DamageLaw::update_many(std::size_t n, const Mat3* F0, const Mat3* F1, double* state,
                            std::size_t stride, Mat3* sigma, double* W) const {
  update_many_cached(n, F0, F1, state, stride, nullptr, 0, sigma, W); // no scratch: no reuse
}

void DamageLaw::update_many_cached(std::size_t n, const Mat3* F0, const Mat3* F1, double* state,
                                   std::size_t stride, double* scratch, std::size_t scratch_stride,
                                   Mat3* sigma, double* W) const {
  if (!law_->has_batch()) {
    Material::update_many(n, F0, F1, state, stride, sigma, W);
    return;
  }
  // The points before the first det F1 <= 0 go through the batch; that point (if any) fails
  // after them, as in the per-particle loop.
  std::size_t m = 0;
  for (; m < n; ++m) {
    const double J = F1[m].determinant();
    if (!(J > 0.0) || !std::isfinite(J)) break;
  }
  const auto ns = static_cast<std::size_t>(n_state_);
  thread_local BatchScratch b;
  b.resize(m, ns);
  const Mat3 I = Mat3::Identity();
  constexpr std::size_t kF = 9 * sizeof(double);
  for (std::size_t i = 0; i < m; ++i) { // eps = U - I (D32), component blocks of ld = m
    // eps of F0: the point's scratch when it holds this F0 (the last step's F1), else computed
    double* c = scratch ? scratch + i * scratch_stride : nullptr;
    std::array<double, 6> e0;
    if (c && std::memcmp(c, F0[i].data(), kF) == 0) {
      std::copy_n(c + 9, 6, e0.begin());
    } else {
      Mat3 R0, U0;
      polar_decomposition(F0[i], R0, U0);
      e0 = to_voigt_strain(U0 - I);
    }
    polar_decomposition(F1[i], b.R1[i], b.U1[i]);
    const auto e1 = to_voigt_strain(b.U1[i] - I);
    if (c) { // (a pure function of F1: right whatever happens to the step)
      std::memcpy(c, F1[i].data(), kF);
      std::copy(e1.begin(), e1.end(), c + 9);
    }
    for (std::size_t k = 0; k < 6; ++k) {
      b.e0[k * m + i] = e0[k];
      b.de[k * m + i] = e1[k] - e0[k];
    }
    for (std::size_t k = 0; k < ns; ++k)
      b.st[k * m + i] = state[i * stride + k];
  }
  pnc_material_point_soa v;
  pnc_material_point_soa_init(&v);
  v.tangent_request = PNC_MATERIAL_TANGENT_NONE;
  v.ld = m;
  v.strain0 = b.e0.data();
  v.dstrain = b.de.data();
  v.state0 = b.st.data();
  v.state1 = b.st.data(); // in place (allowed: state1 == state0)
  v.stress = b.sig.data();
  v.stored_energy = b.W.data();
  v.status = b.status.data();
  const int rc = m > 0 ? law_->try_integrate_batch(m, &v) : PNC_MATERIAL_OK;
  if (rc != PNC_MATERIAL_OK && v.n_failed == 0) { // a refused batch: the per-particle loop
    Material::update_many(n, F0, F1, state, stride, sigma, W);
    return;
  }
  const std::size_t first_bad = v.n_failed > 0 ? v.first_failed : m;
  for (std::size_t i = 0; i < first_bad; ++i) {
    for (std::size_t k = 0; k < ns; ++k)
      state[i * stride + k] = b.st[k * m + i];
    std::array<double, 6> sg;
    for (std::size_t k = 0; k < 6; ++k)
      sg[k] = b.sig[k * m + i];
    W[i] = b.W[i];
    // Biot stress T to Cauchy, as update(): sigma = J^-1 R sym(T U) R^T (D32).
    const Mat3 T = from_voigt_stress(sg);
    const Mat3 TU = T * b.U1[i];
    sigma[i] = b.R1[i] * (0.5 * (TU + TU.transpose())) * b.R1[i].transpose() / F1[i].determinant();
  }
  if (first_bad < n) { // the first failed point: update() gives its message
    std::vector<double> s1(std::max<std::size_t>(ns, 1));
    try {
      update(F0[first_bad], F1[first_bad], state + first_bad * stride, s1.data(), sigma[first_bad],
             W[first_bad]);
    } catch (const pnc::InputError&) {
      throw;
    } catch (const std::exception& ex) {
      throw PointFailure(first_bad, ex.what());
    }
    throw PointFailure(first_bad, "damage_card: the batched entry refused this point and the "
                                  "single-point entry did not");
  }
}

} // namespace pnc::gimp
