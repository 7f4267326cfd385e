#pragma once
// pnc/campaign/slurm.hpp: the Slurm executor of a plan of units (campaign.hpp, decisions D243-D245,
// docs/cluster.md).
//
// Every unit runs as a Slurm job executing `pnc run-unit DIR UNIT...` in the shared run
// folder. The not-done units of one group (e.g. the equilibrations of all replicas, the cases
// of one replica) are one job array (task i runs the group's i-th unit); a group waits for
// the jobs of its needs with --dependency=afterok:<job>[_<task>] (a join unit, the fit, with
// afterany: it starts when they ended and names the units that are missing). Jobs are
// submitted held, their units marked queued(job id), then released: a unit's own `running`
// record can never be overwritten by `queued`. A unit with K > 1 MPI ranks gets --ntasks=K
// and launches its LAMMPS stages with `srun` inside the job (runner.hpp,
// PNC_STAGE_LAUNCHER=srun).
//
// Nothing is built into a shell string: sbatch, squeue, scontrol and scancel are executed with
// argument vectors; the job script is a template file whose {{placeholders}} take validated
// values only (names of [A-Za-z0-9_.-], numbers, Slurm time limits), and the command the job
// runs comes as the script's arguments ("$@").
#include "pnc/campaign/campaign.hpp"

#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

namespace pnc::campaign {

/// Recipe section "slurm" (all optional; CLI options override): where and how long the jobs
/// run, ranks per unit, the job-script template, the MPI plugin of srun.
struct SlurmSpec {
  bool given = false;        ///< the recipe has a "slurm" section (expanded_json keeps it)
  std::string partition;     ///< --partition; "" = the cluster's default
  std::string account;       ///< --account; "" = the user's default
  std::string time;          ///< --time per unit job (minutes, [D-]HH:MM:SS, ...); "" = default
  int ranks = 0;             ///< MPI ranks per case unit under Slurm (0: --ranks or 1)
  int equilibrate_ranks = 0; ///< ranks per equilibration/phase-check unit (0: ranks)
  std::string template_path; ///< job-script template; "" = the built-in one
  std::string mpi = "pmix";  ///< srun --mpi=<this> for units with ranks > 1
  void validate(const std::string& source) const;
};
SlurmSpec parse_slurm_spec(const nlohmann::json& j, const std::string& source);
nlohmann::json slurm_spec_json(const SlurmSpec& s);

/// The built-in job-script template (docs/cluster.md shows it).
const std::string& default_sbatch_template();
/// `text` with each {{name}} replaced by values.at(name); an unknown placeholder or an
/// unclosed "{{" throws InputError naming `source` and the placeholder.
std::string render_template(const std::string& text,
                            const std::map<std::string, std::string>& values,
                            const std::string& source);

struct SlurmSubmission {
  std::map<std::string, std::string> job_of_unit; ///< unit id -> job id ("123" or "123_4")
  std::vector<std::string> jobs;                  ///< job ids given by sbatch, in order
  std::vector<std::string> kept;                  ///< units already queued/running (resume)
};

/// Submits every unit of `p` that is not done and not queued or running in a live job, as
/// above. `pnc_exe` is the pnc the jobs run (absolute path, visible on the compute nodes).
/// Throws InputError with sbatch's own message when a submission fails (jobs submitted by this
/// call are cancelled then).
SlurmSubmission submit_slurm(const std::string& dir, const Plan& p, const SlurmSpec& spec,
                             const std::string& pnc_exe, const std::string& job_prefix);

/// Job id -> Slurm state ("PENDING", "RUNNING", ...; "PENDING (Dependency)" with the reason)
/// of the user's jobs in the queue, array tasks one by one. Throws InputError when squeue
/// cannot be run.
std::map<std::string, std::string> slurm_queue();

/// A unit's state as `pnc status` shows it: the state file, checked against the queue for
/// queued/running units (a job that left the queue without the unit recording an end is
/// reported as failed: "job <id> ended without a report (cancelled, timed out or killed)").
UnitStatus effective_status(const std::string& dir, const std::string& id,
                            const std::map<std::string, std::string>* queue);

} // namespace pnc::campaign
