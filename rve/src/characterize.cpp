// MD pipeline of `pnc characterize` (units real inside, Pa in cases.h5).
#include "pnc/rve/characterize.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/rve/clay.hpp"
#include "pnc/rve/runner.hpp"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace pnc::rve {

namespace fs = std::filesystem;

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
std::string case_dir(const std::string& dir, int replicas, int replica, int id) {
  return (fs::path(replica_dir(dir, replicas, replica)) / "cases" / fmt::format("case_{}", id))
      .string();
}
} // namespace

void write_cases_h5(const std::string& path, const Recipe& r,
                    const std::vector<CaseResult>& cases) {
  write_replica_cases_h5(path, r, {cases});
}

CombinedCases write_replica_cases_h5(const std::string& path, const Recipe& r,
                                     const std::vector<std::vector<CaseResult>>& results) {
  // decisions D130-D134: replicas, reference state, no smoothing in the fit, checked errors
  CombinedCases c = combine_cases(r, results);
  write_combined_cases_h5(path, r, c, results);
  return c;
}

namespace {

/// The force-field commands of the recipe's built-in model (re-issued after every read_restart).
std::vector<std::string> model_forcefield_commands(const Recipe& r) {
  if (r.model == "pnc") return composite_forcefield_commands(r.ff);
  if (r.model == "kg") return bead_spring_commands(r.kg);
  if (r.model == "kg_platelet") return kg_platelet_commands(r.kg, r.platelet);
  return polymer_forcefield_commands(r.ff);
}

/// Build and equilibration of one replica in `rdir` (its own seeds: replica_build_seed).
void prepare_replica(const Recipe& r, const std::string& rdir, bool resume,
                     const std::string& recipe_text, int eq_ranks, MdOutcome& o,
                     ReplicaOutcome& ro) {
  // --- build
  auto t0 = std::chrono::steady_clock::now();
  make_output_directory(rdir);
  const fs::path bdir = fs::path(rdir) / "build";
  make_output_directory(bdir.string());
  ro.data_file = (bdir / "rve.data").string();
  ro.build_record = (bdir / "build.h5").string();
  if (r.system.enabled) { // the user's own data/restart file (decision D121)
    ro.data_file = prepare_user_input(r.system, bdir.string(), resume);
    ro.build_record = (bdir / "system.json").string();
  } else if (!(resume && fs::exists(ro.data_file) && fs::exists(ro.build_record))) {
    std::cerr << fmt::format("pnc characterize [build] {} chains x {} beads at {} g/cm3, seed {}\n",
                             r.build.chains, r.build.beads_per_chain, r.build.density, r.seed);
    CompositeInfo ci;
    PlateletInfo pi;
    const System s = r.model == "pnc"           ? build_composite(r.build, r.ff, r.clay, &ci)
                     : r.model == "kg"          ? build_bead_spring(r.build, r.kg)
                     : r.model == "kg_platelet" ? build_kg_platelet(r.build, r.kg, r.platelet, &pi)
                                                : build_polymer(r.build, r.ff);
    write_data_file(ro.data_file, s, "pnc characterize " + r.name);
    if (r.model == "kg_platelet") { // decision D170: what was built, next to build.h5
      const double dmin = min_polymer_platelet_distance(s);
      write_text_atomically((bdir / "platelet.json").string(),
                            platelet_info_json(pi, r.platelet, r.kg, dmin).dump(2) + "\n");
      std::cerr << fmt::format("  platelet: {} x {} x {} beads ({} bonds), edge {:.2f} A of a "
                               "{:.2f} A box ({:.2f}), bead fraction {:.4f}, min bead-platelet "
                               "distance {:.3f} A, omega bound {:.4f} / fs\n",
                               r.platelet.beads_side, r.platelet.beads_side, r.platelet.layers,
                               pi.platelet_bonds, pi.edge_A, pi.box_A, pi.edge_A / pi.box_A,
                               pi.volume_fraction, dmin, pi.omega_bound_per_fs);
    }
    if (r.model == "kg" || r.model == "kg_platelet")
      write_bead_spring_record(ro.build_record, s, r.build, r.kg, recipe_text);
    else
      write_build_record(ro.build_record, s, r.build, r.ff, recipe_text);
    if (r.model == "pnc") {
      const nlohmann::json cj = {
          {"cells_a", r.clay.cells_a},
          {"cells_b", r.clay.cells_b},
          {"clay_atoms", ci.clay_atoms},
          {"polymer_beads", ci.polymer_beads},
          {"clay_mass_g_mol", ci.clay_mass},
          {"polymer_mass_g_mol", ci.polymer_mass},
          {"platelet_length_A", ci.length},
          {"platelet_width_A", ci.width},
          {"platelet_thickness_A", ci.thickness},
          {"aspect_ratio_length_over_width", ci.aspect_ratio},
          {"clay_bounding_volume_A3", ci.clay_volume},
          {"box_volume_A3", ci.box_volume},
          {"volume_fraction", ci.volume_fraction},
          {"weight_fraction", ci.weight_fraction},
          {"min_polymer_clay_distance_A", min_polymer_clay_distance(s)},
          {"definitions", "volume fraction = platelet bounding volume (cells_a a x cells_b b x "
                          "atom-centre thickness) / box volume at the build; weight fraction = "
                          "W_clay / (W_clay + W_PP)"}};
      write_text_atomically((bdir / "clay.json").string(), cj.dump(2) + "\n");
      std::cerr << fmt::format("  clay: {} x {} cells, {} atoms, {:.2f} x {:.2f} x {:.2f} A "
                               "(aspect ratio {:.2f}), volume fraction {:.4f}, weight fraction "
                               "{:.4f}, min bead-clay distance {:.3f} A\n",
                               r.clay.cells_a, r.clay.cells_b, ci.clay_atoms, ci.length, ci.width,
                               ci.thickness, ci.aspect_ratio, ci.volume_fraction,
                               ci.weight_fraction, min_polymer_clay_distance(s));
    }
    std::cerr << fmt::format("  built {} beads, box {:.3f} A, min non-bonded distance {:.3f} A\n",
                             s.x.size(), s.length()[0],
                             r.model == "kg" || r.model == "kg_platelet"
                                 ? min_unbonded_distance(s)
                                 : min_nonbonded_distance(s));
  } else {
    std::cerr << "pnc characterize [build] done (resumed)\n";
  }
  o.seconds_build += seconds_since(t0);

  pnc::throw_if_stopped("after the build");
  // --- equilibrate
  t0 = std::chrono::steady_clock::now();
  std::cerr << fmt::format("pnc characterize [equilibrate] {}, {} MPI rank(s)\n",
                           r.system.enabled
                               ? fmt::format("{} user stage(s)", r.system.stages.size())
                               : "ensemble " + r.equilibrate.ensemble,
                           eq_ranks);
  const std::string edir = (fs::path(rdir) / "equilibrate").string();
  ro.equilibrated =
      r.system.enabled
          ? equilibrate_user(r.system, ro.data_file, edir, resume, recipe_text, r.seed, eq_ranks)
      : r.model == "kg" ? equilibrate_glass(ro.data_file, r.kg, r.equilibrate, edir, resume,
                                            recipe_text, eq_ranks)
      : r.model == "kg_platelet" ? equilibrate_glass(ro.data_file, r.kg, r.equilibrate, edir,
                                                     resume, recipe_text, eq_ranks, &r.platelet)
                                 : equilibrate(ro.data_file, r.ff, r.equilibrate, edir, resume,
                                               recipe_text, r.model == "pnc", eq_ranks);
  o.seconds_equilibrate += seconds_since(t0);
}

} // namespace

MdOutcome run_md(const Recipe& r, const std::string& dir, bool resume, int jobs, int ranks,
                 int equilibrate_ranks) {
  MdOutcome o;
  o.dir = dir;
  make_output_directory(dir);
  if (r.system.enabled && resume) check_user_input_unchanged(r.system, dir); // decision D121
  const std::string recipe_text = expanded_json(r).dump(2);
  o.recipe_path = (fs::path(dir) / "recipe.json").string();
  if (fs::exists(o.recipe_path)) {
    std::ifstream f(o.recipe_path);
    std::stringstream ss;
    ss << f.rdbuf();
    if (ss.str() != recipe_text + "\n") {
      if (resume)
        fail(o.recipe_path, "", "",
             "--resume with a recipe different from the one this directory was made with; "
             "use a new --out directory");
      if (!fs::is_empty(fs::path(dir)))
        fail(dir, "--out", dir,
             "holds a run of another recipe; use a new --out directory or delete it");
    } else {
      refuse_existing_run(dir, resume, {"cases", "cases.h5", "replica_1"});
    }
  }
  write_text_atomically(o.recipe_path, recipe_text + "\n");

  const int eq_ranks = equilibrate_ranks > 0 ? equilibrate_ranks : ranks;
  const int nrep = std::max(1, r.replicas);
  // decision D130: every replica its own build seed and its own equilibration
  for (int rep = 1; rep <= nrep; ++rep) {
    Recipe rr = r;
    rr.seed = replica_build_seed(r.seed, rep);
    rr.build.seed = rr.seed;
    rr.equilibrate.seed = rr.seed;
    if (nrep > 1) std::cerr << fmt::format("pnc characterize [replica {}/{}]\n", rep, nrep);
    ReplicaOutcome ro;
    ro.dir = replica_dir(dir, nrep, rep);
    prepare_replica(rr, ro.dir, resume, recipe_text, eq_ranks, o, ro);
    o.replicas.push_back(ro);
    pnc::throw_if_stopped("after the equilibration");
  }
  o.data_file = o.replicas[0].data_file;
  o.build_record = o.replicas[0].build_record;
  o.equilibrated = o.replicas[0].equilibrated;

  // --- phase check (phase_check.hpp): solid on the hold time scale? On replica 1 (the
  // replicas share the recipe: one structure answers the question for the protocol).
  if (r.phase_check.enabled) {
    const auto tp = std::chrono::steady_clock::now();
    std::cerr << "pnc characterize [phase check] G(t), bulk modulus, cavitation at "
              << r.deform.temperature << " K\n";
    PhaseCheckInput pin;
    pin.start_state = o.equilibrated.restart;
    pin.force_field = model_forcefield_commands(r);
    pin.probe_A = r.model == "kg" || r.model == "kg_platelet" ? r.kg.sigma : r.ff.sigma;
    if (r.system.enabled) { // the user's force field; no bead size for the void measure
      pin.force_field = r.system.forcefield;
      pin.atom_style = r.system.atom_style;
      pin.probe_A = 0;
    }
    pin.temperature = r.deform.temperature;
    pin.damp_fs = r.deform.damp_fs;
    pin.timestep_fs = r.deform.timestep_fs;
    pin.hold_steps = r.deform.hold_steps;
    pin.hold_sample_every = r.deform.sample_every;
    pin.seed = replica_build_seed(r.seed, 1) * 100 + 50;
    pin.recipe_json = recipe_text;
    pin.equilibrate_dir = (fs::path(o.replicas[0].dir) / "equilibrate").string();
    if (!r.system.enabled && r.equilibrate.ensemble == "npt") // equilibrate.cpp's NPT chunks
      pin.npt_chunk_fs =
          static_cast<double>(std::max<long>(10, (r.equilibrate.npt_steps / 10) / 10 * 10)) *
          r.equilibrate.timestep_fs;
    o.phase =
        run_phase_check(r.phase_check, pin, (fs::path(dir) / "phase").string(), resume, eq_ranks);
    o.seconds_phase = seconds_since(tp);
  }

  // --- cases
  auto t0 = std::chrono::steady_clock::now();
  std::vector<std::pair<StageSpec, StageBody>> stages;
  std::vector<std::string> run_ids;
  for (int rep = 1; rep <= nrep; ++rep)
    for (int id : r.cases) {
      DeformSpec d = r.deform;
      d.case_id = id;
      d.seed = replica_case_seed(r.seed, rep, id);
      d.start_state = o.replicas[rep - 1].equilibrated.restart;
      d.force_field = model_forcefield_commands(r);
      d.recipe_json = recipe_text;
      if (r.system.enabled) { // the user's force field, re-issued after every read_restart
        d.force_field = r.system.forcefield;
        d.atom_style = r.system.atom_style;
      }
      const std::string cdir = case_dir(dir, nrep, rep, id);
      const std::string name =
          nrep > 1 ? fmt::format("replica {} case {}", rep, id) : fmt::format("case {}", id);
      if (resume && fs::exists(fs::path(cdir) / "checkpoint.h5")) {
        const CaseResult c = read_case(cdir);
        if (c.rows_done >= d.steps + 1) {
          std::cerr << fmt::format("pnc characterize [{}] done (resumed)\n", name);
          continue;
        }
        std::cerr << fmt::format("pnc characterize [{}] resuming after step {}/{}\n", name,
                                 c.rows_done - 1, d.steps);
      }
      stages.push_back({case_stage(d, cdir, ranks), case_body(d, cdir, resume)});
      run_ids.push_back(name);
    }
  if (!stages.empty())
    std::cerr << fmt::format("pnc characterize [cases] {} case(s), {} at a time, {} MPI rank(s) "
                             "each; LAMMPS logs in {}/{}cases/case_<n>/lammps.log\n",
                             stages.size(), std::max(1, jobs), ranks, dir,
                             nrep > 1 ? "replica_<r>/" : "");

  const auto outcomes = run_stages(stages, jobs);
  pnc::throw_if_stopped("the running cases stopped; their checkpoints are kept");
  std::size_t first_failed = outcomes.size();
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    if (outcomes[i].ok) {
      std::cerr << fmt::format("pnc characterize [{}] finished in {:.1f} s\n", run_ids[i],
                               outcomes[i].seconds);
    } else {
      std::cerr << fmt::format("pnc characterize [{}] FAILED: {} (log {})\n", run_ids[i],
                               outcomes[i].error, outcomes[i].log_path);
      if (first_failed == outcomes.size()) first_failed = i;
    }
  }
  if (first_failed < outcomes.size()) // the first failure, as the error of its kind
    throw_stage_failure(outcomes[first_failed], "case " + run_ids[first_failed],
                        "; finished steps are kept: rerun with --resume");
  std::vector<std::vector<CaseResult>> results(static_cast<std::size_t>(nrep));
  for (int rep = 1; rep <= nrep; ++rep)
    for (int id : r.cases)
      results[rep - 1].push_back(read_case(case_dir(dir, nrep, rep, id)));
  o.cases = results[0];
  o.seconds_cases = seconds_since(t0);
  o.cases_h5 = (fs::path(dir) / "cases.h5").string();
  o.statistics = write_replica_cases_h5(o.cases_h5, r, results);
  o.statistics_markdown = statistics_markdown(o.statistics);
  return o;
}

} // namespace pnc::rve
