#pragma once
// pnc/rve/characterize.hpp: the MD half of `pnc characterize`: build -> equilibrate ->
// deformation cases -> cases.h5 (SI) for the fit, as units of a plan (pnc/campaign/campaign.hpp)
// that an executor runs (pnc/campaign/executor.hpp: local children; slurm.hpp: Slurm jobs).
//
// Units: LAMMPS `real` inside; cases.h5 in Pa (tension positive).
//
// Output directory layout:
//   recipe.json                      the expanded recipe (a resumed run must match it)
//   build/rve.data, build/build.h5   builder output and record
//   equilibrate/<stage>.{log,h5,restart}
//   phase/phase.{h5,log}             phase check (phase_check.hpp), when the recipe enables it
//   cases/case_<n>/{checkpoint.h5,lammps.log,state_<k>.restart}
//   plan.json, state/<unit>.json     the plan of units and their states (pnc/campaign)
//   cases.h5                         strain/stress (+ standard errors) per case, the stress
//                                    chosen by the recipe, never smoothed (replicas.hpp)
// With "run": {"replicas": N >= 2} (decision D130) build/, equilibrate/ and cases/ are in
// replica_<r>/ (r = 1..N), each replica with its own build seed and equilibration; recipe.json
// and cases.h5 stay at the top.
#include "pnc/campaign/campaign.hpp"
#include "pnc/rve/equilibrate.hpp"
#include "pnc/rve/recipe.hpp"
#include "pnc/rve/replicas.hpp"

#include <string>
#include <vector>

namespace pnc::rve {

struct ReplicaOutcome {
  std::string dir, data_file, build_record;
  EquilibratedState equilibrated;
  PhaseCheckResult phase; ///< phase.done false when the recipe does not enable the check
};

struct MdOutcome {
  std::string dir, recipe_path, data_file, build_record, cases_h5; ///< of replica 1
  EquilibratedState equilibrated;                                  ///< of replica 1
  PhaseCheckResult phase;                                          ///< of replica 1
  std::vector<CaseResult> cases;                                   ///< of replica 1
  std::vector<ReplicaOutcome> replicas;                            ///< every replica, in order
  CombinedCases statistics;        ///< what went into cases.h5 (replicas.hpp)
  std::string statistics_markdown; ///< a "## Statistics" section for report.md
  /// how the replicas came to be (decision D418): "" when the run started with all of them,
  /// else e.g. "24 at first, 25-48 added by --resume (2026-12-06T20:16:44Z)"
  std::string replica_history;
  double seconds_build = 0, seconds_equilibrate = 0, seconds_phase = 0, seconds_cases = 0;
  double started_s = 0; ///< UTC epoch seconds when the first unit of the run started
};

/// The MD pipeline of `pnc characterize` as a plan of units (campaign.hpp, decisions
/// D240-D243):
///   replica_<r>/equilibrate   build + equilibration of replica r (ranks: equilibrate_ranks)
///   phase_check               the phase check on replica 1, needs replica_1/equilibrate
///   replica_<r>/case_<n>      deformation case n of replica r, needs replica_<r>/equilibrate
///   fit                       cases.h5 -> fit -> card, report (join: needs every unit above)
/// Unit ids are the same for one replica (its files then sit in the run folder itself).
/// `parameters` is stored in plan.json as is (ranks, the command's options for the fit).
campaign::Plan characterize_plan(const Recipe& r, int ranks, int equilibrate_ranks,
                                 const nlohmann::json& parameters);

/// Checks the run folder against the recipe and writes recipe.json (the expanded recipe):
/// without `resume` a folder holding another run is refused; with `resume` the recipe (and a
/// user system's input, D121) must equal the stored one but for a larger run.replicas on a
/// run of >= 2 replicas, which adds replicas (decision D418; InputError naming the first other
/// difference, or the count's rule); `refit`: check_refit() passed, the stored recipe is
/// replaced by r's. Each addition is appended to DIR/replica_history.json (replica_history()).
void prepare_run_folder(const Recipe& r, const std::string& dir, bool resume, bool refit = false);
/// `pnc characterize --refit` (decision D400): fit a finished run again with another fit section.
/// The run folder's stored recipe (DIR/recipe.json) and `r` may differ only under "fit", and
/// every unit of its plan but the fit must be done; throws InputError naming the first other
/// difference, or the units not done (and that --resume finishes them). Then the caller
/// continues as --resume: prepare_run_folder() stores r's recipe, only the fit unit runs.
void check_refit(const Recipe& r, const std::string& dir);
/// How the replicas of run folder `dir` came to be (decision D418), from its
/// replica_history.json: "" when none were added, else "M at first, M+1-N added by --resume
/// (UTC time)" per addition, "; "-separated. InputError naming the file if it is not pnc's.
std::string replica_history(const std::string& dir);
/// The recipe a run folder was made with (DIR/recipe.json).
Recipe read_run_recipe(const std::string& dir);

/// Runs one MD unit (equilibrate, phase_check or case) of the plan in this process, its LAMMPS
/// stages in supervised children; continues from what is on disk (finished stages are reused,
/// a case continues from its checkpoint). Returns the unit's detail for its state file
/// (seconds). Throws (throw_stage_failure) ToolError with LAMMPS's message and log,
/// InputError, SimulationError, or Interrupted.
nlohmann::json run_md_unit(const Recipe& r, const std::string& dir, const campaign::Unit& u);

/// The fit's input: every unit `fit` needs must be done (else InputError listing the missing
/// units with their states); reads replicas, phase check and cases from disk and writes
/// cases.h5. Seconds come from the units' state files (build and equilibration summed over the
/// replicas, cases as the wall-time span of the case units).
MdOutcome collect_md(const Recipe& r, const std::string& dir, const campaign::Plan& p);

/// cases.h5 from the case checkpoints of one replica (write_replica_cases_h5 with N = 1).
void write_cases_h5(const std::string& path, const Recipe& r, const std::vector<CaseResult>& cases);
/// cases.h5 from `results[replica][case]`: the stress of `r.stress` relative to each replica's
/// reference, mean over replicas with between-replica errors for N >= 2, never smoothed (a
/// moving average is stored for display only), labelled in `stress_definition` (D130-D134).
CombinedCases write_replica_cases_h5(const std::string& path, const Recipe& r,
                                     const std::vector<std::vector<CaseResult>>& results);

} // namespace pnc::rve
