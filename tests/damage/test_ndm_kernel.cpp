// Tests of the NDM kernel against independent references: closed forms of the damage
// function, the source's energy functions (sigma = dpsi/de, D1), compliance of engineering
// constants, finite differences of the tangent, frame indifference, and the dissertation's
// Table 6.12.
#include "pnc/core/error.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/damage/moduli.hpp"
#include "pnc/damage/ndm.hpp"
#include "pnc/damage/reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace pnc::damage;

namespace {

// P: NdmParameters or PreparedNdm (the two integrate() overloads).
template <class P>
Voigt integrate_total(const P& p, const NdmState& s0, const Voigt& eps, NdmState* s1_out = nullptr,
                      Matrix6* K = nullptr) {
  NdmState s1;
  Voigt sigma;
  ErrorBuffer err;
  EXPECT_EQ(integrate(p, s0, s1, Voigt::Zero(), eps, sigma, K, err), Status::ok) << err.msg;
  if (s1_out) *s1_out = s1;
  return sigma;
}

Eigen::Matrix3d rotation(double a, double b, double c) {
  return (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Matrix3d to_tensor(const Voigt& v) {
  Eigen::Matrix3d e;
  e << v[0], v[5] / 2, v[4] / 2, v[5] / 2, v[1], v[3] / 2, v[4] / 2, v[3] / 2, v[2];
  return e;
}
// Decision D6 written out independently of the kernel: the upper-triangular (LAMMPS cell)
// deformation gradient of a small strain and its largest singular value by Eigen's SVD.
double reference_largest_stretch(const Voigt& v) {
  Eigen::Matrix3d F;
  F << 1 + v[0], v[5], v[4], 0, 1 + v[1], v[3], 0, 0, 1 + v[2];
  return Eigen::JacobiSVD<Eigen::Matrix3d>(F).singularValues()[0];
}
Voigt strain_to_voigt(const Eigen::Matrix3d& e) {
  Voigt v;
  v << e(0, 0), e(1, 1), e(2, 2), 2 * e(1, 2), 2 * e(0, 2), 2 * e(0, 1);
  return v;
}
Eigen::Matrix3d stress_tensor(const Voigt& s) {
  Eigen::Matrix3d t;
  t << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
  return t;
}

} // namespace

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

// ---------------------------------------------------------------- integration
TEST(Kernel, FrameIndifferenceWithARotatedPlatelet) {
  // Rotating the loading and the platelet together rotates the stress:
  // sigma(Q eps Q^T; R Q^T) = Q sigma(eps; R) Q^T.
  NdmParameters p = dissertation_parameters(Model::pnc);
  p.R = rotation(0.4, -0.2, 0.9);
  Voigt e;
  e << 0.09, 0.03, -0.02, 0.05, 0.02, -0.06; // past onset for some modes
  NdmState s;
  const Voigt s1 = integrate_total(p, NdmState{}, e, &s);
  EXPECT_GT(s.D[0] + s.D[1] + s.D[2], 0.0);
  for (int t = 0; t < 5; ++t) {
    const Eigen::Matrix3d Q = rotation(1.0 + t, 0.3 * t, -0.5 * t);
    NdmParameters pq = p;
    pq.R = p.R * Q.transpose();
    const Voigt eq = strain_to_voigt(Q * to_tensor(e) * Q.transpose());
    NdmState sq;
    const Voigt s2 = integrate_total(pq, NdmState{}, eq, &sq);
    EXPECT_LT((stress_tensor(s2) - Q * stress_tensor(s1) * Q.transpose()).norm(),
              1e-9 * stress_tensor(s1).norm());
    for (int m = 0; m < 3; ++m)
      EXPECT_NEAR(sq.D[m], s.D[m], 1e-12);
  }
}

TEST(Kernel, RotatedPlateletEqualsRotatedLoading) {
  // A platelet rotated by R under strain eps behaves as the aligned law under R eps R^T.
  NdmParameters aligned = dissertation_parameters(Model::pnc), rotated = aligned;
  rotated.R = rotation(0.5, 0.2, -0.3);
  Voigt e;
  e << 0.12, -0.01, 0.02, 0.01, 0.03, 0.04;
  const Voigt s_rot = integrate_total(rotated, NdmState{}, e);
  const Voigt el = strain_to_voigt(rotated.R * to_tensor(e) * rotated.R.transpose());
  const Voigt s_loc = integrate_total(aligned, NdmState{}, el);
  const Eigen::Matrix3d back = rotated.R.transpose() * stress_tensor(s_loc) * rotated.R;
  EXPECT_LT((stress_tensor(s_rot) - back).norm(), 1e-9 * back.norm());
}

namespace {
template <class P>
void check_tangent(const P& p, const NdmState& s0, const Voigt& e, const char* what) {
  Matrix6 K;
  integrate_total(p, s0, e, nullptr, &K);
  Matrix6 fd;
  const double h = 1e-7;
  for (int j = 0; j < 6; ++j) {
    Voigt ep = e, em = e;
    ep[j] += h;
    em[j] -= h;
    fd.col(j) = (integrate_total(p, s0, ep) - integrate_total(p, s0, em)) / (2 * h);
  }
  // Central differences: truncation O(h^2 |sigma'''|), round-off O(eps_mach |sigma| / h);
  // with stresses ~1e8 Pa and h = 1e-7 that is ~1e-1 Pa per unit strain against a tangent
  // ~1e9: a relative 1e-6 bound is safe yet catches any missing term (>= 1e-3 relative).
  EXPECT_LT((K - fd).norm(), 1e-6 * K.norm()) << what << "\nK=\n" << K << "\nfd=\n" << fd;
}
} // namespace

TEST(Kernel, TangentMatchesFiniteDifferencesElasticLoadingUnloadingRotated) {
  for (Model m : {Model::pnc, Model::pp}) {
    NdmParameters p = dissertation_parameters(m);
    Voigt elastic, loading, general;
    elastic << 0.01, -0.005, 0.002, 0.004, -0.003, 0.006;
    loading << 0.02, 0.13, -0.01, 0.015, 0.01, -0.02; // mode 2 / max stretch past onset
    general << 0.11, 0.03, 0.095, 0.04, -0.03, 0.05;  // several modes loading
    check_tangent(p, NdmState{}, elastic, "elastic");
    check_tangent(p, NdmState{}, loading, "loading");
    check_tangent(p, NdmState{}, general, "general");
    // Unloading: history beyond the current stretch -> secant stiffness C(D), no D growth.
    NdmState hist;
    hist.kappa = {1.2, 1.2, 1.2};
    hist.D = {damage_function(1.2 / p.alpha()), damage_function(1.2 / p.alpha()),
              damage_function(1.2 / p.alpha())};
    check_tangent(p, hist, general, "unloading");
    Matrix6 K;
    NdmState s1;
    integrate_total(p, hist, general, &s1, &K);
    EXPECT_LT((K - (stiffness_c0(p) + stiffness_c1(p, s1.D))).norm(), 1e-12 * K.norm());
    p.R = rotation(0.3, 0.6, -0.2);
    check_tangent(p, NdmState{}, general, "rotated platelet");
    check_tangent(p, NdmState{}, loading, "rotated platelet, loading");
    // The prepared parameters (precomputed T and rotated stiffness pieces) take another
    // route to the same tangent: check it against finite differences on its own.
    const PreparedNdm q = prepare(p);
    check_tangent(q, NdmState{}, general, "prepared, rotated platelet");
    check_tangent(q, NdmState{}, loading, "prepared, rotated platelet, loading");
    check_tangent(q, hist, general, "prepared, rotated platelet, unloading");
  }
}

TEST(Kernel, PreparedParametersGiveTheSameResultUpToRounding) {
  // integrate(prepare(p), ...) forms T^T (C0 + sum D_m dC1_m) T from rotated pieces; the
  // plain overload rotates the assembled C. Same mathematics, different rounding: stresses
  // and tangents agree to a few ulps of their norm (bound 1e-12 relative), states exactly
  // (the state does not depend on the rotation route). The strains cover the prepared
  // route's branches: below the damage onset (its undamaged shortcut), past it, unloading,
  // and plane strains (e33 = g23 = g13 = 0: three columns of T and C) under a platelet
  // rotated about x3 (block-diagonal local strain: the one-square-root stretches).
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int below_onset = 0, plane = 0;
  for (Model m : {Model::pnc, Model::pp}) {
    for (int rot = 0; rot < 3; ++rot) {
      NdmParameters p = dissertation_parameters(m);
      if (rot == 1) p.R = rotation(0.7, -0.4, 0.25);
      if (rot == 2) p.R = rotation(0.5 * M_PI / 180.0, 0.0, 0.0); // the deal.II demo's (D58)
      const PreparedNdm q = prepare(p);
      EXPECT_EQ(q.rotated, rot != 0);
      for (int t = 0; t < 200; ++t) {
        Voigt e;
        const double scale = t % 5 == 2 ? 0.02 : 1.0; // 2 % strains: below the onset
        for (int i = 0; i < 6; ++i)
          e[i] = scale * (i < 3 ? 0.15 : 0.1) * u(rng); // elastic to well past onset
        if (t % 4 == 1) {
          e[2] = e[3] = e[4] = 0.0;
          ++plane;
        }
        NdmState s0;
        if (t % 3 == 0) s0.kappa = {1.15, 1.2, 1.25}; // some points unloading
        for (int k = 0; k < 3; ++k)
          s0.D[k] = damage_function(s0.kappa[k] / p.alpha());
        Matrix6 Kp, Kq;
        NdmState sp, sq;
        const Voigt a = integrate_total(p, s0, e, &sp, &Kp);
        const Voigt b = integrate_total(q, s0, e, &sq, &Kq);
        EXPECT_LE((a - b).norm(), 1e-12 * a.norm()) << e.transpose();
        EXPECT_LE((Kp - Kq).norm(), 1e-12 * Kp.norm()) << e.transpose();
        bool undamaged = true;
        for (int k = 0; k < 3; ++k) {
          EXPECT_EQ(sp.kappa[k], sq.kappa[k]);
          EXPECT_EQ(sp.D[k], sq.D[k]);
          undamaged = undamaged && sq.D[k] == 0.0;
        }
        below_onset += undamaged;
        // The C-ABI route (arrays, row-major tangent) is the same computation entry by entry.
        const Voigt zero = Voigt::Zero();
        Voigt c;
        double Kr[36];
        NdmState sr;
        ErrorBuffer err;
        ASSERT_EQ(integrate_row_major(q, s0, sr, zero.data(), e.data(), c.data(), Kr, err),
                  Status::ok);
        EXPECT_EQ(c, b);
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < 6; ++j)
            EXPECT_EQ(Kr[6 * i + j], Kq(i, j)) << "K(" << i << "," << j << ")";
        for (int k = 0; k < 3; ++k)
          EXPECT_EQ(sr.kappa[k], sq.kappa[k]);
      }
    }
  }
  EXPECT_GT(below_onset, 100); // the shortcut was taken
  EXPECT_GT(plane, 200);
}

TEST(Kernel, DamageIsIrreversibleOnUnloadAndReload) {
  for (Model m : {Model::pnc, Model::pp}) {
    const NdmParameters p = dissertation_parameters(m);
    // Case 2 path: load to 0.25, unload to 0.10, reload to 0.25, load on to 0.30 (onset is
    // at alpha*lambda_c - 1 = 7.2 % for pnc and 17.1 % for pp).
    std::vector<double> amounts;
    for (int i = 1; i <= 50; ++i)
      amounts.push_back(0.005 * i); // 0..49
    for (int i = 1; i <= 30; ++i)
      amounts.push_back(0.25 - 0.005 * i); // 50..79
    for (int i = 1; i <= 30; ++i)
      amounts.push_back(0.10 + 0.005 * i); // 80..109
    for (int i = 1; i <= 10; ++i)
      amounts.push_back(0.25 + 0.005 * i); // 110..119
    PathMatrix path(static_cast<Eigen::Index>(amounts.size()), 6);
    for (std::size_t i = 0; i < amounts.size(); ++i)
      path.row(static_cast<Eigen::Index>(i)) = case_strain(2, amounts[i]).transpose();
    std::vector<NdmState> st;
    const auto s = stress_path(p, path, &st);
    const int mode = m == Model::pnc ? 1 : 0;
    const double Dmax = st[49].D[mode];
    ASSERT_GT(Dmax, 0.01);
    const double secant = s(49, 1) / 0.25;
    for (int i = 50; i < 110; ++i) {
      EXPECT_EQ(st[static_cast<std::size_t>(i)].D[mode], Dmax) << "step " << i;
      // secant unloading through the origin: sigma/eps constant
      EXPECT_NEAR(s(i, 1) / amounts[static_cast<std::size_t>(i)], secant, 1e-9 * std::abs(secant));
    }
    EXPECT_NEAR(s(109, 1), s(49, 1), 1e-9 * std::abs(s(49, 1))); // reload returns to the curve
    EXPECT_GT(st[119].D[mode], Dmax);                            // then damage grows again
    // and the reloaded curve continues as if never unloaded
    const auto mono = stress_path(p, PathMatrix(case_strain(2, 0.30).transpose()));
    EXPECT_NEAR(s(119, 1), mono(0, 1), 1e-9 * std::abs(mono(0, 1)));
  }
}

TEST(Kernel, RejectsNonFiniteStrainWithAMessage) {
  const NdmParameters p = dissertation_parameters(Model::pnc);
  NdmState s1;
  Voigt sigma = Voigt::Constant(7.0), bad = Voigt::Zero();
  bad[2] = std::nan("");
  ErrorBuffer err;
  EXPECT_EQ(integrate(p, NdmState{}, s1, Voigt::Zero(), bad, sigma, nullptr, err),
            Status::bad_input);
  EXPECT_NE(std::string(err.msg).find("not finite"), std::string::npos);
  EXPECT_EQ(sigma[0], 7.0); // untouched
}

TEST(Kernel, ValidateNamesTheBrokenConstant) {
  NdmParameters p = dissertation_parameters(Model::pnc);
  p["C12"] = 2.0e9; // C12 > sqrt(C11 C22): not positive definite
  try {
    validate(p, "card.h5");
    FAIL() << "expected an error";
  } catch (const pnc::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("card.h5"), std::string::npos);
    EXPECT_NE(m.find("C0"), std::string::npos);
    EXPECT_NE(m.find("positive definite"), std::string::npos);
  }
  p = dissertation_parameters(Model::pp);
  p["alpha"] = 0.0;
  EXPECT_THROW(validate(p, "x"), pnc::InputError);
}

// ---------------------------------------------------------------- dissertation tables
TEST(Dissertation, Table612FromTheTabulatedConstants) {
  const NdmParameters pnc = dissertation_parameters(Model::pnc);
  const NdmParameters pp = dissertation_parameters(Model::pp);
  // Printed to 2-3 decimals: tolerances are half a unit of the last printed digit.
  const double inc = (pnc["C22"] - pp["C11"]) / pp["C11"] * 100;
  EXPECT_NEAR(inc, 106.26, 0.005);
  const DerivedModuli dpp = derive_moduli(pp), dpnc = derive_moduli(pnc);
  EXPECT_NEAR(dpp.E_isotropic_formula / 1e9, 0.162, 0.0005);
  EXPECT_NEAR(dpp.E1 / 1e9, 0.162,
              0.0005); // the isotropic formula is exact for the isotropic reading
  EXPECT_NEAR(dpnc.E2_as_printed / 1e9, 0.567, 0.0005);
  // Compliance inversion (docs/theory.md §1.5): E1 = 0.567, E2 = 0.600, E3 = 0.294.
  EXPECT_NEAR(dpnc.E1 / 1e9, 0.567, 0.0005);
  EXPECT_NEAR(dpnc.E2 / 1e9, 0.600, 0.0005);
  EXPECT_NEAR(dpnc.E3 / 1e9, 0.294, 0.0005);
  EXPECT_NEAR(dpnc.E2_as_printed, dpnc.E1, 1e-6 * dpnc.E1); // the printed "E2" is E1
  // "% increase 250": 0.567 / 0.162 = 3.50 (both printed to 3 digits: +-0.5 %).
  EXPECT_NEAR((dpnc.E2_as_printed / dpp.E_isotropic_formula - 1) * 100, 250, 1.0);
}

// The driven stress of a case in closed form, written out here independently of the kernel:
// sigma = (c0 + c1 D(lambda / alpha)) t with D of docs/theory.md §1.2 (D4) and the case's stretch
// lambda(t). Returns the first local maximum on a fine grid refined by bisection on the
// slope, or a negative strain when the stress rises monotonically up to t_max.
double first_peak_strain(double c0, double c1, double alpha, bool shear, double t_max) {
  const double lc = std::pow(26.0 / 7.0, 1.0 / 6.0);
  const double k = 1.0 / std::abs(2 * std::pow(lc, -13) - std::pow(lc, -7));
  auto sigma = [&](double t) {
    const double lam = shear ? t / 2 + std::sqrt(1 + t * t / 4) : 1 + t;
    const double x = lam / alpha;
    const double D = x > lc ? 1 + k * (2 * std::pow(x, -13) - std::pow(x, -7)) : 0.0;
    return (c0 + c1 * D) * t;
  };
  const int n = 100000;
  for (int i = 1; i < n; ++i) {
    const double t0 = t_max * (i - 1) / n, t1 = t_max * i / n, t2 = t_max * (i + 1) / n;
    if (sigma(t1) > sigma(t0) && sigma(t1) >= sigma(t2)) {
      double a = t0, b = t2; // bisection on the sign of the slope
      for (int it = 0; it < 60; ++it) {
        const double m = 0.5 * (a + b), h = 1e-9;
        (sigma(m + h) > sigma(m - h) ? a : b) = m;
      }
      return 0.5 * (a + b);
    }
  }
  return -1.0;
}

TEST(Dissertation, PurePolymerShearFailureStrain) {
  // The printed pure-polymer shear failure strain is 0.37 (two digits). The small-strain
  // stretch 1 + gamma/2 put the NDM's shear peak at 0.368; with the finite-shear stretch
  // gamma/2 + sqrt(1 + gamma^2/4) of decision D6 it moves earlier. The kernel's peak must be
  // the closed-form one (C44 + B4 D) gamma of the tabulated constants.
  const NdmParameters p = dissertation_parameters(Model::pp);
  const CaseStrength s = case_strength(p, 6, 1.0);
  ASSERT_TRUE(s.peak.has_value());
  const double ref = first_peak_strain(p["C44"], p["B4"], p.alpha(), true, 1.0);
  EXPECT_NEAR(s.strain_at_peak, ref, 1e-5);
  EXPECT_LT(s.strain_at_peak, 0.37); // earlier than the printed value (finite stretch)
}

TEST(Dissertation, NanocompositeStrengthIsTheFirstStressPeak) {
  // Table 6.13: sigma_PNC,2 = 189.37 MPa. sigma22 in case 2 rises again once damage
  // saturates (C22 + 2A5 > 0), so the strength is the first local maximum (D5). The
  // printed constants carry 3 digits (+-0.05 % each), so 0.2 % is the reproduction bound.
  const NdmParameters p = dissertation_parameters(Model::pnc);
  const CaseStrength s = case_strength(p, 2, 1.0);
  ASSERT_TRUE(s.peak.has_value());
  EXPECT_NEAR(*s.peak / 1e6, 189.37, 189.37 * 2e-3);
  EXPECT_NEAR(s.strain_at_peak, first_peak_strain(p["C22"], 2 * p["A5"], p.alpha(), false, 1.0),
              1e-5);
}

TEST(Dissertation, PurePolymerExtensionHasNoStrengthPeakUnderTheRowPairedLabels) {
  // With Table 6.10's rows paired in order (D9: diagonal damage slope -0.405 GPa, D2's
  // rule) the pure polymer's sigma22 in laterally constrained extension never turns over
  // up to 100 % strain, so Table 6.13's 149.04 MPa is not reproduced (D5): the card says
  // "no peak" rather than invent one. Reference: the closed form above.
  const NdmParameters p = dissertation_parameters(Model::pp);
  EXPECT_LT(first_peak_strain(p["C11"], 2 * p["B1"], p.alpha(), false, 1.0), 0.0);
  EXPECT_FALSE(case_strength(p, 2, 1.0).peak.has_value());
}

TEST(Dissertation, CriticalStrainOfOnsetFollowsAlpha) {
  // Damage starts at lambda = alpha * lambda_c (docs/theory.md §1.2, D5): 1.0715 for pnc (alpha =
  // 0.861).
  const NdmParameters p = dissertation_parameters(Model::pnc);
  const double onset = p.alpha() * critical_stretch() - 1;
  NdmState before, after;
  integrate_total(p, NdmState{}, case_strain(2, onset * (1 - 1e-9)), &before);
  integrate_total(p, NdmState{}, case_strain(2, onset * 1.01), &after);
  EXPECT_EQ(before.D[1], 0.0);
  EXPECT_GT(after.D[1], 0.0);
  EXPECT_NEAR(onset, 0.0715, 5e-4);
}
