// Block statistics of MD time series (md/statistics.hpp; decisions D130-D134), on synthetic
// data only: the autocorrelation time of AR(1) series against its closed form, the block-length
// check, the Student factor and the between-replica standard error, block means by hand.
#include "common/synthetic_series.hpp"
#include "pnc/md/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace pnc::md;

using pnc::test::ar1;
using pnc::test::ar1_var_mean;
using pnc::test::binomial_band;

TEST(MdStatistics, AutocorrelationTimeOfAr1MatchesClosedForm) {
  std::mt19937_64 g(11);
  for (const double phi : {0.0, 0.5, 0.9}) {
    const std::size_t n = 200000;
    const AutocorrelationTime a = integrated_autocorrelation_time(ar1(g, n, phi));
    const double tau = 0.5 * (1 + phi) / (1 - phi); // 1/2 + sum phi^t
    // Sokal: var(tau_hat) ~ 2 (2W + 1) / n tau^2; window truncation bias phi^(W+1)/(1-phi)
    const double rel_sd = std::sqrt(2.0 * (2 * a.window + 1) / n);
    const double trunc = std::pow(phi, a.window + 1) / (1 - phi);
    EXPECT_TRUE(a.resolved);
    EXPECT_NEAR(a.tau_int, tau, 4 * rel_sd * tau + trunc) << "phi " << phi;
  }
}

TEST(MdStatistics, ShortBlocksAreFlaggedAndTheirErrorInflatedLongBlocksKept) {
  // phi = 0.95: statistical inefficiency g = 39 samples, tau_int = 19.5. 100 blocks of 50
  // samples (< 5 g) are too short; 10 blocks of 500 samples are long enough.
  const double phi = 0.95, g_ineff = (1 + phi) / (1 - phi), tau = 0.5 * g_ineff;
  const std::size_t n = 5000;
  const double var_true = ar1_var_mean(n, phi);
  std::mt19937_64 g(5);
  const int reps = 400;
  for (const int blocks : {100, 10}) {
    const std::size_t b = n / blocks;
    // E[se_block^2] = (Var(block mean) - Var(mean)) / (blocks - 1), exact for AR(1)
    const double e_block = (ar1_var_mean(b, phi) - var_true) / (blocks - 1);
    std::vector<double> sb, su;
    int flagged = 0;
    for (int i = 0; i < reps; ++i) {
      const HoldEstimate h = checked_block_se(ar1(g, n, phi), blocks);
      sb.push_back(h.se_block * h.se_block);
      su.push_back(h.se * h.se);
      flagged += h.blocks_ok ? 0 : 1;
    }
    const ReplicaEstimate mb = replica_mean_se(sb), mu = replica_mean_se(su);
    std::cout << blocks << " blocks: E[se_block^2]/Var = " << mb.mean / var_true
              << ", E[se_used^2]/Var = " << mu.mean / var_true << ", flagged " << flagged << "/"
              << reps << "\n";
    // the block estimator itself is what the exact expectation says (Monte Carlo error)
    EXPECT_NEAR(mb.mean, e_block, 4 * mb.se) << blocks;
    if (static_cast<double>(b) < kMinBlockOverInefficiency * g_ineff) {
      EXPECT_GT(flagged, reps * 95 / 100) << blocks;
      // the bias the check guards against: short blocks understate the variance
      EXPECT_LT(e_block / var_true, 0.75);
      // inflated to sqrt(g var / n): low only by the windowed estimator's mean-subtraction
      // bias, (2W + 1) / n to first order with W ~ 6 tau (taken twice for higher orders)
      const double bias = 2.0 * (2 * 6 * tau + 1) / static_cast<double>(n);
      EXPECT_GT(mu.mean / var_true, 1 - bias - 4 * mu.se / var_true);
      EXPECT_LT(mu.mean / var_true, 1 + 4 * mu.se / var_true);
    } else {
      EXPECT_LT(flagged, reps * 5 / 100) << blocks;
      EXPECT_GT(e_block / var_true, 0.9); // long blocks: the block error is nearly unbiased
    }
  }
}

TEST(MdStatistics, StudentFactorAndReplicaStandardError) {
  // closed form for 3 dof: P(|T| <= k) = (2/pi) (atan x + x / (1 + x^2)), x = k / sqrt(3)
  const double x = coverage_factor(3) / std::sqrt(3.0);
  EXPECT_NEAR(2 / M_PI * (std::atan(x) + x / (1 + x * x)), 0.6826894921370859, 1e-9);
  EXPECT_NEAR(student_t_cdf(-coverage_factor(3), 3), 0.5 - 0.5 * 0.6826894921370859, 1e-9);
  // large dof -> the normal's 1
  EXPECT_NEAR(coverage_factor(1), std::tan(M_PI * 0.6826894921370859 / 2), 1e-6); // Cauchy
  EXPECT_NEAR(coverage_factor(1000), 1.0, 2e-3);
  const ReplicaEstimate e = replica_mean_se({1.0, 2.0, 3.0, 6.0});
  EXPECT_DOUBLE_EQ(e.mean, 3.0);
  EXPECT_NEAR(e.se, std::sqrt((4 + 1 + 0 + 9) / 3.0) / 2.0, 1e-14);
  EXPECT_TRUE(std::isnan(replica_mean_se({1.0}).se));
}

TEST(MdStatistics, BlockMeanAndErrorByHand) {
  const auto [mean, se] = block_mean_se({1, 1, 3, 3}, 2);
  EXPECT_DOUBLE_EQ(mean, 2.0);
  EXPECT_DOUBLE_EQ(se, 1.0); // block means 1, 3: sd = sqrt(2), / sqrt(2)
  EXPECT_TRUE(std::isnan(block_mean_se({1, 2, 3}, 1).second)); // one block: no error
  // the trailing sample enters the mean, not the blocks: blocks {1,1}, {3,3}, mean 12/5
  const auto [m5, se5] = block_mean_se({1, 1, 3, 3, 4}, 2);
  EXPECT_DOUBLE_EQ(m5, 12.0 / 5.0);
  EXPECT_DOUBLE_EQ(se5, 1.0);
}
