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

/// Runs every unit of `p` that is not done (per its state file in `dir`), as above.
LocalRun run_local(const std::string& dir, const Plan& p, int jobs, const UnitMain& unit_main);

} // namespace pnc::campaign
