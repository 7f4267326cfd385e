#pragma once
// pnc/rve/sense_pairs.hpp: a shear and its negative sense in one run, side by side (decision
// D428). When a run holds a shear case and the registry row that shears the same plane the
// other way (cases 4 and 7, 5 and 8, 6 and 9; D424), each replica answers both senses with one
// structure. The fit treats the two as the same experiment (the law is odd along a shear of its
// frame, docs/theory.md section 2.1); this compares them, along the case (stress times the
// case's sense, so both are positive in a solid), per replica and row, so that a user sees
// whether the material answers both senses alike.
//
// Units: the load t is dimensionless (the engineering shear |gamma| of both cases); stresses
// and their differences in Pa.
#include "pnc/rve/replicas.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pnc::rve {

struct SensePair {
  int positive_id = 0, negative_id = 0; ///< registry ids (e.g. 6 and 9)
  int voigt = 0;                        ///< the sheared component (3..5)
  int replicas = 0;
  std::vector<double> t; ///< load of each compared row (dimensionless), the fitted rows
  /// mean over replicas of the driven stress along each case (Pa) and its standard error (Pa):
  /// between replicas with >= 2, else the hold's own block error
  std::vector<double> positive, positive_se, negative, negative_se;
  /// per row, positive minus negative along the case, paired by replica (one structure
  /// sheared both ways): the mean over replicas and its standard error (Pa; NaN < 2 replicas)
  std::vector<double> difference, difference_se;
  /// each replica's difference averaged over the compared rows (one independent sample per
  /// replica, the rows of one replica being correlated): mean, standard error (Pa) and the
  /// two-sided p of Student's t on replicas - 1 dof (NaN with < 2 replicas)
  double mean_difference = 0, mean_difference_se = 0, p = 0;
  /// the larger of the two senses' mean stress at the last compared row (Pa): the scale the
  /// difference is read against
  double scale = 0;
};

/// Every pair of cases of `c` whose registry rows shear one plane in opposite senses, over the
/// rows the fit used (damage::rows_in_fit_range with `strain_max`, `stretch_max`; 0 = no
/// bound), in the order of the positive case's id. A pair whose two cases were not run to the
/// same loads (other amplitude or steps) is left out: it cannot be compared row by row.
std::vector<SensePair> sense_pairs(const CombinedCases& c, double strain_max, double stretch_max);

/// Markdown section of report.md: per pair the replicas, the mean difference over the rows and
/// at the last row, each against the stress, and p; empty when the run has no pair.
std::string sense_pairs_markdown(const std::vector<SensePair>& pairs);

/// The same for `pnc characterize --json` (statistics.sense_pairs): per pair "cases" [positive,
/// negative], "shear" ("1-2"), "replicas", "rows", "mean_difference_Pa",
/// "mean_difference_stderr_Pa", "p", "last_load" (dimensionless), "last_difference_Pa",
/// "last_difference_stderr_Pa", "stress_scale_Pa"; an error or p that does not exist (one
/// replica) is null.
nlohmann::json sense_pairs_json(const std::vector<SensePair>& pairs);

/// One line per pair for the summary `pnc characterize` prints on stderr: the shear, its cases,
/// the replicas, the mean difference over the fitted rows (MPa, with its standard error), its
/// share of the stress and p ("not judged" with one replica); empty when the run has no pair.
std::string sense_pairs_summary(const std::vector<SensePair>& pairs);

} // namespace pnc::rve
