#pragma once
// pnc/rve/characterize.hpp: the MD half of `pnc characterize`: build -> equilibrate ->
// deformation cases (in parallel child processes) -> cases.h5 (SI) for the fit.
//
// Units: LAMMPS `real` inside; cases.h5 in Pa (tension positive).
//
// Output directory layout:
//   recipe.json                      the expanded recipe (a resumed run must match it)
//   build/rve.data, build/build.h5   builder output and record
//   equilibrate/<stage>.{log,h5,restart}
//   phase/phase.{h5,log}             phase check (phase_check.hpp), when the recipe enables it
//   cases/case_<n>/{checkpoint.h5,lammps.log,state_<k>.restart}
//   cases.h5                         strain/stress (+ standard errors) per case, the stress
//                                    chosen by the recipe, never smoothed (replicas.hpp)
// With "run": {"replicas": N >= 2} (decision D130) build/, equilibrate/ and cases/ are in
// replica_<r>/ (r = 1..N), each replica with its own build seed and equilibration; recipe.json
// and cases.h5 stay at the top.
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
  double seconds_build = 0, seconds_equilibrate = 0, seconds_phase = 0, seconds_cases = 0;
};

/// Runs the MD pipeline. With `resume`, finished parts are reused and cases continue from
/// their checkpoints; the recipe must equal the one stored in `dir`. Failed cases are all
/// run to their end (or failure) before the first failure is thrown as the error of its kind
/// (throw_stage_failure, runner.hpp: pnc::ToolError with LAMMPS's message); finished cases and
/// checkpoints stay on disk. `jobs` cases run at a time, each LAMMPS stage on `ranks` MPI ranks
/// (StageSpec::ranks): jobs x ranks cores in all. The equilibration stages, which run one at a
/// time, use `equilibrate_ranks` (0: `ranks`); different rank counts agree to round-off, not
/// bitwise.
MdOutcome run_md(const Recipe& r, const std::string& dir, bool resume, int jobs, int ranks = 1,
                 int equilibrate_ranks = 0);

/// cases.h5 from the case checkpoints of one replica (write_replica_cases_h5 with N = 1).
void write_cases_h5(const std::string& path, const Recipe& r, const std::vector<CaseResult>& cases);
/// cases.h5 from `results[replica][case]`: the stress of `r.stress` relative to each replica's
/// reference, mean over replicas with between-replica errors for N >= 2, never smoothed (a
/// moving average is stored for display only), labelled in `stress_definition` (D130-D134).
CombinedCases write_replica_cases_h5(const std::string& path, const Recipe& r,
                                     const std::vector<std::vector<CaseResult>>& results);

} // namespace pnc::rve
