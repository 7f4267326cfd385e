#pragma once
// pnc/campaign/campaign.hpp: a long command as a plan of units with dependencies, and each unit's
// state on disk (decisions D240-D242; a library below rve/ and thermo/, D348; docs/cluster.md).
//
// A unit is one piece of work that one process does from the files in the run folder:
// `replica_2/equilibrate`, `replica_2/case_4`, `fit`. Its dependencies (`needs`) are other
// units of the same plan; a unit whose `join` is true runs when its needs have ENDED (done or
// not) and checks them itself (the fit names the units that are missing), any other unit runs
// when its needs are DONE. Units of one `group` are independent of each other and alike (one
// Slurm job array). The plan knows nothing of LAMMPS: `pnc characterize` makes one
// (pnc/rve/characterize.hpp); `pnc thermo ti` makes its own (app/cmd_thermo_ti.cpp).
//
// Files in the run folder DIR:
//   DIR/plan.json                 the plan (written once by the command that made it)
//   DIR/state/<unit id>.json      one state per unit, replaced atomically by whoever changes it
//                                 (the executor: queued; the unit itself: running, done, failed)
// A unit without a state file is pending. Times are UTC seconds since the epoch (`_s` keys).
#include <nlohmann/json.hpp>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pnc::campaign {

struct Unit {
  std::string id;                 ///< [a-z0-9_]+ (/ [a-z0-9_]+)*, e.g. "replica_2/case_4"
  std::string kind;               ///< "equilibrate", "phase_check", "case", "fit", ...
  std::string group;              ///< units of one group are alike and independent (one array)
  std::vector<std::string> needs; ///< ids of units that must end first
  bool join = false;              ///< runs when the needs ended, whatever their outcome
  int ranks = 1;                  ///< MPI ranks of its LAMMPS stages
  std::vector<std::string> inputs, outputs; ///< paths relative to the run folder (documentation)
};

struct Plan {
  std::string command;       ///< the command whose work this is ("characterize")
  nlohmann::json parameters; ///< what run-unit needs besides the recipe (ranks, options)
  std::vector<Unit> units;   ///< in an order where every unit comes after its needs

  const Unit& unit(const std::string& id) const; ///< throws InputError naming plan.json
  bool has(const std::string& id) const;
};

/// Throws InputError (source `source`, field "unit") unless `id` is a valid unit id.
void check_unit_id(const std::string& id, const std::string& source);
/// Checks ids, that every need exists and comes earlier, and that groups are of one kind.
void check_plan(const Plan& p, const std::string& source);

nlohmann::json plan_json(const Plan& p);
Plan plan_from_json(const nlohmann::json& j, const std::string& source);
std::string plan_path(const std::string& dir); ///< DIR/plan.json
void write_plan(const std::string& dir, const Plan& p);
/// Reads DIR/plan.json; throws InputError naming it when absent or malformed.
Plan read_plan(const std::string& dir);

enum class UnitState { pending, queued, running, done, failed };
const char* state_name(UnitState s);

struct UnitStatus {
  UnitState state = UnitState::pending;
  std::string job_id;   ///< Slurm job id ("123" or "123_4" for an array task), "" when local
  std::string host;     ///< where it runs or ran
  long pid = 0;         ///< process id on `host` while running
  std::string message;  ///< why it failed (LAMMPS's own ERROR line when it has one)
  std::string log_path; ///< the log that says more (LAMMPS log or the job's output)
  double queued_s = 0;  ///< UTC epoch seconds when its job was submitted (Slurm)
  double started_s = 0, ended_s = 0;                ///< UTC epoch seconds
  nlohmann::json detail = nlohmann::json::object(); ///< unit-specific numbers (units in keys)
};

nlohmann::json status_json(const UnitStatus& s);
std::string state_path(const std::string& dir, const std::string& id); ///< DIR/state/<id>.json
/// The unit's state; pending when it has no state file. Throws InputError on a malformed one.
UnitStatus read_status(const std::string& dir, const std::string& id);
/// Replaces the unit's state file atomically (creating DIR/state/... as needed).
void write_status(const std::string& dir, const std::string& id, const UnitStatus& s);
/// Deletes the state file (the unit is pending again).
void clear_status(const std::string& dir, const std::string& id);

double epoch_seconds(); ///< now, UTC seconds since the epoch
std::string host_name();

/// What a unit function reports when it fails: the message and the log that says more.
struct UnitFailure : std::runtime_error {
  UnitFailure(const std::string& message, std::string log)
      : std::runtime_error(message), log_path(std::move(log)) {}
  std::string log_path;
};

/// Runs one unit in this process: writes `running` (host, pid, $SLURM_JOB_ID), calls `body`,
/// then `done` with the seconds and `body`'s detail, or `failed` with the message (the log
/// path of a UnitFailure, else `fallback_log`). A stop request (pnc::Interrupted) makes the
/// unit pending again and is rethrown; other exceptions are recorded and rethrown.
void run_unit_recorded(const std::string& dir, const Unit& u,
                       const std::function<nlohmann::json()>& body,
                       const std::string& fallback_log = "");

} // namespace pnc::campaign
