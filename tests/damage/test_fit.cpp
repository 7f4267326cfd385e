// Fit-validation (in the spirit of Ceres' nist.cc): recover known constants from synthetic
// data, check the standard errors statistically, check the hand-derived Jacobian against
// finite differences, and check the dissertation's regression on noise-free data.
#include "pnc/core/error.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/synth.hpp"

#include "fit_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace pnc::damage;
using pnc_fit_test::constants_mpa;

namespace {

StressStrainData synth(Model m, double noise_mpa, std::uint64_t seed, int points = 150) {
  SynthOptions o;
  o.points = points;
  o.noise_sd = noise_mpa * 1e6;
  o.seed = seed;
  o.max_extension = m == Model::pnc ? 0.20 : 0.30; // past onset (7.2 % pnc, 17.1 % pp)
  o.max_shear = 0.40;
  return synthesize(dissertation_parameters(m), o);
}

} // namespace

TEST(FitJacobian, ThetaMapRoundTripsAndItsDerivativeMatchesFiniteDifferences) {
  for (Model m : {Model::pnc, Model::pp}) {
    const auto k = constants_mpa(dissertation_parameters(m));
    const auto th = detail::theta_from_constants(m, k);
    const auto back = detail::constants_from_theta(m, th);
    for (std::size_t i = 0; i < k.size(); ++i)
      EXPECT_NEAR(back[i], k[i], 1e-10 * (1 + std::abs(k[i])));
    const Eigen::MatrixXd G = detail::dconstants_dtheta(m, th);
    for (std::size_t j = 0; j < th.size(); ++j) {
      auto tp = th, tm = th;
      const double h = 1e-4 * (1 + std::abs(th[j]));
      tp[j] += h;
      tm[j] -= h;
      const auto kp = detail::constants_from_theta(m, tp), km = detail::constants_from_theta(m, tm);
      for (std::size_t i = 0; i < k.size(); ++i)
        EXPECT_NEAR(G(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)),
                    (kp[i] - km[i]) / (2 * h), 1e-6 * (1 + std::abs(G(i, j))));
    }
  }
}

TEST(FitJacobian, AnalyticJacobianMatchesCentralDifferences) {
  // At a point away from the truth (so residuals are not zero) and with damage active,
  // including the alpha column (D depends on alpha through kappa/alpha).
  for (Model m : {Model::pnc, Model::pp}) {
    const StressStrainData d = synth(m, 1.0, 3, 40);
    auto k = constants_mpa(dissertation_parameters(m));
    for (std::size_t i = 0; i < k.size(); ++i)
      k[i] *= 1.0 + 0.03 * std::sin(1.0 + static_cast<double>(i));
    auto th = detail::theta_from_constants(m, k);
    Eigen::VectorXd r;
    Eigen::MatrixXd J;
    detail::residuals_and_jacobian(d, m, th, r, &J);
    const Eigen::MatrixXd FD = pnc_fit_test::central_difference_jacobian(d, m, th);
    for (std::size_t j = 0; j < th.size(); ++j) {
      const Eigen::VectorXd fd = FD.col(static_cast<Eigen::Index>(j));
      const Eigen::VectorXd an = J.col(static_cast<Eigen::Index>(j));
      // All residuals are linear in every theta but the Cholesky factors (quadratic: exact
      // under central differences) and alpha (smooth, C1 at onset): a 1e-6 relative bound.
      EXPECT_LT((an - fd).norm(), 1e-6 * (1 + an.norm()))
          << model_name(m) << " column " << j << " (" << constant_names(m)[j] << ")";
    }
  }
}

TEST(FitRecovery, NoiseFreeDataGiveTheConstantsBack) {
  for (Model m : {Model::pnc, Model::pp}) {
    const NdmParameters truth = dissertation_parameters(m);
    const StressStrainData d = synth(m, 0.0, 1, 60);
    FitOptions o;
    o.model = m;
    const FitReport r = fit_ndm(d, o);
    EXPECT_TRUE(r.converged) << r.message;
    for (std::size_t i = 0; i < truth.size(); ++i) {
      // A26 = 0 in the tables: compare on the scale of the stiffnesses (1e-9 of 1 GPa).
      EXPECT_NEAR(r.params.k[i], truth.k[i],
                  1e-7 * std::max(1e9 * (i + 1 < truth.size()), std::abs(truth.k[i])))
          << model_name(m) << " " << constant_names(m)[i];
    }
  }
}

TEST(FitRecovery, NoisyDataWithinTheReportedStandardErrorsAndTheErrorsAreCalibrated) {
  // For each model, fit 12 independent noisy data sets (sigma = 3 MPa). Every constant must
  // lie within 5 standard errors of the truth (p ~ 6e-7 per constant under normality), and
  // the z-scores must have a mean square near 1: if the reported errors were too small or
  // too large by a factor 1.5, that mean square would be 2.25 or 0.44.
  for (Model m : {Model::pnc, Model::pp}) {
    const NdmParameters truth = dissertation_parameters(m);
    double z2 = 0;
    int nz = 0;
    for (std::uint64_t seed = 1; seed <= 12; ++seed) {
      const StressStrainData d = synth(m, 3.0, seed, 120);
      FitOptions o;
      o.model = m;
      const FitReport r = fit_ndm(d, o);
      ASSERT_TRUE(r.converged) << r.message;
      for (std::size_t i = 0; i + 1 < truth.size(); ++i) {
        ASSERT_TRUE(r.fitted[i]) << constant_names(m)[i];
        ASSERT_TRUE(std::isfinite(r.std_error[i]));
        const double z = (r.params.k[i] - truth.k[i]) / r.std_error[i];
        EXPECT_LT(std::abs(z), 5.0)
            << model_name(m) << " seed " << seed << " " << constant_names(m)[i];
        z2 += z * z;
        ++nz;
      }
    }
    const double ms = z2 / nz;
    // With nz = 12 x (21 or 6) z-scores, the sampling sd of the mean square is ~sqrt(2/nz)
    // (0.09 pnc, 0.17 pp) if independent; constants are correlated, so allow a wide band.
    EXPECT_GT(ms, 0.5) << model_name(m);
    EXPECT_LT(ms, 1.8) << model_name(m);
  }
}

TEST(FitRecovery, AlphaIsRecoveredWhenFitted) {
  for (Model m : {Model::pnc, Model::pp}) {
    const NdmParameters truth = dissertation_parameters(m);
    const StressStrainData d = synth(m, 2.0, 5, 200);
    FitOptions o;
    o.model = m;
    o.alpha_mode = AlphaMode::fit;
    o.alpha = truth.alpha() * 1.05; // start off the truth
    const FitReport r = fit_ndm(d, o);
    ASSERT_TRUE(r.converged) << r.message;
    ASSERT_TRUE(r.fitted.back());
    EXPECT_LT(std::abs(r.params.alpha() - truth.alpha()), 5 * r.std_error.back());
    EXPECT_LT(r.std_error.back(), 0.01); // the data pin alpha down to better than 1 %
  }
}

TEST(FitRecovery, RobustLossResistsOutliers) {
  // 5 % of the sigma22 points of case 2 get +60 MPa (20 noise sd): the Huber fit must land
  // closer to the true C22 than plain least squares and within 5 of its standard errors.
  const NdmParameters truth = dissertation_parameters(Model::pnc);
  StressStrainData d = synth(Model::pnc, 3.0, 9, 200);
  for (auto& c : d.cases)
    if (c.id == 2)
      for (Eigen::Index k = 0; k < c.stress.rows(); k += 20)
        c.stress(k, 1) += 60e6;
  FitOptions ls, hub;
  hub.loss = "huber";
  hub.loss_scale = 2.0; // residuals are in units of the data sd (3 MPa)
  const FitReport a = fit_ndm(d, ls), b = fit_ndm(d, hub);
  const double ea = std::abs(a.params["C22"] - truth["C22"]);
  const double eb = std::abs(b.params["C22"] - truth["C22"]);
  EXPECT_LT(eb, ea);
  EXPECT_LT(eb, 5 * b.std_error[1]);
}

TEST(FitRegression, NoiseFreeDataReproduceTheTabulatedCoefficients) {
  // Each stress component of a case is exactly a eps + b D eps in the model, so the
  // dissertation's per-case regression must return the table's numbers for the constants
  // that built the data (C12 printed twice, 0.763 and 0.708: the data use 0.708).
  const NdmParameters truth = dissertation_parameters(Model::pnc);
  const StressStrainData d = synth(Model::pnc, 0.0, 1, 80);
  const auto lines = regress_cases(d, Model::pnc, truth.alpha());
  ASSERT_EQ(lines.size(), 12u);
  for (const auto& l : lines) {
    const bool twice = l.damage_label[0] == '2';
    const double b_true =
        (twice ? 2.0 : 1.0) * truth[twice ? l.damage_label.substr(1) : l.damage_label];
    EXPECT_NEAR(l.a, truth[l.linear_label], 1e-6 * 1e9) << l.case_id << " " << l.linear_label;
    EXPECT_NEAR(l.b, b_true, 1e-6 * 1e9) << l.case_id << " " << l.damage_label;
    EXPECT_GT(l.r2, 0.999999);
  }
  // and against the printed table where the data constants are the printed ones
  for (const auto& p : printed_regression(Model::pnc)) {
    for (const auto& l : lines) {
      if (l.case_id != p.case_id || l.component != p.component) continue;
      if (std::string(p.dam_label) == l.damage_label) EXPECT_NEAR(l.b, p.dam_value, 1e-6 * 1e9);
    }
  }
}

TEST(FitInput, MissingOrForeignCasesAreNamed) {
  StressStrainData d = synth(Model::pnc, 1.0, 1, 30);
  d.source = "md.csv";
  d.cases.erase(d.cases.begin() + 1); // drop case 2
  try {
    fit_ndm(d, FitOptions{});
    FAIL();
  } catch (const pnc::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("md.csv"), std::string::npos) << m;
    EXPECT_NE(m.find("'case'"), std::string::npos) << m;
    EXPECT_NE(m.find("'2'"), std::string::npos) << m;
  }
  FitOptions pp;
  pp.model = Model::pp;
  try {
    StressStrainData shear = synth(Model::pnc, 1.0, 1, 30);
    shear.cases.erase(shear.cases.begin(), shear.cases.begin() + 3); // cases 4-6 only
    fit_ndm(shear, pp);
    FAIL();
  } catch (const pnc::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at least one of cases 1-3"), std::string::npos)
        << e.what();
  }
}

TEST(FitInput, HeldConstantsWhenACaseIsMissingOrDamageIsNeverReached) {
  // The dissertation had no case 6 fit: C66 and A24 are then held at the prior.
  StressStrainData d = synth(Model::pnc, 1.0, 2, 60);
  d.cases.pop_back();
  const FitReport r = fit_ndm(d, FitOptions{});
  EXPECT_TRUE(r.converged);
  const int c66 = constant_index(Model::pnc, "C66"), a24 = constant_index(Model::pnc, "A24");
  EXPECT_FALSE(r.fitted[static_cast<std::size_t>(c66)]);
  EXPECT_FALSE(r.fitted[static_cast<std::size_t>(a24)]);
  EXPECT_TRUE(std::isnan(r.std_error[static_cast<std::size_t>(a24)]));
  EXPECT_NE(r.note[static_cast<std::size_t>(c66)].find("no data"), std::string::npos);
  // Small strains only (below the 7.2 % onset): no A constant can be determined.
  SynthOptions o;
  o.max_extension = 0.05;
  o.max_shear = 0.1;
  o.points = 40;
  o.noise_sd = 1e6;
  const FitReport e = fit_ndm(synthesize(dissertation_parameters(Model::pnc), o), FitOptions{});
  for (const char* a : {"A1", "A5", "A9", "A22"})
    EXPECT_FALSE(e.fitted[static_cast<std::size_t>(constant_index(Model::pnc, a))]) << a;
  EXPECT_TRUE(e.fitted[static_cast<std::size_t>(constant_index(Model::pnc, "C11"))]);
}

TEST(FitOptionsTest, ValidationNamesTheOption) {
  FitOptions o;
  o.loss = "l1";
  EXPECT_THROW(o.validate(), pnc::InputError);
  o = FitOptions{};
  o.max_iterations = 0;
  try {
    o.validate();
    FAIL();
  } catch (const pnc::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_iterations"), std::string::npos);
  }
}
