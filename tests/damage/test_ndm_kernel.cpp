// Tests of the NDM kernel's integration against independent references: finite differences
// of the tangent, frame indifference, irreversibility, input checks and the dissertation's
// Table 6.12. The damage function, stiffness and mode stretches: test_ndm_stretch.cpp.
#include "ndm_test_support.hpp"
#include "pnc/core/error.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/damage/moduli.hpp"
#include "pnc/damage/ndm.hpp"
#include "pnc/damage/reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace pnc::damage;
using namespace pnc_ndm_test;

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
// lambda(t). first_peak_strain returns the first local maximum on a fine grid refined by
// bisection on the slope, or a negative strain when the stress rises monotonically up to t_max.
double closed_form_stress(double c0, double c1, double alpha, bool shear, double t) {
  const double lc = std::pow(26.0 / 7.0, 1.0 / 6.0);
  const double k = 1.0 / std::abs(2 * std::pow(lc, -13) - std::pow(lc, -7));
  const double lam = shear ? t / 2 + std::sqrt(1 + t * t / 4) : 1 + t;
  const double x = lam / alpha;
  const double D = x > lc ? 1 + k * (2 * std::pow(x, -13) - std::pow(x, -7)) : 0.0;
  return (c0 + c1 * D) * t;
}

double first_peak_strain(double c0, double c1, double alpha, bool shear, double t_max) {
  auto sigma = [&](double t) { return closed_form_stress(c0, c1, alpha, shear, t); };
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
  // the same shear in the negative sense (case 9, D424) peaks at the same load with the stress
  // of the other sign: along one shear the law is odd (docs/theory.md section 2.1)
  const CaseStrength n = case_strength(p, 9, 1.0);
  ASSERT_TRUE(n.peak.has_value());
  EXPECT_NEAR(n.strain_at_peak, ref, 1e-5);
  // at the peak the stress is stationary: a load error of 1e-5 moves it by O(1e-10) relative
  const double peak = closed_form_stress(p["C44"], p["B4"], p.alpha(), true, ref);
  EXPECT_NEAR(*s.peak, peak, 1e-8 * peak);
  EXPECT_NEAR(*n.peak, -peak, 1e-8 * peak);
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
