// The isotropic pure polymer (fit option isotropic, decision D396): C44 = (C11 - C12)/2 and
// B4 = B1 - B2/2 are derived from the fitted constants, so that the damaged stiffness
// C0 + D C1 of an amorphous glass stays isotropic. Checked here against things independent of
// the code: finite differences of the tied Jacobian, the exact recovery of isotropic
// constants, the Loewner-order property of a constrained linear least-squares covariance
// (a true constraint never widens an error), the Monte-Carlo coverage of the propagated
// errors of the derived constants, and a law that is not isotropic (the dissertation's pure
// polymer: (C11 - C12)/2 = 0.056 GPa against C44 = 0.109 GPa) flagged as a misfit.
#include "pnc/core/error.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/synth.hpp"

#include "common/temp_dir.hpp"
#include "fit_test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

using namespace pnc::damage;
using pnc_fit_test::constants_mpa;

namespace {

const int kC11 = constant_index(Model::pp, "C11");
const int kC12 = constant_index(Model::pp, "C12");
const int kC44 = constant_index(Model::pp, "C44");
const int kB1 = constant_index(Model::pp, "B1");
const int kB2 = constant_index(Model::pp, "B2");
const int kB4 = constant_index(Model::pp, "B4");

// The tables' pure polymer made isotropic: C44 and B4 replaced by their isotropic values.
NdmParameters isotropic_truth() {
  NdmParameters p = dissertation_parameters(Model::pp);
  p["C44"] = (p["C11"] - p["C12"]) / 2;
  p["B4"] = p["B1"] - p["B2"] / 2;
  return p;
}

StressStrainData curves(const NdmParameters& truth, double noise_pa, double sd_pa,
                        std::uint64_t seed) {
  SynthOptions o;
  o.cases = {1, 2, 3, 4, 5, 6};
  o.points = 40;
  o.max_extension = 0.3; // past the tables' onset (17.1 % for pp)
  o.max_shear = 0.4;
  o.noise_sd = noise_pa;
  o.seed = seed;
  StressStrainData d = synthesize(truth, o);
  if (sd_pa > 0)
    for (CaseCurve& c : d.cases)
      c.stress_stderr = PathMatrix::Constant(c.stress.rows(), 6, sd_pa);
  return d;
}

FitOptions options(bool isotropic) {
  FitOptions o;
  o.model = Model::pp;
  o.isotropic = isotropic;
  return o;
}

} // namespace

TEST(FitIsotropic, TiedConstantsFollowTheirFormulaAndTheJacobianMatchesCentralDifferences) {
  const std::vector<int> tied = {kC44, kB4};
  const StressStrainData d = curves(dissertation_parameters(Model::pp), 0, 0, 1);
  auto k = constants_mpa(dissertation_parameters(Model::pp));
  for (std::size_t i = 0; i < k.size(); ++i) // away from any solution, damage active
    k[i] *= 1.0 + 0.03 * std::sin(1.0 + static_cast<double>(i));
  const auto th = detail::theta_from_constants(Model::pp, k);
  const auto kt = detail::constants_from_theta(Model::pp, th, tied);
  EXPECT_NEAR(kt[kC44], (k[kC11] - k[kC12]) / 2, 1e-12 * std::abs(k[kC11]));
  EXPECT_NEAR(kt[kB4], k[kB1] - k[kB2] / 2, 1e-12 * std::abs(k[kB1]));
  for (int j : {kC11, kC12, kB1, kB2})
    EXPECT_NEAR(kt[j], k[j], 1e-12 * std::abs(k[j]));
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  detail::residuals_and_jacobian(d, Model::pp, th, r, &J, tied);
  const Eigen::MatrixXd FD = pnc_fit_test::central_difference_jacobian(d, Model::pp, th, tied);
  for (std::size_t j = 0; j < th.size(); ++j) {
    const Eigen::VectorXd fd = FD.col(static_cast<Eigen::Index>(j));
    const Eigen::VectorXd an = J.col(static_cast<Eigen::Index>(j));
    // linear in every theta but alpha (smooth): the bound of the untied Jacobian test
    EXPECT_LT((an - fd).norm(), 1e-6 * (1 + an.norm())) << "column " << j;
  }
  // the derived constants' own theta coordinates do nothing
  EXPECT_EQ(J.col(kC44).norm(), 0.0);
  EXPECT_EQ(J.col(kB4).norm(), 0.0);
}

TEST(FitIsotropic, IsotropicDataGiveTheConstantsBackAndATrueConstraintNeverWidensAnError) {
  const NdmParameters truth = isotropic_truth();
  const StressStrainData d = curves(truth, 0, 2e6, 1); // noise-free, 2 MPa recorded errors
  const FitReport free = fit_ndm(d, options(false));
  const FitReport iso = fit_ndm(d, options(true));
  ASSERT_TRUE(free.converged) << free.message;
  ASSERT_TRUE(iso.converged) << iso.message;
  EXPECT_TRUE(iso.isotropic);
  EXPECT_EQ(iso.free_parameters, free.free_parameters - 2);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const std::string name = constant_names(Model::pp)[i];
    EXPECT_NEAR(iso.params.k[i], truth.k[i], 1e-6 * std::max(1e9 * (i + 1 < truth.size()), 1.0))
        << name;
    ASSERT_TRUE(iso.fitted[i]) << name << ": " << iso.note[i];
    const bool derived = static_cast<int>(i) == kC44 || static_cast<int>(i) == kB4;
    EXPECT_EQ(iso.status[i], derived ? "derived" : "fitted") << name;
    // chi^2 = 0 here, so both covariances are (J^T J)^-1 at the same constants; the tied one
    // is that of a linear equality constraint, smaller in the Loewner order: every error
    // (and every derived constant's) at most the free fit's, to the solver's tolerance
    EXPECT_LE(iso.std_error[i], free.std_error[i] * (1 + 1e-6)) << name;
    EXPECT_GT(iso.std_error[i], 0.0) << name;
  }
  EXPECT_NE(iso.note[kB4].find("B4 = B1 - B2 / 2"), std::string::npos) << iso.note[kB4];
  // the card says how C44 and B4 came about
  const auto dir = pnc::test::fresh_dir("test_fit_isotropic");
  const std::string path = (dir / "card.h5").string();
  write_card(path, card_from_fit(iso, d, "none"), "test");
  const Card c = read_card(path);
  EXPECT_TRUE(c.fit.isotropic);
  EXPECT_EQ(c.status[kC44], "derived");
  EXPECT_EQ(c.status[kB4], "derived");
  EXPECT_DOUBLE_EQ(c.std_error[kB4], iso.std_error[kB4]);
  write_card(path, card_from_fit(free, d, "none"), "test");
  EXPECT_FALSE(read_card(path).fit.isotropic);
}

TEST(FitIsotropic, PropagatedErrorsOfTheDerivedConstantsCoverTheTruthAtTheirNominalRate) {
  // 200 noisy data sets; |k - truth| <= s.e. should hold for 68.3 % of them. Binomial sd of
  // the rate sqrt(0.683 * 0.317 / 200) = 0.033: the band 0.58-0.78 is 3 sd, as for the pooled
  // fit (FitPooled), which only the max(1, chi^2/dof) inflation can widen.
  const NdmParameters truth = isotropic_truth();
  const auto data = [&](int s) {
    return curves(truth, 3e6, 0, 900 + static_cast<std::uint64_t>(s));
  };
  const std::vector<double> c = pnc_fit_test::one_sigma_coverage(data, options(true), truth, 200);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_GE(c[i], 0.58) << constant_names(Model::pp)[i];
    EXPECT_LE(c[i], 0.78) << constant_names(Model::pp)[i];
  }
}

TEST(FitIsotropic, NoisyIsotropicDataGiveAUsableCard) {
  // the law isotropic, 0.5 MPa noise with its errors recorded (the isotropic C44 is 0.056 GPa:
  // the shear stress peaks near 20 MPa, and 2 MPa of noise would put its R^2 near the 0.9 gate)
  const FitReport iso = fit_ndm(curves(isotropic_truth(), 0.5e6, 0.5e6, 5), options(true));
  ASSERT_TRUE(iso.converged) << iso.message;
  EXPECT_EQ(iso.verdict.level, VerdictLevel::usable)
      << (iso.verdict.reasons.empty() ? "" : iso.verdict.reasons.front());
}

TEST(FitIsotropic, ALawThatIsNotIsotropicIsNotForcedIntoIsotropyUnnoticed) {
  // The tables' pure polymer: C44 twice (C11 - C12)/2 and B4 fifteen times B1 - B2/2. Its
  // curves with 2 MPa noise fit the free law (chi^2/dof ~ 1) and not the isotropic one.
  const StressStrainData d = curves(dissertation_parameters(Model::pp), 2e6, 2e6, 5);
  const FitReport free = fit_ndm(d, options(false));
  const FitReport iso = fit_ndm(d, options(true));
  ASSERT_GT(free.dof, 0);
  // chi^2/dof of a correct model: mean 1, sd sqrt(2/dof) ~ 0.04 here; 1.3 is > 7 sd
  EXPECT_LT(free.chi2 / free.dof, 1.3);
  EXPECT_GT(iso.chi2 / iso.dof, 2.0); // outside the verdict's gate [0.5, 2]
  EXPECT_NE(iso.verdict.level, VerdictLevel::usable);
  const bool flagged =
      std::any_of(iso.verdict.reasons.begin(), iso.verdict.reasons.end(), [](const std::string& s) {
        return s.find("does not fit the data within their standard errors") != std::string::npos;
      });
  EXPECT_TRUE(flagged);
}

TEST(FitIsotropic, AConstantDeclaredUndefinedIsHeldNotDerived) {
  FitOptions o = options(true);
  o.undefined = {{"C44", "the material relaxes within a hold (test)"}};
  const FitReport r = fit_ndm(curves(isotropic_truth(), 0, 2e6, 1), o);
  EXPECT_EQ(r.status[kC44], "not identified");
  EXPECT_FALSE(r.fitted[kC44]);
  EXPECT_DOUBLE_EQ(r.params.k[kC44], dissertation_parameters(Model::pp)["C44"]);
  EXPECT_EQ(r.status[kB4], "derived");
}

TEST(FitIsotropic, TheOptionIsRefusedForTheNanocompositeLawNamingItAndTheRule) {
  FitOptions o;
  o.model = Model::pnc;
  o.isotropic = true;
  try {
    o.validate();
    FAIL() << "isotropic accepted for model pnc";
  } catch (const pnc::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("isotropic"), std::string::npos) << m;
    EXPECT_NE(m.find("pure polymer model pp"), std::string::npos) << m;
  }
}
