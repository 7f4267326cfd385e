#pragma once
// pnc/campaign/executor.hpp: the local executor of a plan of units (campaign.hpp, decision D241):
// the units that are not done run as child processes of this one, at most `jobs` at a time,
// each as soon as its needs are done (a join unit: as soon as they ended). The Slurm executor
// is in slurm.hpp.
//
// A child runs `unit_main(unit)` (what `pnc run-unit DIR UNIT` runs) and ends with its return
// value; the unit records its own state (run_unit_recorded). A unit whose need failed is not
// run; the others keep going. A stop request (SIGINT/SIGTERM, pnc::process_stop()) starts no
// new unit, lets the running ones stop at their next checkpoint, and throws pnc::Interrupted
// once they have ended. A unit child must not outlive this process (it gets SIGKILL when it
// ends), as the stage children do (runner.hpp).
//
// Each unit that ends prints one progress line of the whole run (core/progress.hpp, D344):
//     pnc characterize: 105/432 units (24.3%), elapsed 31 min, ETA 1 h 36 min; unit
//     replica_12/case_1 done in 33 s
// its ETA from the units' kinds (remaining_seconds; decision D429).
#include "pnc/campaign/campaign.hpp"

#include <functional>
#include <string>
#include <vector>

namespace pnc::campaign {

struct LocalRun {
  std::vector<std::string> ran;     ///< units started by this run, in start order
  std::vector<std::string> failed;  ///< units that ended failed ("id: message (log ...)")
  std::vector<std::string> not_run; ///< units not run because a need failed
  double seconds = 0;               ///< wall time of the run
};

using UnitMain = std::function<int(const Unit&)>;

/// A unit of a run, for the ETA: its kind ("case", "equilibrate", ...) and seconds of wall time
/// (a finished unit: how long it ran; a unit left: how long it has run so far, 0 if waiting).
struct UnitSeconds {
  std::string kind;
  double seconds = 0;
};

/// Wall time left of a run (s; D429): each unit `left` is expected to take the mean of the last
/// (up to) 8 `finished` units of its kind, `finished` in the order they ended (of those of
/// every kind when none of its kind has finished), less what it has run (never below 0), and
/// `jobs` (>= 1) run at a time, so the sum is divided by min(jobs, left.size()). 0 when nothing
/// is left; NaN when no unit has finished yet.
double remaining_seconds(const std::vector<UnitSeconds>& finished,
                         const std::vector<UnitSeconds>& left, int jobs);

/// Runs every unit of `p` that is not done (per its state file in `dir`), as above.
LocalRun run_local(const std::string& dir, const Plan& p, int jobs, const UnitMain& unit_main);

} // namespace pnc::campaign
