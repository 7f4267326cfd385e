// Constitutive laws: stress-free reference, objectivity, small-strain limits, derivatives.
#include "pnc/gimp_coupler/materials.hpp"

#include "inverse_cbrt.hpp" // private (gimp_coupler/src)

#include "pnc/damage/reference.hpp"
#include "pnc/fe_material/material.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>

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

// Material::update_many (the solver's particle update, D264): a damage card through the
// plugin's batched entry gives, for every particle, the Cauchy stress and the state of
// update() bit for bit (the same operations on the same numbers, D261), and the stored
// energy to the rounding of one 6-term dot product in another order. Points of all three
// paths (elastic, damaging, unloading), both models, rotated deformations; the default
// update_many of a law without a batched entry gives the loop's numbers bit for bit.
namespace {
std::shared_ptr<const pnc::fe_material::Material> card_law(pnc::damage::Model model) {
  const auto p = pnc::damage::dissertation_parameters(model);
  return std::make_shared<const pnc::fe_material::Material>(
      pnc::fe_material::Material::from_constants(
          pnc::damage::model_name(model),
          std::vector<double>(p.k.begin(), p.k.begin() + static_cast<long>(p.size()))));
}
} // namespace

TEST(GimpMaterials, UpdateManyEqualsUpdateOnEveryPathAndNamesTheFirstFailedPoint) {
  std::mt19937 rng(20261203);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (auto model : {pnc::damage::Model::pp, pnc::damage::Model::pnc}) {
    auto dm = card_law(model);
    const DamageLaw dl(1000, dm);
    const LinearElastic le(1000, 1e9, 0.3);
    const std::size_t n = 53, ns = static_cast<std::size_t>(dl.n_state()), stride = ns + 1;
    std::vector<Mat3> F0(n), F1(n);
    std::vector<double> state(n * stride, -7.0); // the padding entry must stay untouched
    for (std::size_t i = 0; i < n; ++i) {
      const Mat3 Q = rot(3.0 * u(rng), Eigen::Vector3d(u(rng), u(rng), 1.0));
      Mat3 e;
      e << u(rng), u(rng), u(rng), 0, u(rng), u(rng), 0, 0, u(rng);
      e = 0.5 * (e + e.transpose());
      // path by i % 3: small strain (elastic), large (damage growth), large then back to a
      // quarter of it (unloading from the damaged state of the first step)
      const double amp = i % 3 == 0 ? 0.004 : 0.35;
      F0[i] = Q * (Mat3::Identity() + (i % 3 == 2 ? amp : 0.0) * e);
      F1[i] = Q * (Mat3::Identity() + (i % 3 == 2 ? 0.25 * amp : amp) * e);
      double* s = state.data() + i * stride;
      dl.init_state(s);
      if (i % 3 == 2) { // damage the start state
        std::vector<double> s1(ns);
        Mat3 sg;
        double W;
        dl.update(Mat3::Identity(), F0[i], s, s1.data(), sg, W);
        std::copy(s1.begin(), s1.end(), s);
      }
    }
    // reference: update() point by point
    std::vector<Mat3> sig_ref(n);
    std::vector<double> W_ref(n), st_ref(state);
    int damaging = 0, damaged_start = 0;
    for (std::size_t i = 0; i < n; ++i) {
      std::vector<double> s1(ns);
      dl.update(F0[i], F1[i], state.data() + i * stride, s1.data(), sig_ref[i], W_ref[i]);
      std::copy(s1.begin(), s1.end(), st_ref.begin() + static_cast<long>(i * stride));
      for (std::size_t k = 0; k < ns; ++k) {
        damaging += s1[k] != state[i * stride + k];
        damaged_start += i % 3 == 2 && state[i * stride + k] > 0.0 && k + 1 == ns;
      }
    }
    ASSERT_GT(damaging, 10) << "the large strains must grow damage";
    ASSERT_GT(damaged_start, 0);
    std::vector<Mat3> sig(n);
    std::vector<double> W(n), st(state);
    dl.update_many(n, F0.data(), F1.data(), st.data(), stride, sig.data(), W.data());
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(sig[i], sig_ref[i]) << "point " << i;
      // W = 1/2 T . eps in the batch's summation order: bound 8 u sum |T_k eps_k| / 2
      std::array<double, 6> e0{}, de{}, T{};
      Mat3 R, U0, U1;
      polar_decomposition(F0[i], R, U0);
      polar_decomposition(F1[i], R, U1);
      const auto a0 = to_voigt_strain(U0 - Mat3::Identity());
      const auto a1 = to_voigt_strain(U1 - Mat3::Identity());
      for (int k = 0; k < 6; ++k) {
        e0[static_cast<std::size_t>(k)] = a0[static_cast<std::size_t>(k)];
        de[static_cast<std::size_t>(k)] =
            a1[static_cast<std::size_t>(k)] - a0[static_cast<std::size_t>(k)];
      }
      std::vector<double> s1(ns);
      dm->integrate2(state.data() + i * stride, s1.data(), e0.data(), de.data(), T.data(), nullptr,
                     PNC_MATERIAL_TANGENT_NONE);
      double mag = 0.0;
      for (std::size_t k = 0; k < 6; ++k)
        mag += std::abs(T[k] * a1[k]);
      EXPECT_LE(std::abs(W[i] - W_ref[i]), 8 * std::numeric_limits<double>::epsilon() * 0.5 * mag)
          << "point " << i;
    }
    EXPECT_EQ(st, st_ref); // state bit for bit, padding untouched

    // a particle that fails (det F <= 0) and a later one: the first is named, with the
    // message of update(), and the particles before it are written
    std::vector<Mat3> G1(F1);
    G1[17] = -F1[17];
    G1[30](0, 0) = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> st2(state);
    std::vector<Mat3> sig2(n);
    std::vector<double> W2(n);
    std::string single;
    try {
      std::vector<double> s1(ns);
      Mat3 sg;
      double w;
      dl.update(F0[17], G1[17], state.data() + 17 * stride, s1.data(), sg, w);
    } catch (const std::exception& ex) {
      single = ex.what();
    }
    ASSERT_FALSE(single.empty());
    try {
      dl.update_many(n, F0.data(), G1.data(), st2.data(), stride, sig2.data(), W2.data());
      ADD_FAILURE() << "no PointFailure";
    } catch (const PointFailure& ex) {
      EXPECT_EQ(ex.index(), 17u);
      EXPECT_EQ(std::string(ex.what()), single);
    }
    for (std::size_t i = 0; i < 17; ++i)
      EXPECT_EQ(sig2[i], sig_ref[i]) << "point " << i;

    // the default loop (a law without a batched entry) is update() bit for bit
    std::vector<Mat3> sl(n), sl_ref(n);
    std::vector<double> Wl(n), Wl_ref(n);
    for (std::size_t i = 0; i < n; ++i)
      le.update(F0[i], F1[i], nullptr, nullptr, sl_ref[i], Wl_ref[i]);
    le.update_many(n, F0.data(), F1.data(), nullptr, 0, sl.data(), Wl.data());
    EXPECT_EQ(sl, sl_ref);
    EXPECT_EQ(Wl, Wl_ref);
  }
}

// D405: x^(-1/3) of the hyperelastic law without libm. The last Newton step starts from a
// relative error below 3e-10 (4 % initial guess, error -> 2 e^2 per step), so its truncation
// error is below 2e-19; its roundings are y*y, *y, x*(..) (3 u on x y^3 ~ 1, absolute), 4 - t
// (u on ~3), y*(..), the rounded constant 1/3 and the last product: at most 5 u relative to
// first order (u = 2^-53). Reference: cbrtl in long double (64-bit mantissa).
TEST(GimpMaterials, InverseCubeRootIsWithinItsRoundingBound) {
  const long double u = 0x1p-53L, bound = 5 * u + 1e-18L;
  std::mt19937 rng(405);
  std::uniform_real_distribution<double> logx(-1000.0, 1000.0), near1(-0.5, 0.5);
  auto check = [&](double x) {
    const double y = detail::inverse_cbrt(x);
    const long double ref = 1.0L / cbrtl(static_cast<long double>(x));
    ASSERT_LE(std::fabs(y / ref - 1.0L), bound) << "x = " << x << ", y = " << y;
  };
  for (int k = 0; k < 200000; ++k) {
    check(std::exp2(logx(rng)));
    check(1.0 + near1(rng)); // the det F of a solid's deformation
  }
  for (double x : {1.0, 8.0, 0.125, 0x1p-1000, 0x1p1000, 0x1.fffffffffffffp-1001, 0x1p1001,
                   1e-310 /* subnormal: libm fallback */, 1e308})
    check(x);
}

TEST(GimpMaterials, HyperelasticUpdateManyEqualsUpdateAndNamesTheFailedPoint) {
  const HyperelasticPolymer m(1200, 1.8e8, 1.5e7);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-0.3, 0.3);
  const std::size_t n = 37;
  std::vector<Mat3> F(n), sig(n);
  std::vector<double> W(n);
  for (auto& f : F) {
    f = Mat3::Identity();
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        f(i, k) += U(rng);
  }
  m.update_many(n, F.data(), F.data(), nullptr, 0, sig.data(), W.data());
  for (std::size_t i = 0; i < n; ++i) {
    Mat3 s;
    double w;
    m.update(F[i], F[i], nullptr, nullptr, s, w);
    EXPECT_EQ(s, sig[i]);
    EXPECT_EQ(w, W[i]);
    EXPECT_EQ(s, s.transpose()) << "Cauchy stress not symmetric";
  }
  F[23](0, 0) = -F[23](0, 0) - 5.0; // det F < 0
  try {
    m.update_many(n, F.data(), F.data(), nullptr, 0, sig.data(), W.data());
    FAIL() << "no PointFailure";
  } catch (const PointFailure& ex) {
    EXPECT_EQ(ex.index(), 23u);
    EXPECT_NE(std::string(ex.what()).find("det F"), std::string::npos) << ex.what();
  }
}

// D408: the closed form for plane deformations F = [F2 0; 0 F33]. The three properties that
// define the polar decomposition, each within its rounding bound (u = 2^-53): R U = F within
// 32 u |F|max (cos and sin within 2 u: hypot and a division; each entry of U a two-term product,
// within 8 u |F|max with them; R U another two-term product), R^T R = I within 16 u, det R = 1
// within 16 u, U exactly symmetric and positive definite; the same U as the eigen-solver path of
// a general F (the block perturbed out of plane by 1e-300, below any rounding of the entries)
// within the bound of that path's 1e-13 test.
namespace {
/// F = R U to rounding: R U = F within 32 u |F|_max, R^T R = I and det R = 1 within 16 u
/// (u = 2^-53), U exactly symmetric.
testing::AssertionResult polar_factors_to_rounding(const Mat3& F, const Mat3& R, const Mat3& U) {
  const double u = 0x1p-53, fmax = F.cwiseAbs().maxCoeff();
  if ((R * U - F).cwiseAbs().maxCoeff() > 32 * u * fmax)
    return testing::AssertionFailure() << "R U != F for F =\n" << F;
  if ((R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff() > 16 * u)
    return testing::AssertionFailure() << "R not orthogonal for F =\n" << F;
  if (std::abs(R.determinant() - 1.0) > 16 * u)
    return testing::AssertionFailure() << "det R != 1 for F =\n" << F;
  if (U != U.transpose()) return testing::AssertionFailure() << "U not symmetric for F =\n" << F;
  return testing::AssertionSuccess();
}
} // namespace

TEST(GimpMaterials, GeneralPolarDecompositionIsExactToRoundingAndMatchesTheSvd) {
  // 3-D F with det F > 0 take Higham's Newton iteration (D412). Bounds as for plane F below:
  // R U = F to a few units of rounding of |F|, R a rotation to rounding, U symmetric positive
  // definite; against the polar factors of Eigen's Jacobi SVD F = W S V^T (R = W V^T,
  // U = V S V^T; an independent algorithm), whose perturbation bound for R is |dF| / sigma_min
  // with sigma_min >= 0.2 here: 1e-13 leaves a factor > 10 to both methods' rounding.
  std::mt19937 rng(412);
  std::uniform_real_distribution<double> ang(-3.14159, 3.14159), lst(-1.6, 1.6);
  auto rotation = [&] {
    return Mat3(
        Eigen::AngleAxisd(ang(rng), Eigen::Vector3d(ang(rng), ang(rng), ang(rng)).normalized()));
  };
  int iterations_checked = 0;
  for (int k = 0; k < 20000; ++k) {
    // F = Q diag(l) P^T: any rotations Q, P, stretches from 0.2 to 5; every 7th near identity,
    // every 11th with two equal stretches (a repeated singular value)
    Eigen::Vector3d l(std::exp(lst(rng)), std::exp(lst(rng)), std::exp(lst(rng)));
    if (k % 7 == 0) l = Eigen::Vector3d::Ones() + 1e-3 * l;
    if (k % 11 == 0) l[1] = l[0];
    const Mat3 F = rotation() * l.asDiagonal() * rotation().transpose();
    Mat3 R, U;
    polar_decomposition(F, R, U);
    const double fmax = F.cwiseAbs().maxCoeff();
    ASSERT_TRUE(polar_factors_to_rounding(F, R, U));
    ASSERT_GT(Eigen::SelfAdjointEigenSolver<Mat3>(U).eigenvalues().minCoeff(), 0.0) << F;
    if (k < 2000) {
      const Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
      const Mat3 Rs = svd.matrixU() * svd.matrixV().transpose();
      const Mat3 Us = svd.matrixV() * svd.singularValues().asDiagonal() * svd.matrixV().transpose();
      EXPECT_LT((Rs - R).norm(), 1e-13) << F;
      EXPECT_LT((Us - U).norm(), 1e-13 * fmax) << F;
      ++iterations_checked;
    }
  }
  EXPECT_EQ(iterations_checked, 2000);
  // det F <= 0 (a reflection): not a deformation the iteration takes; the eigen path's R F
  // factorisation still holds
  Mat3 F = Mat3::Identity(), R, U;
  F(2, 2) = -1.0;
  F(0, 1) = 0.3;
  polar_decomposition(F, R, U);
  EXPECT_LE((R * U - F).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(GimpMaterials, PlanePolarDecompositionIsExactToRounding) {
  std::mt19937 rng(408);
  std::uniform_real_distribution<double> ang(-3.14159, 3.14159), lst(-1.6, 1.6), sh(-2.0, 2.0);
  for (int k = 0; k < 20000; ++k) {
    // F2 = Q diag(l1, l2) P^T: any rotation Q, stretches from 0.2 to 5 along any axes P
    const double q = ang(rng), pa = ang(rng), l1 = std::exp(lst(rng)), l2 = std::exp(lst(rng));
    Eigen::Matrix2d Q, P, L = Eigen::Vector2d(l1, l2).asDiagonal();
    Q << std::cos(q), -std::sin(q), std::sin(q), std::cos(q);
    P << std::cos(pa), -std::sin(pa), std::sin(pa), std::cos(pa);
    Mat3 F = Mat3::Identity();
    F.topLeftCorner<2, 2>() = Q * L * P.transpose();
    if (k % 2) F(2, 2) = std::exp(0.3 * sh(rng)); // a 3-D block-diagonal F as well
    Mat3 R, U;
    polar_decomposition(F, R, U);
    const double fmax = F.cwiseAbs().maxCoeff();
    ASSERT_TRUE(polar_factors_to_rounding(F, R, U));
    ASSERT_GT(U.determinant(), 0.0);
    ASSERT_GT(U(0, 0), 0.0);
    if (k < 200) { // against the general (eigen-solver) path
      Mat3 Fg = F, Rg, Ug;
      Fg(0, 2) = 1e-300;
      polar_decomposition(Fg, Rg, Ug);
      EXPECT_LT((Ug - U).norm(), 1e-13 * fmax) << F;
      EXPECT_LT((Rg - R).norm(), 1e-13) << F;
    }
  }
}

// The damage law's scratch between steps (D416): along a path of three steps, update_many_cached
// gives update_many's stress, energy and state bit for bit from a zero scratch, after its
// entries were swapped between points (a reorder: every key misses) and with a padded stride;
// an entry holds the step's F1 and that F1's strain U - I; and a hit is really taken.
TEST(GimpMaterials, TheDamageLawsScratchSkipsTheRepeatedPolarDecompositionAndChangesNoBit) {
  std::mt19937 rng(20261206);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (auto model : {pnc::damage::Model::pp, pnc::damage::Model::pnc}) {
    const DamageLaw dl(1000, card_law(model));
    const std::size_t n = 40, ns = static_cast<std::size_t>(dl.n_state());
    const std::size_t cs = static_cast<std::size_t>(dl.n_scratch()) + 1; // one padding double
    ASSERT_EQ(dl.n_scratch(), 15);
    std::vector<std::array<Mat3, 4>> F(n); // F^0 .. F^3 of each point: growing, rotating strain
    for (std::size_t i = 0; i < n; ++i) {
      Mat3 e;
      e << u(rng), u(rng), u(rng), 0, u(rng), u(rng), 0, 0, u(rng);
      e = 0.5 * (e + e.transpose());
      const Eigen::Vector3d axis(u(rng), u(rng), 1.0);
      for (int k = 0; k < 4; ++k)
        F[i][static_cast<std::size_t>(k)] =
            rot(0.3 * k * u(rng), axis) * (Mat3::Identity() + 0.12 * k * e);
    }
    std::vector<double> st_ref(n * ns), st(n * ns);
    for (std::size_t i = 0; i < n; ++i) {
      dl.init_state(st_ref.data() + i * ns);
      dl.init_state(st.data() + i * ns);
    }
    std::vector<double> scratch(n * cs, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      scratch[i * cs + cs - 1] = -3.0; // the padding must stay untouched
    const std::vector<double> st0 = st;
    int grew = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      std::vector<Mat3> F0(n), F1(n), sig_ref(n), sig(n);
      std::vector<double> W_ref(n), W(n);
      for (std::size_t i = 0; i < n; ++i) {
        F0[i] = F[i][k];
        F1[i] = F[i][k + 1];
      }
      if (k == 2) // a reorder: the entries of neighbours swapped, so that no key matches
        for (std::size_t i = 0; i + 1 < n; i += 2)
          std::swap_ranges(scratch.begin() + static_cast<long>(i * cs),
                           scratch.begin() + static_cast<long>(i * cs + cs - 1),
                           scratch.begin() + static_cast<long>((i + 1) * cs));
      const std::vector<double> before = st_ref;
      dl.update_many(n, F0.data(), F1.data(), st_ref.data(), ns, sig_ref.data(), W_ref.data());
      dl.update_many_cached(n, F0.data(), F1.data(), st.data(), ns, scratch.data(), cs, sig.data(),
                            W.data());
      grew += before != st_ref;
      for (std::size_t i = 0; i < n; ++i) {
        EXPECT_EQ(sig[i], sig_ref[i]) << "step " << k << ", point " << i;
        EXPECT_EQ(W[i], W_ref[i]) << "step " << k << ", point " << i;
        Mat3 R, U;
        polar_decomposition(F1[i], R, U);
        const auto e1 = to_voigt_strain(U - Mat3::Identity());
        const double* c = scratch.data() + i * cs;
        EXPECT_TRUE(std::equal(c, c + 9, F1[i].data())) << "the key is F1, point " << i;
        EXPECT_TRUE(std::equal(c + 9, c + 15, e1.begin())) << "the strain of F1, point " << i;
        EXPECT_EQ(c[15], -3.0);
      }
      EXPECT_EQ(st, st_ref) << "step " << k;
    }
    EXPECT_GE(grew, 2) << "the path must grow damage";
    // a hit is taken: the right key with a non-finite strain makes the point fail (a wrong
    // finite strain would not show: the law reads eps0 + deps, which is F1's strain either way)
    std::vector<double> poisoned(cs, std::numeric_limits<double>::quiet_NaN()),
        s_a(st0.begin(), st0.begin() + static_cast<long>(ns)), s_b(s_a);
    std::copy_n(F[0][1].data(), 9, poisoned.begin());
    Mat3 sa, sb;
    double wa = 0.0, wb = 0.0;
    dl.update_many(1, &F[0][1], &F[0][2], s_a.data(), ns, &sa, &wa);
    EXPECT_TRUE(sa.allFinite());
    EXPECT_THROW(
        dl.update_many_cached(1, &F[0][1], &F[0][2], s_b.data(), ns, poisoned.data(), cs, &sb, &wb),
        PointFailure)
        << "the scratch's strain was not used";
  }
}
