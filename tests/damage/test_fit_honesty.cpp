// A fit that tells the truth about itself: calibrated standard errors (Monte Carlo coverage),
// misfit detection (chi^2, runs), alpha, the finite-shear stretch, identifiability, unit
// mistakes and the card verdict. The data of the misfit and finite-shear tests are written
// out here in closed form, independently of the kernel.
#include "fit_statistics.hpp"
#include "pnc/core/error.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/synth.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>

using namespace pnc::damage;

namespace {

// Closed-form NDM stress of one deformation case (tables' structure, decisions D1-D7 with
// the finite-shear stretch of D6): sigma = (C0 + C1(D(lambda / alpha))) eps along the case.
struct ClosedForm {
  NdmParameters p;
  double D(double lambda) const {
    const double lc = std::pow(26.0 / 7.0, 1.0 / 6.0);
    const double k = 1.0 / std::abs(2 * std::pow(lc, -13) - std::pow(lc, -7));
    const double x = lambda / p.alpha();
    return x > lc ? 1 + k * (2 * std::pow(x, -13) - std::pow(x, -7)) : 0.0;
  }
  Voigt stress(int case_id, double t) const {
    Voigt s = Voigt::Zero();
    const auto& k = p;
    if (case_id <= 3) { // laterally constrained extension: lambda = 1 + t drives D_case
      const double d = D(1 + t);
      if (case_id == 1)
        s << (k["C11"] + 2 * k["A1"] * d) * t, (k["C12"] + k["A10"] * d) * t,
            (k["C13"] + k["A13"] * d) * t, 0, 0, 0;
      if (case_id == 2)
        s << (k["C12"] + k["A11"] * d) * t, (k["C22"] + 2 * k["A5"] * d) * t,
            (k["C23"] + k["A17"] * d) * t, 0, 0, 0;
      if (case_id == 3)
        s << (k["C13"] + k["A15"] * d) * t, (k["C23"] + k["A18"] * d) * t,
            (k["C33"] + 2 * k["A9"] * d) * t, 0, 0, 0;
      return s;
    }
    const double d = D(t / 2 + std::sqrt(1 + t * t / 4)); // simple shear, finite stretch
    if (case_id == 4) s[3] = (k["C44"] + k["A22"] * d) * t;
    if (case_id == 5) s[4] = (k["C55"] + k["A26"] * d) * t;
    if (case_id == 6) s[5] = (k["C66"] + k["A24"] * d) * t;
    return s;
  }
};

// Six cases of `points` points each from the closed form, Gaussian noise of sd(k, i) Pa on
// every component, stress_stderr = that sd (or none when with_errors is false).
template <class Sd>
StressStrainData closed_form_data(const NdmParameters& p, int points, std::uint64_t seed, Sd sd,
                                  bool with_errors = true) {
  const ClosedForm cf{p};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  StressStrainData d;
  d.source = "<closed form>";
  d.stress_definition = "synthetic closed form";
  for (int id = 1; id <= 6; ++id) {
    CaseCurve c;
    c.id = id;
    c.strain.resize(points, 6);
    c.stress.resize(points, 6);
    c.stress_stderr.resize(with_errors ? points : 0, 6);
    const double top = id <= 3 ? 0.2 : 0.4;
    for (int k = 0; k < points; ++k) {
      const double t = top * (k + 1) / points;
      c.strain.row(k) = case_strain(id, t).transpose();
      const Voigt s = cf.stress(id, t);
      for (int i = 0; i < 6; ++i) {
        const double e = sd(id, k, points);
        c.stress(k, i) = s[i] + e * g(rng);
        if (with_errors) c.stress_stderr(k, i) = e;
      }
    }
    d.cases.push_back(std::move(c));
  }
  return d;
}

double uniform_sd(int, int, int) {
  return 1e6;
}
// Unequal errors: grows with strain (as MD noise grows with damage) and differs per case.
double growing_sd(int id, int k, int n) {
  return 0.5e6 * (1 + 0.5 * id) * (1 + 4.0 * k / n);
}

double max_abs_z(const FitReport& r, const NdmParameters& truth) {
  double zmax = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (!r.fitted[i]) continue;
    zmax = std::max(zmax, std::abs(r.params.k[i] - truth.k[i]) / r.std_error[i]);
  }
  return zmax;
}

bool has_reason(const Verdict& v, const std::string& text) {
  for (const auto& r : v.reasons)
    if (r.find(text) != std::string::npos) return true;
  return false;
}

} // namespace

// ---------------------------------------------------------------- statistics pieces
TEST(FitStatistics, ChiSquareTailMatchesClosedForms) {
  // dof = 2: P(X >= x) = exp(-x/2) exactly; dof = 1: erfc(sqrt(x/2)).
  for (double x : {0.1, 1.0, 4.0, 20.0, 80.0}) {
    EXPECT_NEAR(stats::chi2_upper_tail(x, 2), std::exp(-x / 2), 1e-12 * (1 + std::exp(-x / 2)));
    EXPECT_NEAR(stats::chi2_upper_tail(x, 1), std::erfc(std::sqrt(x / 2)), 1e-12);
  }
  // Large dof: the median of chi^2_dof is ~ dof (1 - 2/(9 dof))^3.
  const double dof = 500, med = dof * std::pow(1 - 2 / (9 * dof), 3);
  EXPECT_NEAR(stats::chi2_upper_tail(med, dof), 0.5, 2e-3);
}

TEST(FitStatistics, RunsTestSeesTrendsNotNoise) {
  std::vector<double> trend, alternating;
  for (int i = 0; i < 40; ++i) {
    trend.push_back(i < 20 ? -1.0 : 1.0); // two runs
    alternating.push_back(i % 2 ? 1.0 : -1.0);
  }
  const auto t = stats::runs_test(trend), a = stats::runs_test(alternating);
  EXPECT_EQ(t.runs, 2);
  EXPECT_EQ(a.runs, 40);
  EXPECT_NEAR(t.expected, 21.0, 1e-12); // 2 n+ n- / n + 1 with n+ = n- = 20
  EXPECT_LT(t.p_too_few, 1e-6);
  EXPECT_GT(a.p_too_few, 0.99);
  EXPECT_GT(t.lag1, 0.9);
  EXPECT_LT(a.lag1, -0.9);
  // Independent noise: the one-sided p-value is uniform, so p < 0.05 in about 5 % of series.
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  int small = 0;
  const int series = 2000;
  for (int s = 0; s < series; ++s) {
    std::vector<double> r(60);
    for (auto& x : r)
      x = g(rng);
    small += stats::runs_test(r).p_too_few < 0.05;
  }
  // binomial sd of the count: sqrt(2000 * 0.05 * 0.95) = 9.7; the normal approximation of
  // the runs distribution at n = 60 is good to ~1 %: allow 3 % .. 7 %.
  EXPECT_GT(small, 0.03 * series);
  EXPECT_LT(small, 0.07 * series);
}

TEST(FitStatistics, IdentifiabilityFindsZeroColumnsAndDegenerateCombinations) {
  Eigen::MatrixXd J(5, 4);
  J << 1, 2, 0, 2, 2, 1, 0, 1, 3, 0, 0, 0, 1, 1, 0, 1, 0, 2, 0, 2;
  // column 2 is zero; column 3 equals column 1 (only their sum is determined)
  std::vector<std::string> why;
  const auto bad = stats::not_identified(J, why, {"a", "b", "c", "d"});
  EXPECT_FALSE(bad[0]);
  EXPECT_TRUE(bad[1]);
  EXPECT_TRUE(bad[2]);
  EXPECT_TRUE(bad[3]);
  EXPECT_NE(why[2].find("no effect"), std::string::npos);
  EXPECT_NE(why[1].find("b, d"), std::string::npos) << why[1];
}

// ---------------------------------------------------------------- calibration
// Coverage of the reported 1-sigma intervals over N independent data sets of 30 points per
// case (an MD characterisation has 20-40 strain steps per case). With correct
// errors a constant is covered with probability 0.683; over N = 400 sets the count is
// binomial with sd sqrt(0.683 * 0.317 / 400) = 2.3 %, so [60 %, 76 %] is +-3.4 sd: for 22
// constants the chance that any falls outside by luck alone is ~1.5 %. Errors wrong by 25 %
// (coverage 0.58 or 0.79) fall outside.
void expect_calibrated(bool with_errors) {
  const NdmParameters truth = dissertation_parameters(Model::pnc);
  const int N = 400;
  std::vector<int> covered(truth.size(), 0), counted(truth.size(), 0);
  for (int s = 0; s < N; ++s) {
    const StressStrainData d =
        closed_form_data(truth, 30, 1000 + static_cast<std::uint64_t>(s), growing_sd, with_errors);
    FitOptions o;
    o.max_iterations = 50;
    const FitReport r = fit_ndm(d, o);
    for (std::size_t i = 0; i < truth.size(); ++i) {
      if (!r.fitted[i] || !std::isfinite(r.std_error[i])) continue;
      ++counted[i];
      covered[i] += std::abs(r.params.k[i] - truth.k[i]) <= r.std_error[i];
    }
  }
  for (std::size_t i = 0; i < truth.size(); ++i) {
    ASSERT_EQ(counted[i], N) << constant_names(Model::pnc)[i] << " not always fitted";
    const double c = static_cast<double>(covered[i]) / N;
    if (std::getenv("PNC_PRINT_COVERAGE"))
      std::printf("%s %.3f\n", constant_names(Model::pnc)[i].c_str(), c);
    EXPECT_GE(c, 0.60) << constant_names(Model::pnc)[i];
    EXPECT_LE(c, 0.76) << constant_names(Model::pnc)[i];
  }
}

TEST(FitCalibration, OneSigmaCoverageWithTheDataErrorsAsWeights) {
  expect_calibrated(true);
}

TEST(FitCalibration, OneSigmaCoverageWithTheSandwichEstimateWhenNoErrorsAreGiven) {
  expect_calibrated(false);
}

// ---------------------------------------------------------------- alpha and misfit
TEST(FitAlpha, ADifferentAlphaIsFittedByDefaultAndAHeldOneIsFlaggedAsMisfit) {
  NdmParameters truth = dissertation_parameters(Model::pnc);
  truth["alpha"] = 0.90; // the tables say 0.861
  const StressStrainData d = closed_form_data(truth, 40, 7, uniform_sd);
  const FitReport a = fit_ndm(d, FitOptions{});
  EXPECT_TRUE(a.fitted.back()) << a.alpha_choice;
  // 22 constants: |z| < 4 for all of them by chance with probability 0.9986.
  EXPECT_LT(max_abs_z(a, truth), 4.0);
  EXPECT_NE(a.verdict.level, VerdictLevel::not_usable);
  EXPECT_FALSE(has_reason(a.verdict, "does not fit")) << a.chi2 / a.dof;

  FitOptions hold;
  hold.alpha_mode = AlphaMode::hold; // at the tables' 0.861
  const FitReport h = fit_ndm(d, hold);
  EXPECT_FALSE(h.fitted.back());
  EXPECT_TRUE(has_reason(h.verdict, "does not fit the data within their standard errors"));
  EXPECT_TRUE(has_reason(h.verdict, "alpha is held although the data pass the damage onset"));
  EXPECT_NE(h.verdict.level, VerdictLevel::usable);
}

TEST(FitAlpha, FiniteShearDataAreFittedWithoutBias) {
  // The closed form uses the principal stretch of simple shear gamma/2 + sqrt(1 + gamma^2/4);
  // the kernel's stretch (D6) must be the same, so the shear damage constants come back.
  const NdmParameters truth = dissertation_parameters(Model::pnc);
  const StressStrainData d = closed_form_data(truth, 40, 11, uniform_sd);
  const FitReport r = fit_ndm(d, FitOptions{});
  EXPECT_LT(max_abs_z(r, truth), 4.0);
  for (const char* a : {"A22", "A24"}) {
    const auto j = static_cast<std::size_t>(constant_index(Model::pnc, a));
    EXPECT_LT(std::abs(r.params.k[j] - truth.k[j]), 4 * r.std_error[j]) << a;
  }
  EXPECT_FALSE(has_reason(r.verdict, "does not fit"));
}

// ---------------------------------------------------------------- identifiability
TEST(FitIdentifiability, AlphaWithoutDataPastAnyOnsetIsNotIdentified) {
  // Strains below every onset: asked to fit alpha, the fit finds it has no effect on the
  // stresses at the solution, holds it and says so; the A constants likewise.
  SynthOptions o;
  o.max_extension = 0.05;
  o.max_shear = 0.1;
  o.points = 30;
  o.noise_sd = 1e6;
  FitOptions f;
  f.alpha_mode = AlphaMode::fit;
  const FitReport r = fit_ndm(synthesize(dissertation_parameters(Model::pnc), o), f);
  EXPECT_EQ(r.status.back(), "not identified");
  EXPECT_TRUE(std::isnan(r.std_error.back()));
  EXPECT_EQ(r.status[static_cast<std::size_t>(constant_index(Model::pnc, "A5"))], "not identified");
  EXPECT_TRUE(has_reason(r.verdict, "alpha is not identified"));
  EXPECT_EQ(r.status[static_cast<std::size_t>(constant_index(Model::pnc, "C22"))], "fitted");
}

// ---------------------------------------------------------------- units
TEST(FitUnits, StressesInPascalReadAsMegapascalAreRefused) {
  StressStrainData d = closed_form_data(dissertation_parameters(Model::pnc), 20, 5, uniform_sd);
  for (auto& c : d.cases) { // a CSV written in Pa under the MPa header: 1e6 times too large
    c.stress *= 1e6;
    c.stress_stderr *= 1e6;
  }
  d.source = "in_pa.csv";
  try {
    fit_ndm(d, FitOptions{});
    FAIL() << "accepted";
  } catch (const pnc::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("in_pa.csv"), std::string::npos) << m;
    EXPECT_NE(m.find("Pa instead of MPa"), std::string::npos) << m;
  }
  FitOptions o;
  o.check_units = false; // the override
  EXPECT_NO_THROW(fit_ndm(d, o));
}

// ---------------------------------------------------------------- the verdict
StressStrainData offset_noise_data() {
  // What a noise-dominated MD run looks like to the fit: a stress offset the model (sigma =
  // C eps, no intercept) cannot have, plus noise, and hardly any signal.
  NdmParameters tiny = dissertation_parameters(Model::pnc);
  for (std::size_t i = 0; i + 1 < tiny.size(); ++i)
    tiny.k[i] *= 1e-4;
  StressStrainData d = closed_form_data(tiny, 20, 3, [](int, int, int) { return 2e6; });
  for (auto& c : d.cases)
    c.stress.array() += 30e6;
  return d;
}

TEST(FitVerdict, NoiseDominatedDataGiveANotUsableCardThatSaysWhy) {
  const StressStrainData d = offset_noise_data();
  FitOptions o;
  o.check_units = false; // the MD pipeline's setting: judged, not refused
  const FitReport r = fit_ndm(d, o);
  EXPECT_EQ(r.verdict.level, VerdictLevel::not_usable);
  EXPECT_TRUE(has_reason(r.verdict, "worse than their mean"));
  // the card carries it
  const auto dir = pnc::test::fresh_dir("test_verdict");
  const std::string path = (dir / "bad.h5").string();
  write_card(path, card_from_fit(r, d, "none"), "test");
  const Card c = read_card(path);
  EXPECT_EQ(c.verdict.level, VerdictLevel::not_usable);
  EXPECT_EQ(c.verdict.reasons, r.verdict.reasons);
  std::filesystem::remove_all(dir);
}

TEST(FitVerdict, CleanDataGiveAUsableCard) {
  const FitReport r = fit_ndm(
      closed_form_data(dissertation_parameters(Model::pnc), 40, 21, uniform_sd), FitOptions{});
  EXPECT_EQ(r.verdict.level, VerdictLevel::usable)
      << (r.verdict.reasons.empty() ? "" : r.verdict.reasons.front());
}

// D12g: a damage constant whose mode never reaches the onset of the *start* alpha is freed
// once the fitted alpha moves the onset into the data. Pure polymer, truth alpha = 0.82
// (onset at stretch 1.0205: shear gamma = 0.041), start alpha = the tables' 0.941 (onset at
// stretch 1.171: extension reaches it at 0.2, shear up to gamma = 0.2, stretch 1.105, does
// not). Without the re-examination B4 stays at the tables' value and the shear curve is
// described by a wrong damage constant.
TEST(FitAlpha, ADamageConstantHeldAtTheStartAlphaIsFreedWhenTheFittedOnsetReachesItsMode) {
  NdmParameters truth = dissertation_parameters(Model::pp);
  truth["alpha"] = 0.82;
  truth["B4"] = -0.4 * truth["C44"]; // well away from the tables' value
  const double lc = std::pow(26.0 / 7.0, 1.0 / 6.0);
  const double kd = 1.0 / std::abs(2 * std::pow(lc, -13) - std::pow(lc, -7));
  auto D = [&](double lambda) {
    const double x = lambda / truth.alpha();
    return x > lc ? 1 + kd * (2 * std::pow(x, -13) - std::pow(x, -7)) : 0.0;
  };
  std::mt19937_64 rng(31);
  std::normal_distribution<double> g(0.0, 1.0);
  const double sd = 0.5e6, n = 60;
  StressStrainData d;
  d.source = "<closed form>";
  d.stress_definition = "synthetic closed form";
  for (int id : {2, 6}) {
    CaseCurve c;
    c.id = id;
    c.strain.resize(static_cast<Eigen::Index>(n), 6);
    c.stress.resize(static_cast<Eigen::Index>(n), 6);
    c.stress_stderr = Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(n), 6, sd);
    for (int k = 0; k < n; ++k) {
      const double t = 0.2 * (k + 1) / n;
      c.strain.row(k) = case_strain(id, t).transpose();
      Voigt s = Voigt::Zero();
      if (id == 2) {
        const double dd = D(1 + t);
        s << (truth["C12"] + truth["B2"] * dd) * t, (truth["C11"] + 2 * truth["B1"] * dd) * t,
            (truth["C12"] + truth["B2"] * dd) * t, 0, 0, 0;
      } else {
        s[5] = (truth["C44"] + truth["B4"] * D(t / 2 + std::sqrt(1 + t * t / 4))) * t;
      }
      for (int i = 0; i < 6; ++i)
        c.stress(k, i) = s[i] + sd * g(rng);
    }
    d.cases.push_back(std::move(c));
  }
  FitOptions o;
  o.model = Model::pp;
  const FitReport r = fit_ndm(d, o);
  ASSERT_TRUE(r.fitted.back()) << r.alpha_choice;
  const auto jB4 = static_cast<std::size_t>(constant_index(Model::pp, "B4"));
  EXPECT_TRUE(r.fitted[jB4]) << r.note[jB4];
  EXPECT_EQ(r.status[jB4], "fitted");
  // 6 constants: |z| < 4 for all by chance with probability 0.9996
  EXPECT_LT(max_abs_z(r, truth), 4.0);
  EXPECT_EQ(r.verdict.level, VerdictLevel::usable)
      << (r.verdict.reasons.empty() ? "" : r.verdict.reasons.front());
}
