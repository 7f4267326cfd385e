// Statistics of the replicas' deformation data (rve/replicas.hpp on md/statistics.hpp;
// decisions D130-D134), on synthetic data only (no MD): Monte Carlo coverage of the
// between-replica standard error of a fitted slope, the reference-state error propagation
// against Monte Carlo, and smoothing that must not shrink an error.
#include "common/synthetic_series.hpp"
#include "pnc/damage/cases.hpp"
#include "pnc/md/statistics.hpp"
#include "pnc/rve/replica_fits.hpp"
#include "pnc/rve/replicas.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <set>

using namespace pnc::rve;
using namespace pnc::md;
using pnc::test::ar1;
using pnc::test::binomial_band;

namespace {

/// One synthetic case 2 result: row 0 the zero-strain hold, rows 1..steps strain k h. The
/// virial and total stresses are given the same numbers (the choice is tested elsewhere).
CaseResult synthetic_case(int id, const std::vector<double>& s, const std::vector<double>& se,
                          double h) {
  CaseResult c;
  c.case_id = id;
  const auto n = static_cast<Eigen::Index>(s.size());
  c.rows_done = static_cast<int>(n);
  c.strain = PathM::Zero(n, 6);
  c.stress_total = PathM::Zero(n, 6);
  c.stress_total_se = PathM::Constant(n, 6, 1.0);
  const int v = pnc::damage::single_driven(pnc::damage::deformation_case(id), "test");
  for (Eigen::Index k = 0; k < n; ++k) {
    c.strain(k, v) = static_cast<double>(k) * h;
    c.stress_total(k, v) = s[static_cast<std::size_t>(k)];
    c.stress_total_se(k, v) = se[static_cast<std::size_t>(k)];
  }
  c.stress_virial = c.stress_total;
  c.stress_virial_se = c.stress_total_se;
  c.stress_total_tau_fs = c.stress_virial_tau_fs = PathM::Constant(n, 6, 1.0);
  c.stress_total_inflated = c.stress_virial_inflated = PathM::Zero(n, 6);
  return c;
}

} // namespace

// Many synthetic replica sets: each replica has its own modulus (structure), its own
// reference error (common to its whole curve) and AR(1) noise correlated along the curve;
// replicas are independent. The nominal 68 % interval slope +- t se must cover the truth.
TEST(RveReplicas, BetweenReplicaErrorOfAFittedSlopeCoversTheTruth) {
  Recipe r;
  r.stress = "total";
  r.reference = "subtract";
  const double E = 1.0e9, h = 0.005, noise = 8e6, ref_noise = 8e6, struct_sd = 0.2e9;
  const int steps = 20, sets = 1500;
  std::mt19937_64 g(2026);
  std::normal_distribution<double> z(0.0, 1.0);
  for (const int nrep : {2, 4}) {
    r.replicas = nrep;
    int covered = 0, covered_naive = 0;
    for (int s = 0; s < sets; ++s) {
      std::vector<std::vector<CaseResult>> results;
      for (int rep = 0; rep < nrep; ++rep) {
        const double Er = E + struct_sd * z(g), s0 = 1e8 + 3e7 * z(g);
        const auto ar = ar1(g, steps, 0.7);
        std::vector<double> y(steps + 1), se(steps + 1, noise);
        y[0] = s0 + ref_noise * z(g);
        for (int k = 1; k <= steps; ++k)
          y[k] = s0 + Er * k * h + noise * ar[k - 1];
        results.push_back({synthetic_case(2, y, se, h)});
      }
      const CombinedCases c = combine_cases(r, results);
      const CombinedCase& cc = c.cases[0];
      EXPECT_EQ(c.error_method, "replicas");
      if (std::fabs(cc.slope - E) <= cc.slope_coverage_factor * cc.slope_se) ++covered;
      if (std::fabs(cc.slope - E) <= cc.slope_se) ++covered_naive;
    }
    const double p = 0.6826894921370859;
    std::cout << "N = " << nrep << " replicas: coverage " << static_cast<double>(covered) / sets
              << " (t factor), " << static_cast<double>(covered_naive) / sets << " (se alone)\n";
    EXPECT_NEAR(static_cast<double>(covered) / sets, p, binomial_band(p, sets)) << nrep;
    // without the Student factor the interval is too short for few replicas: P(|T_1| <= 1)
    // = 0.5, P(|T_3| <= 1) = 0.609
    const double p_naive = nrep == 2 ? 0.5 : 2 * student_t_cdf(1.0, 3) - 1;
    EXPECT_NEAR(static_cast<double>(covered_naive) / sets, p_naive, binomial_band(p_naive, sets))
        << nrep;
  }
}

// One replica: the reference error is common to every point. Its propagation (D131) must
// give the Monte Carlo scatter of the slope; adding it in quadrature to every point as if
// independent (the old way) understates the scatter.
TEST(RveReplicas, ReferenceErrorPropagationMatchesMonteCarlo) {
  Recipe r;
  r.reference = "subtract";
  r.replicas = 1;
  const double E = 1.0e9, h = 0.005, noise = 8e6, ref_se = 8e6;
  const int steps = 20, sets = 4000;
  std::mt19937_64 g(7);
  std::normal_distribution<double> z(0.0, 1.0);
  std::vector<double> slopes;
  double reported = 0, naive = 0;
  for (int s = 0; s < sets; ++s) {
    std::vector<double> y(steps + 1), se(steps + 1, noise);
    y[0] = ref_se * z(g);
    se[0] = ref_se;
    for (int k = 1; k <= steps; ++k)
      y[k] = E * k * h + noise * z(g);
    const CombinedCases c = combine_cases(r, {{synthetic_case(2, y, se, h)}});
    slopes.push_back(c.cases[0].slope);
    reported = c.cases[0].slope_se; // the same in every set (errors given, not estimated)
    // the old way: every point's error sqrt(se^2 + se_ref^2), treated as independent
    const CombinedCase& cc = c.cases[0];
    Eigen::VectorXd t(10), yy(10), ss(10);
    for (int k = 0; k < 10; ++k) {
      t[k] = cc.strain(k, 1);
      yy[k] = cc.stress(k, 1);
      ss[k] = cc.stress_stderr(k, 1);
    }
    naive = slope_through_origin(t, yy, ss, 0.0).se;
  }
  const ReplicaEstimate mc = replica_mean_se(slopes);
  std::cout << "slope scatter: Monte Carlo " << mc.sd << ", propagated " << reported
            << ", independent-quadrature " << naive << " Pa\n";
  const double sd_rel = 1 / std::sqrt(2.0 * (sets - 1)); // relative s.e. of a sample sd
  EXPECT_NEAR(mc.mean, E, 4 * mc.se);
  EXPECT_NEAR(mc.sd / reported, 1.0, 4 * sd_rel);
  // closed form of this design (rows k = 1..10 of 20): se_indep^2 = noise^2 / (h^2 sum k^2),
  // se_common = ref_se sum k / (h sum k^2): sum k = 55, sum k^2 = 385
  const double expect = std::hypot(noise / (h * std::sqrt(385.0)), ref_se * 55 / (h * 385));
  EXPECT_NEAR(reported, expect, 1e-9 * expect);
  EXPECT_LT(naive / mc.sd, 0.6); // the old way: sqrt(2/385)/... ~ 0.5 of the true scatter
}

TEST(RveReplicas, SmoothingNeverShrinksTheErrorsOfTheFitData) {
  Recipe plain, smooth;
  smooth.moving_average = 5;
  std::mt19937_64 g(3);
  std::normal_distribution<double> z(0.0, 1.0);
  std::vector<double> y(21), se(21);
  for (int k = 0; k <= 20; ++k) {
    y[k] = 1e9 * 0.005 * k + 5e6 * z(g);
    se[k] = 5e6 * (1 + 0.1 * k);
  }
  const auto c = synthetic_case(6, y, se, 0.005);
  const CombinedCases a = combine_cases(plain, {{c}}), b = combine_cases(smooth, {{c}});
  // the fit data are the unsmoothed points with their own errors, whatever the recipe asks
  EXPECT_EQ(a.cases[0].stress, b.cases[0].stress);
  EXPECT_EQ(a.cases[0].stress_stderr, b.cases[0].stress_stderr);
  EXPECT_DOUBLE_EQ(a.cases[0].slope_se, b.cases[0].slope_se);
  // the smoothed curve exists for display only
  EXPECT_EQ(a.cases[0].display_moving_average.rows(), 0);
  ASSERT_EQ(b.cases[0].display_moving_average.rows(), 20);
  EXPECT_NEAR(b.cases[0].display_moving_average(2, 5),
              b.cases[0].stress.middleRows(0, 5).col(5).mean(), 1e-6);
  EXPECT_NE(b.stress_definition.find("display only"), std::string::npos);
  // the point error is never below the point's own hold error
  for (Eigen::Index k = 0; k < 20; ++k)
    EXPECT_GE(b.cases[0].stress_stderr(k, 5), se[static_cast<std::size_t>(k + 1)]);
}

TEST(RveReplicas, ReplicaSeedsAndDirectories) {
  EXPECT_EQ(replica_build_seed(7, 1), 7u);
  EXPECT_EQ(replica_case_seed(7, 1, 2), 702u);
  std::set<std::uint64_t> seen;
  for (int rep = 2; rep <= 64; ++rep) {
    const auto s = replica_build_seed(7, rep);
    EXPECT_GE(s, 1u);
    EXPECT_LE(s, 800000000u);
    seen.insert(s);
    for (int id = 1; id <= 6; ++id)
      EXPECT_LE(replica_case_seed(7, rep, id), 800000000u);
  }
  EXPECT_EQ(seen.size(), 63u);
  EXPECT_EQ(replica_dir("/x", 1, 1), "/x");
  EXPECT_EQ(replica_dir("/x", 3, 2), "/x/replica_2");
}

// Two replicas that agree exactly at one strain step: that point's own between-replica
// variance is zero (one degree of freedom), an infinite fit weight. The point error is the
// variance pooled over the curve's rows instead (D130).
TEST(RveReplicas, FewReplicasNeverGiveAPointAZeroError) {
  Recipe r;
  std::vector<double> y1 = {0, 1e6, 2e6, 3e6, 4e6}, y2 = {0, 1e6, 4e6, 3e6, 8e6};
  const std::vector<double> se(5, 1e5);
  const CombinedCases c =
      combine_cases(r, {{synthetic_case(2, y1, se, 0.01)}, {synthetic_case(2, y2, se, 0.01)}});
  const CombinedCase& cc = c.cases[0];
  // rows (k >= 1): differences 0, 2e6, 0, 4e6; variances d^2 / 2 = 0, 2e12, 0, 8e12
  const double pooled = (0 + 2e12 + 0 + 8e12) / 4;
  EXPECT_NEAR(cc.stress_stderr(0, 1), std::sqrt(pooled / 2), 1e-6);
  EXPECT_NEAR(cc.stress_stderr(1, 1), std::sqrt(pooled / 2), 1e-6); // own 2e12 < pooled
  EXPECT_NEAR(cc.stress_stderr(3, 1), std::sqrt(8e12 / 2), 1e-6);   // own above pooled
  EXPECT_NEAR(cc.stress(3, 1), 6e6, 1e-6);
}

TEST(RveReplicas, ErrorsAreRaisedToTheLargerOfTwoAndNeverLowered) {
  // the rule of D130 / D431 on constructed numbers: below the floor -> the floor; above it ->
  // kept; NaN floor (not fitted) -> kept; NaN error with a finite floor -> the floor
  const double nan = std::nan("");
  std::vector<double> err = {1.0, 5.0, 2.0, nan, 3.0};
  const std::vector<double> floor = {2.0, 4.0, nan, 7.0, 3.0};
  std::vector<bool> raised(err.size(), false);
  EXPECT_EQ(pnc::rve::raise_errors(err, floor, &raised), 2);
  EXPECT_EQ(err[0], 2.0);
  EXPECT_EQ(err[1], 5.0);
  EXPECT_EQ(err[2], 2.0);
  EXPECT_EQ(err[3], 7.0);
  EXPECT_EQ(err[4], 3.0); // equal: not raised
  EXPECT_EQ(raised, (std::vector<bool>{true, false, false, true, false}));
}
