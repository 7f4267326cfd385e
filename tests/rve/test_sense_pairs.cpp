// A shear and its negative sense side by side (pnc/rve/sense_pairs.hpp, decision D428), on
// replica curves made here: the comparison is paired by replica and read along each case.
#include "pnc/damage/cases.hpp"
#include "pnc/md/statistics.hpp"
#include "pnc/rve/sense_pairs.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace pnc;

namespace {

// Case `id` of `nrep` replicas, rows gamma = 0.01 .. 0.05 (t = 0.01 k): replica r's driven
// stress along the case is G t + `offset`[r] + `bias` t / 0.05 (Pa); the other components zero.
rve::CombinedCase shear_case(int id, int nrep, const std::vector<double>& offset, double bias) {
  const damage::DeformationCase& row = damage::deformation_case(id);
  const double sense = damage::driven_sense(row);
  rve::CombinedCase c;
  c.id = id;
  c.voigt = row.driven[0];
  const int n = 5;
  c.strain = rve::PathM::Zero(n, 6);
  c.stress = rve::PathM::Zero(n, 6);
  c.stress_stderr = rve::PathM::Constant(n, 6, 1e5);
  for (int k = 0; k < n; ++k)
    c.strain.row(k) = damage::case_strain(id, 0.01 * (k + 1)).transpose();
  for (int r = 0; r < nrep; ++r) {
    rve::PathM y = rve::PathM::Zero(n, 6);
    for (int k = 0; k < n; ++k) {
      const double t = 0.01 * (k + 1);
      y(k, c.voigt) = sense * (0.5e9 * t + offset[static_cast<std::size_t>(r)] + bias * t / 0.05);
    }
    c.replica_stress.push_back(y);
    c.replica_stderr.push_back(rve::PathM::Constant(n, 6, 1e5));
    c.stress += y / nrep;
  }
  return c;
}

} // namespace

// Case 9 equal to case 6 along the case but for a known bias: the paired difference is exactly
// the bias at every row, whatever each replica's own offset (common to both senses of one
// structure); its mean over the rows is the bias's mean; with a bias of zero nothing is found.
TEST(SensePairs, ThePairedDifferenceIsTheSenseBiasWhateverEachReplicasOffset) {
  const int nrep = 6;
  std::vector<double> offset;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0, 3e6); // replica offsets of 3 MPa
  for (int r = 0; r < nrep; ++r)
    offset.push_back(g(rng));
  rve::CombinedCases c;
  c.replicas = nrep;
  c.cases = {shear_case(4, nrep, offset, 0), shear_case(6, nrep, offset, 0),
             shear_case(9, nrep, offset, -2e6)}; // case 4 has no negative partner in the run
  const auto pairs = rve::sense_pairs(c, 0, 0);
  ASSERT_EQ(pairs.size(), 1u);
  const rve::SensePair& s = pairs[0];
  EXPECT_EQ(s.positive_id, 6);
  EXPECT_EQ(s.negative_id, 9);
  EXPECT_EQ(s.voigt, 5);
  ASSERT_EQ(s.t.size(), 5u);
  for (std::size_t k = 0; k < s.t.size(); ++k) {
    const double t = 0.01 * static_cast<double>(k + 1);
    EXPECT_DOUBLE_EQ(s.t[k], t);
    EXPECT_GT(s.negative[k], 0.0) << "along the case: positive in both senses";
    // positive minus negative sense: 0 - (-2 MPa t / 0.05), the offsets cancel in each pair
    EXPECT_NEAR(s.difference[k], 2e6 * t / 0.05, 1e-6);
    EXPECT_NEAR(s.difference_se[k], 0.0, 1e-6);
  }
  EXPECT_NEAR(s.mean_difference, 2e6 * 0.6, 1e-6); // the mean of t / 0.05 over the rows: 0.6
  EXPECT_LT(s.p, 1e-6);
  EXPECT_NE(rve::sense_pairs_markdown(pairs).find("| 1-2 | 6, 9 | 6 |"), std::string::npos)
      << rve::sense_pairs_markdown(pairs);
  // the line of the stderr summary: the pair, its replicas and the injected mean bias in MPa
  const std::string line = rve::sense_pairs_summary(pairs);
  for (const char* want :
       {"shear 1-2 both ways (cases 6, 9; 6 replicas)", "+1.20 ± 0.00 MPa", "p = "})
    EXPECT_NE(line.find(want), std::string::npos) << want << " not in: " << line;
  EXPECT_EQ(std::count(line.begin(), line.end(), '\n'), 1) << "one line per pair";
  EXPECT_EQ(rve::sense_pairs_summary({}), "");

  // no bias: every difference zero; a fit range of gamma <= 0.03 compares three rows
  c.cases[2] = shear_case(9, nrep, offset, 0);
  const auto none = rve::sense_pairs(c, 0.03, 0);
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0].t.size(), 3u);
  EXPECT_NEAR(none[0].mean_difference, 0.0, 1e-6);
}

// Independent noise per curve: the paired test keeps its level. 400 runs of 8 replicas without
// a bias: p < 0.05 in 5 % of them (binomial sd 1.1 %; the band 1.5-9.5 % is 4 sd), and the
// standard error of the mean difference covers the truth (0) at the 68.3 % of t on 7 dof
// scaled by its factor.
TEST(SensePairs, WithoutABiasThePairedTestKeepsItsLevel) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0, 1);
  const int nrep = 8, runs = 400;
  int alarms = 0, covered = 0;
  const double k = md::coverage_factor(nrep - 1);
  for (int i = 0; i < runs; ++i) {
    std::vector<double> offset(nrep);
    for (double& o : offset)
      o = 3e6 * g(rng);
    rve::CombinedCases c;
    c.replicas = nrep;
    c.cases = {shear_case(5, nrep, offset, 0), shear_case(8, nrep, offset, 0)};
    for (auto* cc : {&c.cases[0], &c.cases[1]}) // independent 1 MPa noise on every point
      for (auto& y : cc->replica_stress)
        for (int row = 0; row < y.rows(); ++row)
          y(row, 4) += 1e6 * g(rng);
    const auto s = rve::sense_pairs(c, 0, 0);
    ASSERT_EQ(s.size(), 1u);
    alarms += s[0].p < 0.05;
    covered += std::fabs(s[0].mean_difference) <= k * s[0].mean_difference_se;
  }
  EXPECT_GE(alarms, runs * 15 / 1000);
  EXPECT_LE(alarms, runs * 95 / 1000);
  // 68.3 % +- 4 binomial sd (2.3 %)
  EXPECT_GE(covered, runs * 590 / 1000);
  EXPECT_LE(covered, runs * 776 / 1000);
}

// Cases run to other loads are not compared row by row.
TEST(SensePairs, CasesRunToOtherLoadsAreNotPaired) {
  const std::vector<double> offset(3, 0.0);
  rve::CombinedCases c;
  c.replicas = 3;
  c.cases = {shear_case(6, 3, offset, 0), shear_case(9, 3, offset, 0)};
  c.cases[1].strain *= 2; // the negative sense sheared twice as far per row
  EXPECT_TRUE(rve::sense_pairs(c, 0, 0).empty());
}
