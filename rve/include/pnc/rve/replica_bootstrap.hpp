#pragma once
// pnc/rve/replica_bootstrap.hpp: the calibration check of the card's error bars by a bootstrap
// of the joint fit over replicas (decision D431).
//
// Units: constants and their spreads in Pa (alpha dimensionless), as damage::fit_ndm returns
// them; ratios dimensionless.
//
// The card's standard error of a constant is the larger of the joint fit's own and the
// between-replica one of the replicas' separate fits (D130). Neither is the spread of the
// joint fit itself over independent runs. The bootstrap measures that spread from one run:
// draw N of the run's N replicas with replacement, combine them as combine_cases does (mean and
// sd/sqrt(N) per point, D130), refit jointly with the card's options, repeat. The standard
// deviation of a constant over the resamples, scaled by sqrt(N/(N-1)) (the bootstrap's spread
// of a mean is low by sqrt((N-1)/N)), over the card's error, is the check's ratio:
// near 1 or below, the card's error covers the joint fit's sampling spread; above 1 it would
// be too small, and the card's error is raised to it (apply_bootstrap).
#include "pnc/damage/fit.hpp"
#include "pnc/rve/replicas.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace pnc::rve {

/// Fewest replicas the bootstrap runs with: with N replicas there are C(2N-1, N) distinct
/// resamples (35 for N = 4) and the bootstrap's spread is biased by sqrt((N-1)/N); from 8 on
/// both are small (6435 resamples, bias 6 %).
inline constexpr int kBootstrapMinReplicas = 8;

struct ReplicaBootstrap {
  bool applicable = false;
  std::string why_not;            ///< when not applicable, in words
  int replicas = 0;               ///< N of the run
  int resamples = 0;              ///< refits that worked
  int failed = 0;                 ///< refits that threw an InputError (left out)
  std::uint64_t seed = 0;         ///< of the resampling (the same seed gives the same draws)
  std::vector<std::string> names; ///< constant names (damage::constant_names)
  std::vector<double> value;      ///< per constant: the joint fit's value (Pa; alpha 1)
  std::vector<double> card_error; ///< per constant: the card's error before the check
  std::vector<double> spread;     ///< per constant: sd over the resamples x sqrt(N/(N-1))
                                  ///< (Pa; alpha 1)
  std::vector<double> ratio;      ///< spread / card_error; NaN where not fitted
  std::vector<bool> raised;       ///< per constant: the card's error was raised to spread

  /// Whether the run's report, JSON and summary show the check at all (>= 2 replicas; with one
  /// there is nothing to resample and nothing to say).
  bool shown() const { return replicas >= 2; }
  /// Sampling error of ratio[i] from the finite number of resamples B: ratio / sqrt(2(B-1)).
  double ratio_stderr(std::size_t i) const;
};

/// The joint-fit data of the replicas `pick` (indices into c's replicas, repeats allowed):
/// per case and point the mean and sd/sqrt(N) as combine_cases stores them (D130). Pa.
damage::StressStrainData replica_mean_data(const CombinedCases& c, const std::vector<int>& pick);

/// Bootstraps the joint fit over the replicas of `c`: `resamples` draws of c.replicas replicas
/// with replacement (std::mt19937_64 seeded with `seed`), each combined per point as mean and
/// sd/sqrt(N) (D130) and fitted with `options` (the card's). `joint` is the card's fit and
/// `card_error` its standard errors per constant (after D130). Not applicable (why_not says
/// why) with fewer than kBootstrapMinReplicas replicas, resamples < 20, or no fitted constant.
ReplicaBootstrap bootstrap_joint_fit(const CombinedCases& c, const damage::FitOptions& options,
                                     const damage::FitReport& joint,
                                     const std::vector<double>& card_error, int resamples,
                                     std::uint64_t seed);

/// Raises every fitted constant's `std_error` below the bootstrap spread to that spread (never
/// lowers one: a ratio below 1 is reported, not used; rve::raise_errors) and marks it in
/// b.raised. Returns how many were raised.
int apply_bootstrap(ReplicaBootstrap& b, std::vector<double>& std_error);

/// Markdown section for report.md: per constant the card's error, the bootstrap spread, their
/// ratio with its sampling error, and whether the error was raised; or why the check did not run.
/// Empty when !b.shown() (as are the summary line and, null, the JSON).
std::string replica_bootstrap_markdown(const ReplicaBootstrap& b);
/// One line for the run's summary on stderr: the range of the ratios and which errors were
/// raised, or why the check did not run.
std::string replica_bootstrap_summary(const ReplicaBootstrap& b);
/// The same as JSON (keys state units: _Pa; alpha's spread in "1").
nlohmann::json replica_bootstrap_json(const ReplicaBootstrap& b);

} // namespace pnc::rve
