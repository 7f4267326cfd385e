// Constitutive laws: stress-free reference, objectivity, small-strain limits, derivatives.
#include "pnc/gimp_coupler/materials.hpp"

#include "pnc/damage/reference.hpp"
#include "pnc/fe_material/material.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

using namespace pnc::gimp;

namespace {
Mat3 rot(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}
Mat3 sample_F() {
  Mat3 F;
  F << 1.12, 0.07, -0.03, 0.02, 0.93, 0.05, -0.04, 0.01, 1.05;
  return F;
}
/// Small-strain stiffness C_ijkl e_kl -> d sigma / d eps (6x6, engineering Voigt) by central
/// differences of the law at F = I + eps.
Eigen::Matrix<double, 6, 6> small_strain_stiffness(const Material& m) {
  Eigen::Matrix<double, 6, 6> C;
  const int idx[6][2] = {{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};
  const double h = 1e-6;
  for (int j = 0; j < 6; ++j) {
    Mat3 e = Mat3::Zero();
    const double amt = j < 3 ? h : 0.5 * h; // engineering shear gamma = h
    e(idx[j][0], idx[j][1]) += amt;
    if (j >= 3) e(idx[j][1], idx[j][0]) += amt;
    Mat3 sp, sm;
    double W;
    std::vector<double> s0(8), s1(8);
    m.init_state(s0.data());
    m.update(Mat3::Identity(), Mat3::Identity() + e, s0.data(), s1.data(), sp, W);
    m.update(Mat3::Identity(), Mat3::Identity() - e, s0.data(), s1.data(), sm, W);
    const Mat3 d = (sp - sm) / (2 * h);
    for (int i = 0; i < 6; ++i)
      C(i, j) = d(idx[i][0], idx[i][1]);
  }
  return C;
}
void expect_isotropic(const Eigen::Matrix<double, 6, 6>& C, double E, double nu, double tol) {
  const Eigen::Matrix<double, 6, 6> S = C.inverse();
  EXPECT_NEAR(1.0 / S(0, 0), E, tol * E);
  EXPECT_NEAR(-S(0, 1) / S(0, 0), nu, tol);
  EXPECT_NEAR(C(3, 3), E / (2 * (1 + nu)), tol * E);
}
} // namespace

TEST(GimpMaterials, HyperelasticStressFreeAndEnergyZeroAtIdentity) {
  const HyperelasticPolymer m(1200, 34.3e6, 9.59e6);
  Mat3 s;
  double W = 1;
  m.update(Mat3::Identity(), Mat3::Identity(), nullptr, nullptr, s, W);
  EXPECT_LT(s.norm(), 1e-6);
  EXPECT_NEAR(W, 0.0, 1e-6);
  EXPECT_LT(m.pk2(Mat3::Identity()).norm(), 1e-6);
}

TEST(GimpMaterials, HyperelasticStressIsDerivativeOfEnergy) {
  const HyperelasticPolymer m(1200, 1.8e8, 1.5e7);
  const Mat3 F = sample_F();
  const Mat3 C = F.transpose() * F;
  const Mat3 S = m.pk2(C);
  // S = 2 dW/dC, checked component by component (symmetric perturbation).
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Mat3 d = Mat3::Zero();
      const double h = 1e-7;
      d(i, j) += 0.5 * h;
      d(j, i) += 0.5 * h;
      // (W(C + d) - W(C - d)) / h = 2 dW/dC_ij for this symmetric perturbation.
      const double fd = (m.energy(C + d) - m.energy(C - d)) / h;
      EXPECT_NEAR(S(i, j), fd, 1e-5 * S.norm()) << i << j;
    }
  // The b-form Cauchy stress of update() equals J^-1 F S F^T.
  Mat3 sigma;
  double W;
  m.update(Mat3::Identity(), F, nullptr, nullptr, sigma, W);
  const Mat3 ref = F * S * F.transpose() / F.determinant();
  EXPECT_LT((sigma - ref).norm(), 1e-10 * ref.norm());
  EXPECT_NEAR(W, m.energy(C), 1e-10 * std::abs(W));
}

TEST(GimpMaterials, HyperelasticSmallStrainLimitAndCalibration) {
  // Closed form: K = 8 c1, mu = 38 c2 (decision D31), checked by differentiating the law.
  const auto [c1, c2] = HyperelasticPolymer::calibrate(1.5e9, 0.33);
  EXPECT_NEAR(c1, 1.5e9 / (3 * (1 - 0.66)) / 8, 1.0);
  EXPECT_NEAR(c2, 1.5e9 / (2 * 1.33) / 38, 1.0);
  const HyperelasticPolymer m(1200, c1, c2);
  EXPECT_NEAR(m.youngs_modulus(), 1.5e9, 1e-3);
  EXPECT_NEAR(m.poisson_ratio(), 0.33, 1e-12);
  expect_isotropic(small_strain_stiffness(m), 1.5e9, 0.33, 1e-5);
  // The printed constants give a different limit (reported in D31).
  const HyperelasticPolymer printed(1200, 34.3e6, 9.59e6);
  expect_isotropic(small_strain_stiffness(printed), printed.youngs_modulus(),
                   printed.poisson_ratio(), 1e-5);
  EXPECT_GT(std::abs(printed.youngs_modulus() - 1.5e9), 0.3e9);
}

TEST(GimpMaterials, LinearElasticSmallStrainIsHooke) {
  const LinearElastic m(7800, 2e11, 0.3);
  expect_isotropic(small_strain_stiffness(m), 2e11, 0.3, 1e-5);
  EXPECT_NEAR(m.wave_speed(), std::sqrt(2e11 * 0.7 / (1.3 * 0.4) / 7800), 1e-9);
}

TEST(GimpMaterials, AllLawsAreObjective) {
  auto dm = std::make_shared<const pnc::fe_material::Material>(
      pnc::fe_material::Material::from_constants("pp", [] {
        const auto p = pnc::damage::dissertation_parameters(pnc::damage::Model::pp);
        return std::vector<double>(p.k.begin(), p.k.begin() + static_cast<long>(p.size()));
      }()));
  const LinearElastic le(1000, 1e9, 0.3);
  const HyperelasticPolymer hp(1000, 1.8e8, 1.5e7);
  const DamageLaw dl(1000, dm);
  const Mat3 F = sample_F();
  const Mat3 Q = rot(1.234, Eigen::Vector3d(0.3, -1.0, 0.5));
  for (const Material* m : std::vector<const Material*>{&le, &hp, &dl}) {
    std::vector<double> s0(8), s1(8), s1b(8);
    m->init_state(s0.data());
    Mat3 a, b;
    double Wa, Wb;
    m->update(Mat3::Identity(), F, s0.data(), s1.data(), a, Wa);
    m->update(Mat3::Identity(), Q * F, s0.data(), s1b.data(), b, Wb);
    EXPECT_LT((b - Q * a * Q.transpose()).norm(), 1e-9 * a.norm()) << m->type();
    EXPECT_NEAR(Wa, Wb, 1e-9 * std::abs(Wa)) << m->type();
    for (int k = 0; k < m->n_state(); ++k)
      EXPECT_NEAR(s1[k], s1b[k], 1e-12) << m->type();
  }
}

TEST(GimpMaterials, PolarDecomposition) {
  const Mat3 F = rot(0.7, Eigen::Vector3d(1, 2, 3)) * sample_F();
  Mat3 R, U;
  polar_decomposition(F, R, U);
  EXPECT_LT((R * U - F).norm(), 1e-13);
  EXPECT_LT((R.transpose() * R - Mat3::Identity()).norm(), 1e-13);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-13);
  EXPECT_LT((U - U.transpose()).norm(), 1e-13);
}
