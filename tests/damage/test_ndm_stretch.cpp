// Tests of the NDM kernel's pieces against independent references: closed forms of the
// damage function, the source's energy functions (sigma = dpsi/de, D1), compliance of
// engineering constants, and the mode stretches of D6/D7 (closed forms, Eigen's SVD, finite
// differences). The integration itself: test_ndm_kernel.cpp.
#include "ndm_internal.hpp"
#include "ndm_test_support.hpp"
#include "pnc/core/error.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/damage/moduli.hpp"
#include "pnc/damage/ndm.hpp"
#include "pnc/damage/reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace pnc::damage;
using namespace pnc_ndm_test;

// ---------------------------------------------------------------- damage function
TEST(DamageFunction, CriticalStretchIsTheLennardJonesForcePeak) {
  // r_max/sigma from dF/dr = 0 of F = (24 eps/r)(2 (s/r)^12 - (s/r)^6): (26/7)^(1/6).
  EXPECT_NEAR(critical_stretch(), 1.24446, 5e-6); // printed lambda_c value (docs/theory.md §1.2)
  // Independent check: the force magnitude g(x) = 2x^-13 - x^-7 is extremal there.
  auto g = [](double x) { return 2 * std::pow(x, -13) - std::pow(x, -7); };
  const double lc = critical_stretch(), h = 1e-5;
  EXPECT_NEAR((g(lc + h) - g(lc - h)) / (2 * h), 0.0, 1e-8);
}

TEST(DamageFunction, ContinuousAtOnsetAndSaturatesAtOne) {
  const double lc = critical_stretch();
  EXPECT_EQ(damage_function(lc), 0.0);
  EXPECT_EQ(damage_function(1.0), 0.0);
  EXPECT_NEAR(damage_function(lc * (1 + 1e-9)), 0.0, 1e-12); // no jump at onset
  EXPECT_NEAR(damage_function(1e3), 1.0, 1e-12);             // complete separation
  // The printed prefactor 10.015 = 24/2.396 (|F_max| = 2.396 eps/sigma of the LJ force;
  // docs/theory.md §1.2, D4): reconstruct it from the kernel: D(x) - 1 = k (2x^-13 - x^-7).
  const double x = 1.5;
  const double k = (damage_function(x) - 1) / (2 * std::pow(x, -13) - std::pow(x, -7));
  EXPECT_NEAR(k, 10.015, 5e-4);
  EXPECT_NEAR(24.0 / k, 2.396, 5e-4);
}

TEST(DamageFunction, MonotoneAndDerivativeMatchesFiniteDifference) {
  double prev = 0;
  for (double x = 1.25; x < 4.0; x += 0.01) {
    const double D = damage_function(x);
    EXPECT_GE(D, prev);
    prev = D;
    const double h = 1e-6;
    const double fd = (damage_function(x + h) - damage_function(x - h)) / (2 * h);
    EXPECT_NEAR(damage_function_derivative(x), fd, 1e-6 * (1 + std::abs(fd)));
  }
  // Zero slope at onset: the force peak (dF/dr = 0), so the tangent is continuous there.
  EXPECT_NEAR(damage_function_derivative(critical_stretch() * (1 + 1e-12)), 0.0, 1e-8);
}

// ---------------------------------------------------------------- stiffness
TEST(Stiffness, C0FromEngineeringConstantsHasTheOrthotropicCompliance) {
  const double E1 = 2.0e9, E2 = 1.2e9, E3 = 0.7e9, n12 = 0.3, n13 = 0.25, n23 = 0.35;
  const double G12 = 0.4e9, G13 = 0.3e9, G23 = 0.2e9;
  const Matrix6 C = c0_from_engineering(E1, E2, E3, n12, n13, n23, G12, G13, G23);
  // Independent: the orthotropic compliance written from the definitions.
  // nu_ij E_j = nu_ji E_i symmetry makes S symmetric.
  Eigen::Matrix3d S;
  S << 1 / E1, -n12 / E1, -n13 / E1, -n12 / E1, 1 / E2, -n23 / E2, -n13 / E1, -n23 / E2, 1 / E3;
  const Eigen::Matrix3d Cn = C.topLeftCorner<3, 3>();
  EXPECT_LT((Cn * S - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(C(3, 3), G23);
  EXPECT_DOUBLE_EQ(C(4, 4), G13);
  EXPECT_DOUBLE_EQ(C(5, 5), G12);
}

TEST(Stiffness, C0AndC1AreTheGradientOfTheFreeEnergy531to535) {
  // psi0 (5.31-5.32) + psi1 (5.33-5.35, reduced as in 5.58-5.66), written in TENSORIAL
  // Voigt strains e_I (e4 = gamma23/2 ...). The dissertation's Voigt stress is
  // sigma_I = dpsi/de_I (D1: this is what makes 2 c7 on the diagonal of the source's
  // c-constant stiffness consistent with c7 = C0_44). With e4 = gamma/2, dpsi/de4 = 2 dpsi/dgamma4.
  const std::array<double, 9> c = {0.6, 0.55, 0.3, 0.7, 0.58, 0.56, 0.19, 0.04, 0.17};
  NdmParameters p;
  p.model = Model::pnc;
  const Matrix6 C0 = c0_from_c_constants(c);
  p["C11"] = C0(0, 0);
  p["C22"] = C0(1, 1);
  p["C33"] = C0(2, 2);
  p["C12"] = C0(0, 1);
  p["C13"] = C0(0, 2);
  p["C23"] = C0(1, 2);
  p["C44"] = C0(3, 3);
  p["C55"] = C0(4, 4);
  p["C66"] = C0(5, 5);
  const double A1 = -0.5, A5 = -0.45, A9 = -0.25, A10 = -0.6, A11 = -0.55, A13 = -0.47, A15 = -0.59,
               A17 = -0.43, A18 = -0.5, A22 = -0.33, A24 = -0.3, A26 = -0.1;
  p["A1"] = A1;
  p["A5"] = A5;
  p["A9"] = A9;
  p["A10"] = A10;
  p["A11"] = A11;
  p["A13"] = A13;
  p["A15"] = A15;
  p["A17"] = A17;
  p["A18"] = A18;
  p["A22"] = A22;
  p["A24"] = A24;
  p["A26"] = A26;
  p["alpha"] = 1.0;
  const std::array<double, 3> D = {0.2, 0.35, 0.1};
  auto psi = [&](const Voigt& g) {
    const double e1 = g[0], e2 = g[1], e3 = g[2], e4 = g[3] / 2, e5 = g[4] / 2, e6 = g[5] / 2;
    const double D1 = D[0], D2 = D[1], D3 = D[2];
    const double psi0 = c[0] * e1 * e1 + c[1] * e2 * e2 + c[2] * e3 * e3 + c[3] * e1 * e2 +
                        c[4] * e1 * e3 + c[5] * e2 * e3 + c[6] * e4 * e4 + c[7] * e5 * e5 +
                        c[8] * e6 * e6;
    const double psi1 = A1 * e1 * e1 * D1 + A5 * e2 * e2 * D2 + A9 * e3 * e3 * D3 +
                        A10 * e1 * e2 * D1 + A11 * e1 * e2 * D2 + A13 * e1 * e3 * D1 +
                        A15 * e1 * e3 * D3 + A17 * e2 * e3 * D2 + A18 * e2 * e3 * D3 +
                        A22 * e4 * e4 * D2 + A26 * e5 * e5 * D3 + A24 * e6 * e6 * D2;
    return psi0 + psi1;
  };
  Voigt g;
  g << 0.01, -0.02, 0.015, 0.03, -0.01, 0.02;
  const Voigt sigma = (stiffness_c0(p) + stiffness_c1(p, D)) * g;
  for (int i = 0; i < 6; ++i) {
    Voigt gp = g, gm = g;
    const double h = 1e-6;
    gp[i] += h;
    gm[i] -= h;
    const double dpsi_de = (psi(gp) - psi(gm)) / (2 * h) * (i < 3 ? 1.0 : 2.0);
    EXPECT_NEAR(sigma[i], dpsi_de, 1e-9) << "component " << i;
  }
}

// ---------------------------------------------------------------- kinematics
TEST(ModeStretch, LaterallyConstrainedExtensionDrivesOnlyItsOwnMode) {
  for (int k = 0; k < 3; ++k) {
    const ModeStretch ms = mode_stretches(Model::pnc, case_strain(k + 1, 0.1), false);
    for (int m = 0; m < 3; ++m)
      EXPECT_NEAR(ms.lambda[m], m == k ? 1.1 : 1.0, 1e-14);
    EXPECT_NEAR(mode_stretches(Model::pp, case_strain(k + 1, 0.1), false).lambda[0], 1.1, 1e-14);
  }
}

TEST(ModeStretch, SimpleShearGivesTheFiniteStrainPrincipalStretchToTheInPlaneModes) {
  // D6: the kernel's stretch is exact for finite simple shear. The deformation gradient of
  // simple shear by gamma has the principal stretches gamma/2 +- sqrt(1 + gamma^2/4) (closed
  // form; the small-strain reading would give 1 + gamma/2). Modes whose plane contains the
  // shear take that stretch; the mode normal to the shear plane stays at 1 (D7).
  for (double g : {0.01, 0.1, 0.3, 0.8}) {
    const double exact = g / 2 + std::sqrt(1 + g * g / 4);
    for (int c : {4, 5, 6}) {
      const ModeStretch ms = mode_stretches(Model::pnc, case_strain(c, g), false);
      EXPECT_NEAR(ms.lambda_max, exact, 1e-14);
      const int out_of_plane = c == 4 ? 0 : c == 5 ? 1 : 2; // shear 2-3 leaves mode 1 alone
      for (int m = 0; m < 3; ++m)
        EXPECT_NEAR(ms.lambda[m], m == out_of_plane ? 1.0 : exact, 1e-14) << c << " " << m;
      EXPECT_NEAR(mode_stretches(Model::pp, case_strain(c, g), false).lambda[0], exact, 1e-14);
    }
  }
}

TEST(ModeStretch, NeverExceedsTheMaximumPrincipalStretchAndIsOneAtRest) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (int t = 0; t < 200; ++t) {
    Voigt e;
    for (int i = 0; i < 6; ++i)
      e[i] = u(rng);
    const ModeStretch ms = mode_stretches(Model::pnc, e, false);
    const double lmax = reference_largest_stretch(e);
    EXPECT_NEAR(ms.lambda_max, lmax, 1e-13);
    for (int m = 0; m < 3; ++m)
      EXPECT_LE(ms.lambda[m], lmax + 1e-14);
  }
  const ModeStretch rest = mode_stretches(Model::pnc, Voigt::Zero(), false);
  for (int m = 0; m < 3; ++m)
    EXPECT_EQ(rest.lambda[m], 1.0);
}

TEST(ModeStretch, ModeStretchIsTheCappedDefinitionOfD7) {
  // D7 with D6: lambda_k = min(lambda_max, e_kk + t_k + sqrt(1 + t_k^2)), t_k the shear on
  // the plane normal to x_k. The kernel decides whether the cap binds without computing
  // lambda_max (Sylvester's criterion on lambda^2 I - F^T F); reference: the definition with
  // Eigen's SVD. Includes strains where the cap binds for some modes and not others, and
  // plane strains (e33 = g13 = g23 = 0).
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  int capped = 0, free = 0;
  for (int t = 0; t < 2000; ++t) {
    Voigt e;
    for (int i = 0; i < 6; ++i)
      e[i] = u(rng);
    if (t % 2) e[2] = e[3] = e[4] = 0.0;
    const Eigen::Matrix3d et = to_tensor(e);
    const double lmax = reference_largest_stretch(e);
    const ModeStretch ms = mode_stretches(Model::pnc, e, true);
    for (int k = 0; k < 3; ++k) {
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      const double sh = std::hypot(et(k, a), et(k, b));
      const double raw = et(k, k) + sh + std::sqrt(1 + sh * sh);
      EXPECT_NEAR(ms.lambda[k], std::min(raw, lmax), 1e-14) << e.transpose();
      (raw > lmax ? capped : free) += 1;
    }
  }
  EXPECT_GT(capped, 100); // both branches exercised
  EXPECT_GT(free, 100);
}

TEST(ModeStretch, StretchDerivativesMatchCentralDifferences) {
  // d lambda_k / d eps of both branches (capped: the eigenvector of F^T F; uncapped: the
  // finite-shear term) against central differences of the stretches themselves. Step 1e-6:
  // truncation ~1e-12 (curvatures O(1)), rounding ~1e-16/1e-6 = 1e-10; bound 1e-7 keeps
  // clear of both and of points within 1e-6 of the cap's kink, which are skipped.
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  int checked = 0;
  for (int t = 0; t < 400; ++t) {
    Voigt e;
    for (int i = 0; i < 6; ++i)
      e[i] = u(rng);
    if (t % 2) e[2] = e[3] = e[4] = 0.0;
    for (Model m : {Model::pnc, Model::pp}) {
      const ModeStretch ms = mode_stretches(m, e, true);
      const int nm = m == Model::pnc ? 3 : 1;
      for (int i = 0; i < 6; ++i) {
        if (t % 2 && (i == 2 || i == 3 || i == 4)) continue; // stay in the plane branch
        Voigt ep = e, em = e;
        const double h = 1e-6;
        ep[i] += h;
        em[i] -= h;
        const ModeStretch p = mode_stretches(m, ep, false), q = mode_stretches(m, em, false);
        for (int k = 0; k < nm; ++k) {
          const double fd = (p.lambda[k] - q.lambda[k]) / (2 * h);
          const double one_sided = (p.lambda[k] - ms.lambda[k]) / h;
          if (std::abs(fd - one_sided) > 1e-4) continue; // a kink (cap) within h
          EXPECT_NEAR(ms.dlambda(k, i), fd, 1e-7) << "mode " << k << " comp " << i;
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 5000);
}

TEST(ModeStretch, ClosedFormLargestStretchMatchesEigenOnDegenerateStrains) {
  // The kernel takes the largest eigenvalue of F^T F in closed form (acos of the cubic's
  // invariant, or one square root for block-diagonal strains); repeated eigenvalues are
  // where that formula is delicate. Reference: Eigen's SVD of the same F.
  std::vector<Voigt> cases;
  Voigt v;
  v << 0, 0, 0, 0, 0, 0;
  cases.push_back(v); // zero
  v << 0.03, 0.03, 0.03, 0, 0, 0;
  cases.push_back(v); // hydrostatic
  v << 0.03, 0.03, -0.01, 0, 0, 0;
  cases.push_back(v); // equibiaxial
  v << -0.01, -0.01, 0.03, 0, 0, 0;
  cases.push_back(v); // uniaxial (two equal)
  v << 0, 0, 0, 0, 0, 0.04;
  cases.push_back(v); // pure shear
  v << 0.02, 0.02, 0.02, 1e-12, 0, 0;
  cases.push_back(v); // nearly hydrostatic
  v << 0.01, 0.01, 0.01, 0.02, 0.02, 0.02;
  cases.push_back(v); // double root below the top
  v << 1e-9, -1e-9, 0, 3e-10, 0, 0;
  cases.push_back(v); // tiny
  // block-diagonal strains: plane strain in each plane, with the out-of-plane normal the
  // largest, the smallest, and tied
  v << 0.02, -0.01, 0.0, 0, 0, 0.03;
  cases.push_back(v);
  v << 0.02, -0.01, 0.05, 0, 0, 0.03;
  cases.push_back(v);
  v << -0.01, 0.02, 0.03, 0, 0.04, 0;
  cases.push_back(v);
  v << -0.02, 0.01, 0.01, 0.02, 0, 0;
  cases.push_back(v);
  v << 0.01, 0.01, 0.0, 0, 0, 0.0;
  cases.push_back(v);
  for (const Voigt& c : cases)
    EXPECT_NEAR(mode_stretches(Model::pp, c, false).lambda_max, reference_largest_stretch(c), 1e-14)
        << c.transpose();
}

TEST(ModeStretch, CubicRootCosineIsWithinItsRoundingBound) {
  // cos(acos(r) / 3) without libm (D409): c = 1/2 + w u, w = sqrt(1 + r), u by two Newton
  // steps. Rounding bound for an exact r (u_r = 2^-53): w carries 1.5 u_r relative (1 + r,
  // then the root), u about 3.5 u_r relative (the last residual 6u^2 + 4wu^3 - 1 of terms near
  // 1, over a derivative above 4, and the update), so w u <= 1/2 is within 2.5 u_r and the sum
  // 1/2 + w u adds half an ulp of c <= 1: about 3.5 u_r; asserted at 8 u_r. Reference:
  // cosl(acosl(r) / 3) in 64-bit-mantissa long double (its own error ~1e-19). The grid is
  // dense over [-1, 1] and geometric towards both ends (r = -1: the two largest eigenvalues
  // meet, c = 1/2 with a square-root slope; r = 1: c = 1).
  std::vector<double> rs;
  for (int k = 0; k <= 20000; ++k)
    rs.push_back(-1.0 + 2.0 * k / 20000.0);
  for (int k = 1; k <= 60; ++k) {
    rs.push_back(-1.0 + std::ldexp(1.0, -k));
    rs.push_back(1.0 - std::ldexp(1.0, -k));
  }
  const double bound = 8.0 * std::ldexp(1.0, -53);
  double worst = 0.0;
  for (double r : rs) {
    const long double ref = std::cos(std::acos(static_cast<long double>(r)) / 3.0L);
    const double err = static_cast<double>(std::abs(pnc::damage::detail::eigen_cos(r) - ref));
    worst = std::max(worst, err);
    EXPECT_LE(err, bound) << "r = " << r;
  }
  EXPECT_NEAR(pnc::damage::detail::eigen_cos(1.0), 1.0, bound);
  EXPECT_NEAR(pnc::damage::detail::eigen_cos(-1.0), 0.5, bound);
  RecordProperty("worst_error_in_units_of_2^-53", std::to_string(worst / std::ldexp(1.0, -53)));
}

TEST(ModeStretch, PrincipalStretchIsObjectiveToFirstOrder) {
  // D6 reads a strain as an upper-triangular deformation gradient F = I + e + W (W skew,
  // |W| <= |e|), so the largest stretch depends on the basis only through
  // F^T F - (I + e)^2 = [e, W] + W^T W: |lambda(Q e Q^T) - lambda(e)| <= 2 * 3 |e|_F^2 / 2
  // (|e|_F < 0.1 here). The small-strain value 1 + max eig(e) is the common first order.
  Voigt e0;
  e0 << 0.05, -0.01, 0.02, 0.03, -0.04, 0.06;
  for (double s : {1.0, 0.1, 0.01}) {
    const Voigt e = s * e0;
    const double norm2 = to_tensor(e).squaredNorm();
    const double l0 = mode_stretches(Model::pp, e, false).lambda[0];
    for (int t = 0; t < 20; ++t) {
      const Eigen::Matrix3d Q = rotation(0.3 * t, 0.7 - 0.1 * t, 1.1 + 0.05 * t);
      const Voigt er = strain_to_voigt(Q * to_tensor(e) * Q.transpose());
      EXPECT_LE(std::abs(mode_stretches(Model::pp, er, false).lambda[0] - l0), 3 * norm2 + 1e-15);
    }
  }
}
