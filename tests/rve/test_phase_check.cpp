// Phase-check estimators (pnc/rve/phase_check.hpp) on synthetic Ornstein-Uhlenbeck series
// whose autocorrelation is known exactly: <x(0) x(k dt)> = s^2 phi^k, phi = exp(-dt/tau).
#include "pnc/core/error.hpp"
#include "pnc/rve/phase_check.hpp"
#include "pnc/rve/recipe.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace pnc::rve;
using namespace pnc::md;

namespace {
/// Exact discretisation of an OU process: stationary start, variance s2, phi per sample.
std::vector<double> ou(std::size_t n, double s2, double phi, std::mt19937_64& g) {
  std::normal_distribution<double> z(0.0, 1.0);
  std::vector<double> x(n);
  x[0] = std::sqrt(s2) * z(g);
  const double w = std::sqrt(s2 * (1 - phi * phi));
  for (std::size_t i = 1; i < n; ++i)
    x[i] = phi * x[i - 1] + w * z(g);
  return x;
}
/// 97.5 % quantile of Student's t with 9 degrees of freedom (10 blocks)
constexpr double kT9 = 2.262;
} // namespace

TEST(PhaseAcf, OrnsteinUhlenbeckMatchesTheAnalyticAutocorrelation) {
  std::mt19937_64 g(11);
  const double s2 = 4.0, tau = 10.0, phi = std::exp(-1.0 / tau);
  std::vector<std::vector<double>> c;
  for (int k = 0; k < 3; ++k)
    c.push_back(ou(40000, s2, phi, g));
  const AcfEstimate e = autocorrelation(c, 1.0, 40, 10);
  ASSERT_EQ(e.value.size(), 41u);
  for (int k : {0, 5, 10, 20, 40}) {
    const double exact = s2 * std::pow(phi, k);
    // 5 standard errors: for a calibrated error bar (t with 9 dof) a ~1-in-1000 event
    EXPECT_NEAR(e.value[k], exact, 5 * e.se[k]) << "lag " << k;
    EXPECT_GT(e.se[k], 0.0);
  }
  // integrated time of AR(1): (1 + phi) / (2 (1 - phi)); Sokal's error sqrt(2(2W+1)/N) tau
  const double ti = (1 + phi) / (2 * (1 - phi));
  EXPECT_NEAR(e.tau_int, ti, 4 * ti * std::sqrt(2.0 * (2 * 5 * ti + 1) / 40000.0));
  EXPECT_TRUE(e.blocks_ok); // blocks of ~4000 samples >> 5 x 10.5
}

TEST(PhaseAcf, ErrorBarCoverageOverIndependentSeriesIsNominal) {
  // 400 independent runs; the block error (10 blocks: t with 9 dof) must cover the exact value
  // at the nominal 95 %: binomial sd sqrt(0.95 * 0.05 / 400) = 0.011, 4 sd -> [0.906, 0.994]
  std::mt19937_64 g(12345);
  const double s2 = 1.0, tau = 8.0, phi = std::exp(-1.0 / tau);
  const int runs = 400;
  const int lags[] = {0, 8, 16};
  int hit[3] = {0, 0, 0}, whit = 0;
  double wexact = 0; // window mean over lags 4..12 (how the plateau is formed)
  for (int k = 4; k <= 12; ++k)
    wexact += s2 * std::pow(phi, k) / 9;
  for (int r = 0; r < runs; ++r) {
    std::vector<std::vector<double>> c;
    for (int k = 0; k < 3; ++k)
      c.push_back(ou(4000, s2, phi, g));
    const AcfEstimate e = autocorrelation(c, 1.0, 16, 10);
    for (int i = 0; i < 3; ++i)
      if (std::fabs(e.value[lags[i]] - s2 * std::pow(phi, lags[i])) < kT9 * e.se[lags[i]]) ++hit[i];
    const auto [wm, wse] = window_mean(e, 4, 12);
    if (std::fabs(wm - wexact) < kT9 * wse) ++whit;
  }
  EXPECT_GT(whit / 400.0, 0.906);
  EXPECT_LT(whit / 400.0, 0.994);
  for (int i = 0; i < 3; ++i) {
    const double cov = static_cast<double>(hit[i]) / runs;
    EXPECT_GT(cov, 0.906) << "lag " << lags[i];
    EXPECT_LT(cov, 0.994) << "lag " << lags[i];
  }
}

TEST(PhaseAcf, BlockCheckFlagsBlocksShorterThanTheCorrelationTime) {
  std::mt19937_64 g(3);
  // tau_int ~ 200 samples, blocks of (4000 - 10) / 10 = 399 samples < 5 tau_int: flagged
  const double slow = std::exp(-1.0 / 200.0), fast = std::exp(-1.0 / 2.0);
  std::vector<std::vector<double>> a{ou(4000, 1, slow, g), ou(4000, 1, slow, g)};
  const AcfEstimate ea = autocorrelation(a, 1.0, 10, 10);
  EXPECT_FALSE(ea.blocks_ok) << ea.tau_int << " " << ea.block_length;
  EXPECT_GT(kMinBlockOverTau * ea.tau_int, ea.block_length);
  std::vector<std::vector<double>> b{ou(4000, 1, fast, g), ou(4000, 1, fast, g)};
  const AcfEstimate eb = autocorrelation(b, 1.0, 10, 10);
  EXPECT_TRUE(eb.blocks_ok) << eb.tau_int << " " << eb.block_length;
  // too short a series for the lags and blocks: refused
  EXPECT_THROW(autocorrelation({std::vector<double>(20, 0.0)}, 1.0, 15, 10), std::invalid_argument);
}

TEST(PhaseAcf, SlopeAndItsErrorOnAKnownLine) {
  // y = 2 + 3 t + e, e ~ N(0, 1): slope se = 1/sqrt(sum (t - tbar)^2); coverage over 400 runs
  std::mt19937_64 g(5);
  std::normal_distribution<double> z(0, 1);
  std::vector<double> t;
  for (int i = 0; i < 20; ++i)
    t.push_back(i);
  int hit = 0;
  for (int r = 0; r < 400; ++r) {
    std::vector<double> y;
    for (double ti : t)
      y.push_back(2 + 3 * ti + z(g));
    const auto [b, se] = slope_se(t, y);
    if (std::fabs(b - 3) < 2.101 * se) ++hit; // t_18, 97.5 %
  }
  EXPECT_GT(hit / 400.0, 0.906);
  EXPECT_LT(hit / 400.0, 0.994);
}

TEST(PhaseClassify, ThresholdsAsDocumented) {
  PhaseCheckResult r;
  r.G_plateau_Pa = 1e9;
  r.G_hold_Pa = 1.2e9; // 55 % of the plateau G_hold + G_acf(0.5 ps), resolved
  r.G_hold_se_Pa = 0.1e9;
  classify(r);
  EXPECT_TRUE(r.solid);
  EXPECT_EQ(r.phase, "solid on the hold time scale");
  r.G_hold_Pa = 0.9e9; // 47 %
  classify(r);
  EXPECT_FALSE(r.solid);
  r.G_hold_Pa = 2e9;
  r.G_hold_se_Pa = 0.7e9; // 2.9 s.e.: not resolved
  classify(r);
  EXPECT_FALSE(r.solid);
  EXPECT_EQ(r.phase, "relaxes within a hold");
  EXPECT_NE(r.summary.find("not resolved"), std::string::npos);
}

TEST(PhaseRecipe, KeyDefaultsValidationAndPresets) {
  const auto r = parse_recipe(nlohmann::json::object(), "t.json");
  EXPECT_FALSE(r.phase_check.enabled); // off unless asked
  for (const auto& n : preset_names()) {
    const auto p = parse_recipe(preset_json(n), n);
    EXPECT_TRUE(p.phase_check.enabled) << n;
    EXPECT_GE(p.phase_check.steps, 2 * p.deform.hold_steps) << n;
    // the expanded recipe carries every key and reads back to the same spec
    const auto back = parse_recipe(expanded_json(p), n);
    EXPECT_EQ(back.phase_check.steps, p.phase_check.steps);
    EXPECT_EQ(back.phase_check.cavitation_strain, p.phase_check.cavitation_strain);
  }
  auto err = [](const char* text) {
    try {
      parse_recipe(nlohmann::json::parse(text), "t.json");
    } catch (const pnc::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err(R"({"phase_check": {"steps": 10}})").find("phase_check.steps"), std::string::npos);
  EXPECT_NE(err(R"({"phase_check": {"bulk_strain": -0.1}})").find("phase_check.bulk_strain"),
            std::string::npos);
  EXPECT_NE(err(R"({"phase_check": {"enabled": 1}})").find("phase_check.enabled"),
            std::string::npos);
  EXPECT_NE(err(R"({"phase_check": {"colour": 1}})").find("unknown key"), std::string::npos);
  const std::string s = err(R"({"phase_check": {"enabled": true, "steps": 15000},
                                "deform": {"hold_steps": 10000}})");
  EXPECT_NE(s.find("2 x deform.hold_steps"), std::string::npos) << s;
}

TEST(PhaseHold, HoldMeanErrorCoverageAndBlockRule) {
  // hold means: 400 OU runs of 400 samples, tau_int ~ 5.5 samples -> 10 blocks of 40 (>= 5
  // tau): coverage of +-t_9 s.e. of the exact mean 0 in [0.906, 0.994]
  std::mt19937_64 g(77);
  const double phi = std::exp(-1.0 / 5.0);
  int hit = 0, ok = 0;
  for (int r = 0; r < 400; ++r) {
    const MeanSe m = hold_mean_se(ou(400, 1.0, phi, g));
    ok += m.ok;
    hit += std::fabs(m.mean) < (m.blocks == 10 ? kT9 : 3.182) * m.se;
  }
  EXPECT_EQ(ok, 400);
  EXPECT_GT(hit / 400.0, 0.906);
  EXPECT_LT(hit / 400.0, 0.994);
  // tau ~ 50 samples: 4 blocks of 5 tau do not fit in 400 samples -> flagged
  const MeanSe slow = hold_mean_se(ou(400, 1.0, std::exp(-1.0 / 50.0), g));
  EXPECT_FALSE(slow.ok);
  EXPECT_EQ(slow.blocks, 4);
}
