#pragma once
// The driver side of a plan of units (pnc/campaign/campaign.hpp) that every planned command shares:
// `pnc characterize` and `pnc thermo ti` (app/cmd_campaign.cpp; docs/cluster.md, decisions
// D240-D246 and D285-D289). A command makes its plan, registers how one of its units runs
// (`pnc run-unit DIR UNIT` dispatches by plan.command), and hands the plan to the local or the
// Slurm executor; its last unit (the fit, the TI analysis) is a join unit that names what is
// missing.
#include "pnc/campaign/campaign.hpp"
#include "pnc/campaign/slurm.hpp"
#include "stopped_report.hpp"

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace pnc::app {

/// Runs unit `u` of the plan in run folder `dir` in this process and records its state
/// (campaign::run_unit_recorded); returns the process exit code. Errors are printed when
/// `print_errors` (a Slurm job's output); a local child leaves that to the executor.
using PlanUnitRunner = std::function<int(const std::string& dir, const campaign::Plan& p,
                                         const campaign::Unit& u, bool print_errors)>;
/// `pnc run-unit` runs the units of plans whose command is `command` with `runner`.
void register_plan_command(const std::string& command, PlanUnitRunner runner);

/// `body` with the exit codes of a unit: its return value; 128 + N when stopped by signal N
/// (the unit is pending again); 1 on bad input or a failed LAMMPS stage; 2 internal error.
int guarded_unit(const campaign::Unit& u, bool print_errors, const std::function<int()>& body);

/// The Slurm options of a planned command (--partition, --account, --time, --sbatch-template,
/// --mpi, --job-name, --wait); empty strings keep the recipe's or the cluster's defaults.
struct SlurmOptions {
  std::string partition, account, time, sbatch_template, job_name;
  std::string mpi; ///< srun's MPI plugin of K > 1 rank units (D332); "" the file's, else pmix
  bool wait = false;
};
/// Adds those options to `cmd`; `file` (e.g. "the recipe", "the input file"; "" none): an
/// option not given comes from that file's "slurm" section first (pnc characterize, pnc thermo
/// ti --input; D301).
void add_slurm_options(CLI::App* cmd, SlurmOptions& o, const std::string& file);

/// MPI ranks per LAMMPS stage and units at a time of a planned command (pnc characterize, pnc
/// thermo ti; D333). Started as `mpirun -np K pnc ...`, rank 0 is the supervisor and runs every
/// stage on K ranks (a fresh mpirun per stage, so a LAMMPS error still ends only that stage);
/// ranks 1..K-1 leave at once, freeing their cores: returns false on those follower ranks.
/// `cli_ranks`, `cli_jobs`: the values set explicitly (0: not set); unset, `ranks` is K (1
/// without mpirun) and `jobs` 1 under mpirun, else `default_jobs`. Prints one line under mpirun
/// and a warning on stderr when ranks x jobs exceeds the machine's cores.
bool plan_parallelism(int cli_ranks, int cli_jobs, int default_jobs, int& ranks, int& jobs);

/// What the driver of a planned command knows about its run.
struct PlanDriver {
  std::string command;    ///< "characterize", "thermo ti" (messages, --json)
  std::string dir;        ///< the run folder
  std::string final_unit; ///< the join unit whose end ends the run ("fit", "analysis")
  bool json = false;      ///< --json: the submission as JSON when not waiting
};

/// Throws the failure of a run whose final unit is not done: the recorded LAMMPS or
/// simulation error of a failed unit (exit code 7 or 6, docs/errors.md), else an InputError
/// naming the first failed unit and the count; either way the user is told to --resume.
void throw_unless_final_done(const PlanDriver& d, const campaign::Plan& p,
                             const std::vector<std::string>& failed,
                             const std::vector<std::string>& not_run);

/// Runs `body` (the local executor and the conclusion of a planned command). When it throws
/// because the run stopped early (a signal, a failed unit), the run folder still gets
/// report.html / report.md saying so first (stopped_report.hpp: why, how many units are done,
/// which are not, the finished units' outputs, the resume command); the error then goes on to
/// main() as before. `title`: the report's title.
int run_local_reported(const PlanDriver& d, const campaign::Plan& p, const std::string& title,
                       const std::function<int()>& body);

/// The state of every unit of a plan, by unit id.
using UnitStates = std::map<std::string, campaign::UnitStatus>;
/// The states as recorded in DIR/state (the local executor's view).
UnitStates recorded_states(const std::string& dir, const campaign::Plan& p);
/// The states as Slurm sees them (campaign::effective_status: a queued or running unit whose job
/// left the queue failed); `have_queue` false (and one warning line) when squeue cannot answer,
/// then the states as recorded.
UnitStates slurm_states(const std::string& dir, const campaign::Plan& p, bool& have_queue);
/// The title of a plan's report: "pnc characterize: RECIPE-NAME", else "pnc COMMAND: DIR".
std::string plan_report_title(const std::string& dir, const campaign::Plan& p);

/// The short report of a planned run that stopped early (stopped_report.hpp) in `d.dir`: the
/// units done (their outputs), failed and not finished (a Slurm unit with its job id and
/// message); `stop` gives the reason, the resume command and the tone. Prints one line naming
/// the page; returns its path, or "" when it could not be written (one warning line).
std::string write_plan_stopped_report(const PlanDriver& d, const campaign::Plan& p,
                                      const UnitStates& states, const std::string& title,
                                      RunStop stop);
/// The same with the recorded states, `reason`, `failure` and this command with --resume.
std::string write_plan_stopped_report(const PlanDriver& d, const campaign::Plan& p,
                                      const std::string& title, const std::string& reason,
                                      bool failure);
/// `pnc status DIR` of a Slurm plan (decision D300): when `final_unit` is not done and no unit
/// is queued or running any more, writes the stopped report in `dir` (the reason: the first
/// failed unit; the resume command: the plan's recorded command line with --resume) and
/// returns its path; else "" and nothing is written.
std::string ended_slurm_plan_report(const std::string& dir, const campaign::Plan& p,
                                    const UnitStates& states, const std::string& final_unit);

/// Ctrl-C or SIGTERM (`sig`) while `--wait` follows the Slurm jobs of a plan (decision D306):
/// the jobs keep running (nothing is cancelled). Writes the stopped report in `d.dir` with the
/// unit states at that moment (squeue), saying that only the waiting stopped, how to follow
/// the jobs (`pnc status DIR`) and how to cancel them (`scancel` with the live job ids); prints
/// one line saying the same; returns the exit code 128 + `sig`.
int slurm_wait_interrupted(const PlanDriver& d, const campaign::Plan& p, int sig);

/// The Slurm executor for a planned command: submits what is not done (spec overridden by
/// `o`), prints the jobs; without --wait returns 0 at once (with --json the submission on
/// stdout); with --wait polls the unit states until the final unit ended and returns
/// `conclude(failed)`; when that throws because the final unit is not done, the run folder
/// first gets the stopped report (write_plan_stopped_report, decision D300); a signal during
/// the wait ends it with slurm_wait_interrupted() (D306). `default_prefix` names
/// the jobs when --job-name is not given.
int run_plan_slurm(const PlanDriver& d, const campaign::Plan& p, campaign::SlurmSpec spec,
                   const SlurmOptions& o, const std::string& default_prefix,
                   const std::function<int(const std::vector<std::string>&)>& conclude);

/// "pnc-" + `name` with every character outside [A-Za-z0-9.-] replaced by '_' (40 at most).
std::string job_prefix_of(const std::string& name);

} // namespace pnc::app
