// The bootstrap of the joint fit over replicas (decision D431), by Monte Carlo on replica
// curves whose noise is correlated along the curve as an MD replica's is (a random offset per
// replica and component plus AR(1) noise, lag-1 correlation 0.9; replica_noise.hpp). Calibration:
// the bootstrap spread of one run estimates the spread of the joint fit over independent runs. Use:
// an error below that spread is raised to it, one above it is never lowered; fewer than 8 replicas
// are refused with the reason.
#include "pnc/damage/fit.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/rve/replica_bootstrap.hpp"
#include "replica_noise.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace pnc;

namespace {

// N replicas of cases 2 and 6 of the pure-polymer law with alpha 0.85, 40 rows to 0.12; noise
// per replica and component an offset of sd 0.3 MPa plus AR(1) of sd 0.51 MPa (replica_noise.hpp)
rve::CombinedCases make_run(int nrep, std::mt19937_64& rng) {
  return test::make_trial(nrep, rng, 0.0, {2, 6}, 0.3).cases;
}

damage::FitOptions options() {
  damage::FitOptions o;
  o.model = damage::Model::pp;
  o.alpha = 0.85;
  o.alpha_mode = damage::AlphaMode::fit;
  return o;
}

/// The joint fit of every replica of the run, combined as cases.h5 holds it (D130).
damage::FitReport joint_fit(const rve::CombinedCases& c) {
  std::vector<int> all;
  for (int r = 0; r < c.replicas; ++r)
    all.push_back(r);
  return damage::fit_ndm(rve::replica_mean_data(c, all), options());
}

} // namespace

TEST(ReplicaBootstrap, SpreadOfOneRunEstimatesTheSpreadOverIndependentRuns) {
  constexpr int kReplicas = 16, kRuns = 200, kBootRuns = 24, kResamples = 60;
  std::mt19937_64 rng(431);
  // the truth: the joint fit's spread over independent runs
  std::vector<std::vector<double>> values;
  damage::FitReport first;
  for (int t = 0; t < kRuns; ++t) {
    const damage::FitReport f = joint_fit(make_run(kReplicas, rng));
    ASSERT_TRUE(f.converged);
    if (t == 0) first = f;
    values.emplace_back(f.params.k.begin(), f.params.k.end());
  }
  const std::size_t nk = damage::constant_names(damage::Model::pp).size();
  std::vector<double> true_sd(nk, 0.0);
  for (std::size_t i = 0; i < nk; ++i) {
    double m = 0, v = 0;
    for (const auto& x : values)
      m += x[i] / kRuns;
    for (const auto& x : values)
      v += (x[i] - m) * (x[i] - m) / (kRuns - 1);
    true_sd[i] = std::sqrt(v);
  }
  // the estimate: the bootstrap spread of single runs, averaged over kBootRuns runs
  std::vector<double> spread(nk, 0.0);
  for (int t = 0; t < kBootRuns; ++t) {
    const rve::CombinedCases c = make_run(kReplicas, rng);
    const damage::FitReport f = joint_fit(c);
    const rve::ReplicaBootstrap b =
        rve::bootstrap_joint_fit(c, options(), f, true_sd, kResamples, 1000 + t);
    ASSERT_TRUE(b.applicable) << b.why_not;
    EXPECT_EQ(b.failed, 0);
    for (std::size_t i = 0; i < nk; ++i)
      if (first.fitted[i]) spread[i] += b.spread[i] / kBootRuns;
  }
  // Relative standard errors: true_sd from 200 runs 1/sqrt(2*199) = 0.050; one run's bootstrap
  // spread 1/sqrt(2*59) = 0.092 from 60 resamples and ~1/sqrt(2*15) = 0.18 from its 16
  // replicas, 0.20 together, 0.041 as the mean of 24 runs; the ratio 0.065. The bootstrap
  // spread is corrected for its bias for a mean, sqrt((N-1)/N) = 0.968; for the nonlinear
  // damage constants the bias may differ by a few % either way. Band: 1 -+ 3 x 0.065, widened
  // by that 3.2 % on both sides. B4 is left out: with these curves
  // the shear case barely constrains it (some runs find it "not identified", held at the
  // prior), so its spread over runs is not a finite, normal-like number to estimate.
  const auto names = damage::constant_names(damage::Model::pp);
  int checked = 0;
  for (std::size_t i = 0; i < nk; ++i) {
    if (!first.fitted[i] || names[i] == "B4") continue;
    ++checked;
    const double ratio = spread[i] / true_sd[i];
    EXPECT_GT(ratio, 0.968 * (1 - 3 * 0.065)) << names[i];
    EXPECT_LT(ratio, (1 + 3 * 0.065) / 0.968) << names[i];
    std::printf("%s: bootstrap spread / true spread %.3f\n", names[i].c_str(), ratio);
  }
  EXPECT_EQ(checked, 6); // C11, C12, C44, B1, B2, alpha
}

TEST(ReplicaBootstrap, RaisesAnErrorBelowTheSpreadAndNeverLowersOne) {
  std::mt19937_64 rng(7);
  const rve::CombinedCases c = make_run(12, rng);
  const damage::FitReport f = joint_fit(c);
  const std::size_t nk = damage::constant_names(damage::Model::pp).size();
  std::vector<double> large(nk), small(nk);
  const auto names = damage::constant_names(damage::Model::pp);
  for (std::size_t i = 0; i < nk; ++i) {
    // 1 Pa and 1000 GPa (alpha: 1e-9 and 1000): far below and far above any spread here
    const bool alpha = names[i] == "alpha";
    small[i] = alpha ? 1e-9 : 1.0;
    large[i] = alpha ? 1e3 : 1e12;
  }
  rve::ReplicaBootstrap up = rve::bootstrap_joint_fit(c, options(), f, small, 40, 3);
  ASSERT_TRUE(up.applicable) << up.why_not;
  std::vector<double> errors = small;
  const int raised = rve::apply_bootstrap(up, errors);
  int fitted = 0;
  for (std::size_t i = 0; i < errors.size(); ++i) {
    if (!f.fitted[i]) {
      EXPECT_EQ(errors[i], small[i]) << "a held constant is left alone";
      continue;
    }
    ++fitted;
    EXPECT_TRUE(up.raised[i]);
    EXPECT_EQ(errors[i], up.spread[i]);
    EXPECT_GT(up.ratio[i], 1.0);
  }
  EXPECT_EQ(raised, fitted);
  rve::ReplicaBootstrap keep = rve::bootstrap_joint_fit(c, options(), f, large, 40, 3);
  errors = large;
  EXPECT_EQ(rve::apply_bootstrap(keep, errors), 0);
  EXPECT_EQ(errors, large);
  // the same seed draws the same resamples: the check is reproducible
  for (std::size_t i = 0; i < nk; ++i)
    if (std::isfinite(up.spread[i])) {
      EXPECT_EQ(keep.spread[i], up.spread[i]);
    }
  const std::string md = rve::replica_bootstrap_markdown(up);
  EXPECT_NE(md.find("| yes |"), std::string::npos) << md;
  EXPECT_EQ(rve::replica_bootstrap_json(up)["resamples"], 40);
  const std::string line = rve::replica_bootstrap_summary(up);
  EXPECT_NE(line.find("raised to the spread: C11, C12, C44, B1, B2"), std::string::npos) << line;
  EXPECT_NE(rve::replica_bootstrap_summary(keep).find("raised to the spread: none"),
            std::string::npos);
}

TEST(ReplicaBootstrap, RefusesFewReplicasAndFewResamplesWithTheReason) {
  std::mt19937_64 rng(1);
  const rve::CombinedCases few = make_run(7, rng);
  const damage::FitReport f = joint_fit(few);
  std::vector<double> errors = f.std_error;
  rve::ReplicaBootstrap b = rve::bootstrap_joint_fit(few, options(), f, errors, 200, 1);
  EXPECT_FALSE(b.applicable);
  EXPECT_NE(b.why_not.find(">= 8 replicas (this run: 7)"), std::string::npos) << b.why_not;
  EXPECT_EQ(rve::apply_bootstrap(b, errors), 0);
  EXPECT_NE(rve::replica_bootstrap_markdown(b).find("Not run"), std::string::npos);
  EXPECT_NE(rve::replica_bootstrap_summary(b).find("not checked"), std::string::npos);
  const rve::CombinedCases enough = make_run(8, rng);
  rve::ReplicaBootstrap off =
      rve::bootstrap_joint_fit(enough, options(), joint_fit(enough), errors, 19, 1);
  EXPECT_FALSE(off.applicable);
  EXPECT_NE(off.why_not.find("below 20"), std::string::npos) << off.why_not;
}
