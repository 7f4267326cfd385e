// The pure polymer fitted to any of cases 1-6 (decision D12l). Under the isotropic reading
// of the pp law (D3) cases 1, 2, 3 are the same curve with the stress components permuted,
// and so are cases 4, 5, 6. Pooling all six cases with the same point errors therefore
// triples J^T J: every covariance shrinks by exactly 3 and every standard error by sqrt(3),
// an exact consequence of the symmetry that the tests below check, together with the
// recovery of the constants and the Monte-Carlo coverage of the pooled errors.
#include "pnc/core/error.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/synth.hpp"

#include "fit_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

using namespace pnc::damage;

namespace {

// Noise-free curves with a recorded point error of sd_pa on every point: chi^2 = 0, so the
// covariance is (J^T J)^-1 with no chi^2/dof factor (D11), a deterministic quantity.
StressStrainData exact_curves(const std::vector<int>& cases, double sd_pa) {
  SynthOptions o;
  o.cases = cases;
  o.points = 40;
  o.max_extension = 0.3; // past the tables' onset (17.1 % for pp)
  o.max_shear = 0.4;
  o.noise_sd = 0;
  StressStrainData d = synthesize(dissertation_parameters(Model::pp), o);
  for (CaseCurve& c : d.cases)
    c.stress_stderr = PathMatrix::Constant(c.stress.rows(), 6, sd_pa);
  return d;
}

StressStrainData noisy_curves(const std::vector<int>& cases, double sd_pa, std::uint64_t seed) {
  SynthOptions o;
  o.cases = cases;
  o.points = 40;
  o.max_extension = 0.3;
  o.max_shear = 0.4;
  o.noise_sd = sd_pa;
  o.seed = seed;
  return synthesize(dissertation_parameters(Model::pp), o);
}

FitOptions pp_options() {
  FitOptions o;
  o.model = Model::pp;
  return o;
}

} // namespace

TEST(FitPooled, SixIsotropicCasesGiveTheConstantsAndErrorsSmallerBySqrtThree) {
  const NdmParameters truth = dissertation_parameters(Model::pp);
  const FitReport two = fit_ndm(exact_curves({2, 6}, 2e6), pp_options());
  const FitReport six = fit_ndm(exact_curves({1, 2, 3, 4, 5, 6}, 2e6), pp_options());
  ASSERT_TRUE(two.converged) << two.message;
  ASSERT_TRUE(six.converged) << six.message;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const std::string name = constant_names(Model::pp)[i];
    ASSERT_TRUE(six.fitted[i]) << name;
    // noise-free data: the constants come back to the solver's tolerance
    EXPECT_NEAR(six.params.k[i], truth.k[i], 1e-6 * std::max(1e9 * (i + 1 < truth.size()), 1.0))
        << name;
    // J^T J tripled: s.e. ratio 1/sqrt(3); the Jacobians are evaluated at fitted constants
    // that equal the truth to ~1e-8, hence the 1e-5 tolerance
    EXPECT_NEAR(six.std_error[i] / two.std_error[i], 1 / std::sqrt(3.0), 1e-5) << name;
  }
}

TEST(FitPooled, PooledStandardErrorsCoverTheTruthAtTheirNominalRate) {
  // 200 noisy data sets of all six cases; |k - truth| <= s.e. should hold for 68.3 % of them.
  // Binomial sd of the rate: sqrt(0.683 * 0.317 / 200) = 0.033; the band 0.58-0.78 is
  // 3 sd, plus the small bias of the max(1, chi^2/dof) inflation (it only widens errors).
  const NdmParameters truth = dissertation_parameters(Model::pp);
  const auto data = [](int s) {
    return noisy_curves({1, 2, 3, 4, 5, 6}, 3e6, 500 + static_cast<std::uint64_t>(s));
  };
  const std::vector<double> c = pnc_fit_test::one_sigma_coverage(data, pp_options(), truth, 200);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_GE(c[i], 0.58) << constant_names(Model::pp)[i];
    EXPECT_LE(c[i], 0.78) << constant_names(Model::pp)[i];
  }
}

TEST(FitPooled, AnyExtensionCaseIsEnoughAndItsComponentsAreLabelledIsotropically) {
  // Case 1 alone carries C11 (sigma11) and C12 (sigma22, sigma33) under isotropy.
  const FitReport r = fit_ndm(exact_curves({1, 5}, 2e6), pp_options());
  ASSERT_TRUE(r.converged) << r.message;
  const NdmParameters truth = dissertation_parameters(Model::pp);
  for (std::size_t i = 0; i < truth.size(); ++i)
    EXPECT_NEAR(r.params.k[i], truth.k[i], 1e-6 * std::max(1e9 * (i + 1 < truth.size()), 1.0))
        << constant_names(Model::pp)[i];
  int seen = 0;
  for (const RegressionLine& l : r.regression) {
    if (l.case_id != 1) continue;
    ++seen;
    EXPECT_EQ(l.linear_label, l.component == 0 ? "C11" : "C12");
    EXPECT_EQ(l.damage_label, l.component == 0 ? "2B1" : "B2");
  }
  EXPECT_EQ(seen, 3);
}

TEST(FitPooled, ANegativeShearInformsWhatItsPositiveOneDoes) {
  // Case 9 is case 6 sheared the other way (D424); along one shear the law is odd
  // (docs/theory.md section 2.1), so every residual's Jacobian row is the positive case's with
  // the sign flipped: J^T J, hence the constants and their errors, are those of case 6 alone.
  // Both senses together: the information I_2 + 2 I_6 lies between I_2 + I_6 and twice it, so
  // every standard error lies between the one-sense error / sqrt(2) and the one-sense error.
  const NdmParameters truth = dissertation_parameters(Model::pp);
  const FitReport pos = fit_ndm(exact_curves({2, 6}, 2e6), pp_options());
  const FitReport neg = fit_ndm(exact_curves({2, 9}, 2e6), pp_options());
  const FitReport both = fit_ndm(exact_curves({2, 6, 9}, 2e6), pp_options());
  ASSERT_TRUE(pos.converged) << pos.message;
  ASSERT_TRUE(neg.converged) << neg.message;
  ASSERT_TRUE(both.converged) << both.message;
  const Verdict v = judge_fit(neg, VerdictLimits{});
  for (const std::string& why : v.reasons) // the sign rule of the verdict reads the case's sense
    EXPECT_EQ(why.find("not of the sign of its strain"), std::string::npos) << why;
  EXPECT_NE(v.level, VerdictLevel::not_usable);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const std::string name = constant_names(Model::pp)[i];
    EXPECT_NEAR(neg.params.k[i], truth.k[i], 1e-6 * std::max(1e9 * (i + 1 < truth.size()), 1.0))
        << name;
    // as in the six-case test: Jacobians at constants equal to the truth to ~1e-8
    EXPECT_NEAR(neg.std_error[i] / pos.std_error[i], 1.0, 1e-5) << name;
    const double r = both.std_error[i] / pos.std_error[i];
    EXPECT_LE(r, 1 + 1e-5) << name;
    EXPECT_GE(r, 1 / std::sqrt(2.0) - 1e-5) << name;
  }
}
