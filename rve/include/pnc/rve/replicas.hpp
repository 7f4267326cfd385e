#pragma once
// pnc/rve/replicas.hpp: independent replicas of a `pnc characterize` run and the honest
// combination of their case curves into cases.h5 (docs/rve.md "Statistics: replicas, errors,
// reference state", docs/formats.md, decisions D130-D134).
//
// Units: stresses in Pa (tension positive), strains dimensionless (engineering shear), as in
// CaseResult and cases.h5.
//
// A replica is a structure of its own: its own build seed, its own equilibration, then every
// case of the recipe (D130). Per replica and case, the fit rows are sigma(eps_k) - sigma_ref
// for k >= 1, with sigma_ref the mean of the zero-strain holds (row 0, reference_holds x
// hold_steps long) of all cases of that replica (D131). Then:
//   * 1 replica: the point error is sqrt(se_k^2 + se_ref^2) (blocks, checked against the
//     autocorrelation time, D132); se_ref, common to every point of the replica, is stored
//     apart as reference_stderr;
//   * N >= 2 replicas: mean over replicas, point error sd/sqrt(N) over replicas.
// A moving average (analysis.moving_average > 1) is stored for display only (D133).
#include "pnc/md/statistics.hpp"
#include "pnc/rve/deform.hpp"
#include "pnc/rve/recipe.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace pnc::rve {

using PathM = Eigen::Matrix<double, Eigen::Dynamic, 6>;

/// Build (and equilibration) seed of replica `replica` (1-based): replica 1 keeps the recipe's
/// seed, so a one-replica run is the run of before; others are hashed into 1..800000000.
std::uint64_t replica_build_seed(std::uint64_t seed, int replica);
/// Case seed: replica 1 keeps seed * 100 + case_id; others hashed into 1..800000000.
std::uint64_t replica_case_seed(std::uint64_t seed, int replica, int case_id);
/// Directory of replica `replica` of a run in `dir`: `dir` itself when replicas == 1 (the
/// single-replica layout), `dir`/replica_<r> otherwise.
std::string replica_dir(const std::string& dir, int replicas, int replica);

struct CombinedCase {
  int id = 0;
  int voigt = 0;                       ///< driven component (0..5)
  PathM strain;                        ///< fit rows
  PathM stress, stress_stderr;         ///< Pa: mean over replicas and its (marginal) standard error
  Eigen::RowVectorXd reference_stderr; ///< Pa, the part common to every point (1 x 6)
  PathM display_moving_average;        ///< Pa, display only; 0 rows when moving_average == 1
  std::vector<PathM> replica_stress, replica_stderr; ///< per replica, fit rows
  /// Linear-range slope of the driven component through the origin (rows with strain <= half
  /// the largest), with its honest error (D131 propagation for one replica, between-replica
  /// standard error for N >= 2, where the nominal 68 % interval is slope +- factor * se).
  double slope = 0, slope_se = 0, slope_coverage_factor = 1;
  std::vector<double> replica_slopes;
};

struct CombinedCases {
  std::vector<CombinedCase> cases; ///< sorted by id
  int replicas = 1;
  std::string error_method;                  ///< "replicas" (N >= 2) or "blocks"
  std::string stress_definition;             ///< what cases.h5 holds, in words
  int holds_checked = 0, holds_inflated = 0; ///< driven component, every replica and row
  std::vector<Eigen::RowVectorXd> reference, reference_se; ///< per replica, Pa (1 x 6)
  /// The case with this id, or nullptr.
  const CombinedCase* find(int id) const;
};

/// Mean over the replicas `pick` (indices into cc.replica_stress, repeats allowed; N =
/// pick.size() >= 2) and its between-replica standard error sd/sqrt(N) per point, with the
/// pooled floor of D130 below kPointVarianceReplicas (8) replicas: what combine_cases stores,
/// and what the bootstrap of D431 recomputes for each resample. Pa.
void replica_mean_curve(const CombinedCase& cc, const std::vector<int>& pick, PathM& mean,
                        PathM& stderr_out);

/// Combines `results[replica][case]` (cases in the same order in every replica). Throws
/// pnc::InputError when a case has no strain step or replicas disagree in their strains.
CombinedCases combine_cases(const Recipe& r, const std::vector<std::vector<CaseResult>>& results);

/// Writes cases.h5 (atomically): the fit data under /case_<n> (read by
/// damage::read_stress_strain_h5), the per-replica raw and fit-row curves under
/// /replicas/replica_<r>/, and the error model in root attributes (docs/formats.md).
void write_combined_cases_h5(const std::string& path, const Recipe& r, const CombinedCases& c,
                             const std::vector<std::vector<CaseResult>>& results);

/// Markdown paragraph for report.md: error method, replicas, block check, slopes.
std::string statistics_markdown(const CombinedCases& c);
/// The same as JSON for `pnc characterize --json` (keys state units: _Pa).
nlohmann::json statistics_json(const CombinedCases& c);

} // namespace pnc::rve
