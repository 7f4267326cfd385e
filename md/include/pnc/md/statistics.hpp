#pragma once
// pnc/md/statistics.hpp: error estimates of the deformation data that do not lie
// (docs/rve.md "Statistics: replicas, errors, reference state", decisions D130-D134).
//
// Pure numerics, no LAMMPS: every function works on plain numbers and keeps the units of its
// input (stresses in Pa where the pipeline calls them, times in samples unless stated).
//
//   * integrated_autocorrelation_time: tau_int = 1/2 + sum_{t>=1} rho(t) of a time series, in
//     samples (independent samples: 1/2), with Sokal's self-consistent window; the statistical
//     inefficiency is g = 2 tau_int (var(mean) = g var(x) / n).
//   * checked_block_se: the block-averaged standard error of a hold, used only when the blocks
//     are at least kMinBlockOverInefficiency statistical inefficiencies long; otherwise the
//     error is inflated to sqrt(g var / n) and flagged (decision D132).
//   * replica_mean_se / coverage_factor: between-replica mean and standard error sd/sqrt(N),
//     and the Student-t factor that makes mean +- factor * se a 68.27 % interval (D130).
//   * slope_through_origin: weighted slope of y = b t with independent per-point errors plus a
//     common error shared by every point (the reference stress subtracted from the whole
//     curve), propagated exactly (D131).
#include <Eigen/Dense>

#include <utility>
#include <vector>

namespace pnc::md {

struct AutocorrelationTime {
  double tau_int = 0.5; ///< samples; 1/2 for independent samples
  int window = 0;       ///< lags summed
  bool resolved = true; ///< false: the window reached n/4 before it was self-consistent
};

/// Integrated autocorrelation time of `x` (n >= 2 samples) with the window W the smallest lag
/// with W >= c tau_int(W) (Sokal; c = 6). Constant series: tau_int = 1/2.
AutocorrelationTime integrated_autocorrelation_time(const std::vector<double>& x, double c = 6.0);

/// Blocks shorter than this many statistical inefficiencies g = 2 tau_int give a block
/// standard error that is biased low (AR(1): variance low by about g / (2 b)); decision D132.
inline constexpr double kMinBlockOverInefficiency = 5.0;

struct HoldEstimate {
  double mean = 0;       ///< mean of all samples
  double se = 0;         ///< the standard error to use (block s.e., inflated when flagged)
  double se_block = 0;   ///< sd(block means) / sqrt(blocks)
  double se_tau = 0;     ///< sqrt(g var(x) / n) from the autocorrelation time
  double tau_int = 0.5;  ///< samples
  bool blocks_ok = true; ///< blocks >= kMinBlockOverInefficiency * g samples and tau resolved
};

/// Mean and block-averaged standard error sd(block means)/sqrt(blocks) of a series (`blocks`
/// contiguous blocks, trailing remainder samples only in the mean); se NaN for fewer than 2
/// blocks. Units of `x`.
std::pair<double, double> block_mean_se(const std::vector<double>& x, int blocks);

/// Mean and checked standard error of one hold's samples (`blocks` >= 2 contiguous blocks).
/// When the blocks are too short or tau is not resolved, se = max(se_block, se_tau) and
/// blocks_ok = false.
HoldEstimate checked_block_se(const std::vector<double>& x, int blocks);

struct ReplicaEstimate {
  double mean = 0;
  double sd = 0; ///< sample standard deviation over replicas (n - 1); NaN for n < 2
  double se = 0; ///< sd / sqrt(n); NaN for n < 2
  int n = 0;
};
ReplicaEstimate replica_mean_se(const std::vector<double>& values);

/// Student-t distribution function P(T <= t) with `dof` >= 1 degrees of freedom.
double student_t_cdf(double t, int dof);
/// Factor k with P(|T_dof| <= k) = coverage (default 0.6827, one normal sigma): mean +- k se
/// is the nominal interval of N = dof + 1 replicas. Tends to 1 for many replicas.
double coverage_factor(int dof, double coverage = 0.6826894921370859);

struct SlopeFit {
  double slope = 0;
  double se = 0;             ///< total: sqrt(se_independent^2 + se_common^2)
  double se_independent = 0; ///< from the per-point errors
  double se_common = 0;      ///< from the common error shared by every point
};
/// y_k = b t_k fitted with weights 1 / se_k^2 (se_k > 0; all 1 when `se` is empty). The common
/// error `se_common` (e.g. of the subtracted reference) shifts every y_k by the same amount,
/// so it enters as (sum w t / sum w t^2) se_common, not divided among the points.
SlopeFit slope_through_origin(const Eigen::VectorXd& t, const Eigen::VectorXd& y,
                              const Eigen::VectorXd& se, double se_common);

} // namespace pnc::md
