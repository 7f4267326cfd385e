// MD pipeline of `pnc characterize` (units real inside, Pa in cases.h5).
#include "pnc/rve/characterize.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/version.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/md/stage_stop.hpp"
#include "pnc/rve/clay.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace pnc::rve {

namespace fs = std::filesystem;
// the generic plan layer (pnc/campaign/campaign.hpp); the plan of characterize is made here
using campaign::check_plan;
using campaign::epoch_seconds;
using campaign::Plan;
using campaign::plan_path;
using campaign::read_status;
using campaign::Unit;
using campaign::UnitState;
using campaign::UnitStatus;

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
  return md::polymer_forcefield_commands(r.ff);
}

/// Build and equilibration of one replica in `rdir` (its own seeds: replica_build_seed).
void prepare_replica(const Recipe& r, const std::string& rdir, bool resume,
                     const std::string& recipe_text, int eq_ranks, double& seconds_build,
                     double& seconds_equilibrate, ReplicaOutcome& ro) {
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
    const md::System s = r.model == "pnc"  ? build_composite(r.build, r.ff, r.clay, &ci)
                         : r.model == "kg" ? build_bead_spring(r.build, r.kg)
                         : r.model == "kg_platelet"
                             ? build_kg_platelet(r.build, r.kg, r.platelet, &pi)
                             : md::build_polymer(r.build, r.ff);
    md::write_data_file(ro.data_file, s, "pnc characterize " + r.name);
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
      md::write_build_record(ro.build_record, s, r.build, r.ff, recipe_text);
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
                                 : md::min_nonbonded_distance(s));
  } else {
    std::cerr << "pnc characterize [build] done (resumed)\n";
  }
  seconds_build += seconds_since(t0);

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
  seconds_equilibrate += seconds_since(t0);
}

} // namespace

namespace {

/// The recipe of replica `rep`: its own build and equilibration seed (decision D130).
Recipe replica_recipe(const Recipe& r, int rep) {
  Recipe rr = r;
  rr.seed = replica_build_seed(r.seed, rep);
  rr.build.seed = rr.seed;
  rr.equilibrate.seed = rr.seed;
  return rr;
}

std::string case_name(int nrep, int rep, int id) {
  return nrep > 1 ? fmt::format("replica {} case {}", rep, id) : fmt::format("case {}", id);
}

/// "replica_<r>/..." -> r; "case_<n>" in the last part -> n (unit ids of characterize_plan).
int number_after(const std::string& id, const std::string& prefix, const std::string& source) {
  const auto at = id.find(prefix);
  if (at == std::string::npos) fail(source, "unit", id, "is not a unit of pnc characterize");
  std::size_t k = at + prefix.size(), end = k;
  while (end < id.size() && std::isdigit(static_cast<unsigned char>(id[end])))
    ++end;
  if (end == k || end - k > 4) fail(source, "unit", id, "is not a unit of pnc characterize");
  return std::stoi(id.substr(k, end - k));
}

std::string equilibrate_dir(const std::string& dir, int nrep, int rep) {
  return (fs::path(replica_dir(dir, nrep, rep)) / "equilibrate").string();
}

DeformSpec case_spec(const Recipe& r, const std::string& recipe_text, const std::string& start,
                     int rep, int id) {
  DeformSpec d = r.deform;
  d.case_id = id;
  d.seed = replica_case_seed(r.seed, rep, id);
  d.start_state = start;
  d.force_field = model_forcefield_commands(r);
  d.recipe_json = recipe_text;
  if (r.system.enabled) { // the user's force field, re-issued after every read_restart
    d.force_field = r.system.forcefield;
    d.atom_style = r.system.atom_style;
  }
  return d;
}

PhaseCheckInput phase_input(const Recipe& r, const std::string& recipe_text,
                            const std::string& start, const std::string& equilibrate_dir1) {
  PhaseCheckInput pin;
  pin.start_state = start;
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
  pin.equilibrate_dir = equilibrate_dir1;
  if (!r.system.enabled && r.equilibrate.ensemble == "npt") // equilibrate.cpp's NPT chunks
    pin.npt_chunk_fs =
        static_cast<double>(std::max<long>(10, (r.equilibrate.npt_steps / 10) / 10 * 10)) *
        r.equilibrate.timestep_fs;
  return pin;
}

nlohmann::json run_case_unit(const Recipe& r, const std::string& dir, const std::string& recipe,
                             int nrep, int rep, int id, int ranks) {
  const std::string name = case_name(nrep, rep, id);
  const std::string start = read_equilibrated(equilibrate_dir(dir, nrep, rep)).restart;
  const DeformSpec d = case_spec(r, recipe, start, rep, id);
  const std::string cdir = case_dir(dir, nrep, rep, id);
  if (fs::exists(fs::path(cdir) / "checkpoint.h5")) {
    const CaseResult c = read_case(cdir);
    if (c.rows_done >= d.steps + 1) {
      std::cerr << fmt::format("pnc characterize [{}] done (resumed)\n", name);
      return {{"resumed", true}};
    }
    std::cerr << fmt::format("pnc characterize [{}] resuming after step {}/{}\n", name,
                             c.rows_done - 1, d.steps);
  }
  std::cerr << fmt::format("pnc characterize [{}] {} MPI rank(s); LAMMPS log {}/lammps.log\n", name,
                           ranks, cdir);
  const md::StageOutcome o = md::run_stage(case_stage(d, cdir, ranks), case_body(d, cdir, true));
  pnc::throw_if_stopped(fmt::format("{} stopped; its checkpoint is kept", name));
  if (!o.ok) {
    std::cerr << fmt::format("pnc characterize [{}] FAILED: {} (log {})\n", name, o.error,
                             o.log_path);
    md::throw_stage_failure(o, "stage " + name); // ToolError with LAMMPS's message: exit code 7
  }
  std::cerr << fmt::format("pnc characterize [{}] finished in {:.1f} s\n", name, o.seconds);
  return {{"resumed", false}};
}

} // namespace

Plan characterize_plan(const Recipe& r, int ranks, int equilibrate_ranks,
                       const nlohmann::json& parameters) {
  Plan p;
  p.command = "characterize";
  p.parameters = parameters;
  p.parameters["ranks"] = ranks;
  p.parameters["equilibrate_ranks"] = equilibrate_ranks;
  const int nrep = std::max(1, r.replicas);
  const auto rel = [&](int rep, const std::string& what) {
    const fs::path rd = nrep > 1 ? fs::path(fmt::format("replica_{}", rep)) : fs::path();
    return (rd / what).string();
  };
  Unit fit{"fit", "fit", "fit", {}, true, 1, {"recipe.json"}, {}};
  for (int rep = 1; rep <= nrep; ++rep) {
    Unit u{fmt::format("replica_{}/equilibrate", rep),
           "equilibrate",
           "equilibrate",
           {},
           false,
           equilibrate_ranks,
           {"recipe.json"},
           {rel(rep, "build"), rel(rep, "equilibrate")}};
    if (r.system.enabled) u.inputs.push_back(r.system.input_file);
    fit.needs.push_back(u.id);
    p.units.push_back(u);
  }
  if (r.phase_check.enabled) {
    p.units.push_back({"phase_check",
                       "phase_check",
                       "phase_check",
                       {"replica_1/equilibrate"},
                       false,
                       equilibrate_ranks,
                       {rel(1, "equilibrate/final.restart")},
                       {"phase"}});
    fit.needs.push_back("phase_check");
  }
  for (int rep = 1; rep <= nrep; ++rep)
    for (int id : r.cases) {
      Unit u{fmt::format("replica_{}/case_{}", rep, id),
             "case",
             fmt::format("cases_replica_{}", rep),
             {fmt::format("replica_{}/equilibrate", rep)},
             false,
             ranks,
             {rel(rep, "equilibrate/final.restart")},
             {rel(rep, fmt::format("cases/case_{}", id))}};
      fit.needs.push_back(u.id);
      p.units.push_back(u);
    }
  fit.outputs = {"cases.h5", "card.h5", "report.md", "summary.json", "plots"};
  p.units.push_back(fit);
  check_plan(p, "<characterize plan>");
  return p;
}

namespace {
/// DIR/replica_history.json: [{"from": M, "to": N, "utc": "..."}, ...] (decision D418).
nlohmann::json read_replica_history(const std::string& path) {
  std::ifstream f(path);
  nlohmann::json h = nlohmann::json::parse(f, nullptr, false);
  bool ok = h.is_array();
  for (const auto& e : ok ? h : nlohmann::json::array())
    ok = ok && e.is_object() && e.contains("from") && e["from"].is_number_integer() &&
         e.contains("to") && e["to"].is_number_integer() && e.contains("utc") &&
         e["utc"].is_string();
  if (!ok)
    fail(path, "", "",
         "is not pnc's replica history (a JSON array of {\"from\": M, \"to\": N, \"utc\": "
         "TIME}, D418)");
  return h;
}

/// --resume with a recipe that differs from the run's stored one (decision D418): allowed only
/// when the one difference is a larger run.replicas on a run of >= 2 replicas (their folders,
/// seeds and units do not depend on the count: replica_dir, replica_build_seed); fails naming
/// the first other difference, or the count's rule.
void check_replica_extension(const Recipe& r, const std::string& recipe_path,
                             const std::string& stored_text) {
  nlohmann::json stored = nlohmann::json::parse(stored_text, nullptr, false);
  if (!stored.is_object()) fail(recipe_path, "", "", "is not a JSON object (not pnc's)");
  nlohmann::json now = expanded_json(r);
  const auto count = [](const nlohmann::json& j) {
    const nlohmann::json* run = j.contains("run") && j["run"].is_object() ? &j["run"] : nullptr;
    return run && run->contains("replicas") && (*run)["replicas"].is_number_integer()
               ? (*run)["replicas"].get<int>()
               : 1;
  };
  const int was = count(stored);
  const int is = std::max(1, r.replicas);
  for (nlohmann::json* j : {&stored, &now})
    if (j->contains("run") && (*j)["run"].is_object()) (*j)["run"].erase("replicas");
  require_same_input(recipe_path, stored, now, recipe_path, "run.replicas, to add replicas (D418)");
  if (is == was) return; // the same recipe, written otherwise (compared as JSON values)
  if (is < was)
    fail(recipe_path, "run.replicas", std::to_string(is),
         fmt::format("is fewer than the {} replicas this run was started with: --resume keeps "
                     "every replica of a run and may add more (D418); a run of fewer replicas "
                     "needs a new --out directory",
                     was));
  if (was < 2)
    fail(recipe_path, "run.replicas", std::to_string(is),
         "differs from the 1 replica this run was started with: a run of one replica keeps its "
         "files in the run folder itself, not in replica_<k> folders, and cannot be extended "
         "(D418); start the run of several replicas in a new --out directory");
  std::cerr << fmt::format("pnc characterize: --resume adds replicas {}..{} to the {} of this run "
                           "(their own seeds; the {} done are kept; D418)\n",
                           was + 1, is, was, was);
  // the additions are kept: a reader of the card can tell a count fixed in advance from one
  // extended after a result was seen (D418)
  const std::string hist = (fs::path(recipe_path).parent_path() / "replica_history.json").string();
  nlohmann::json h = nlohmann::json::array();
  if (fs::exists(hist)) h = read_replica_history(hist);
  h.push_back({{"from", was}, {"to", is}, {"utc", utc_timestamp()}});
  write_text_atomically(hist, h.dump(2) + "\n");
}
} // namespace

void prepare_run_folder(const Recipe& r, const std::string& dir, bool resume, bool refit) {
  make_output_directory(dir);
  if (r.system.enabled && resume) check_user_input_unchanged(r.system, dir); // decision D121
  const std::string recipe_text = expanded_json(r).dump(2);
  const std::string recipe_path = (fs::path(dir) / "recipe.json").string();
  if (fs::exists(recipe_path)) {
    std::ifstream f(recipe_path);
    std::stringstream ss;
    ss << f.rdbuf();
    if (ss.str() != recipe_text + "\n" && !refit) {
      if (resume)
        check_replica_extension(r, recipe_path, ss.str()); // D418
      else if (!fs::is_empty(fs::path(dir)))
        fail(dir, "--out", dir,
             "holds a run of another recipe; use a new --out directory or delete it");
    } else {
      refuse_existing_run(dir, resume, {"cases", "cases.h5", "replica_1", "plan.json"});
    }
  }
  write_text_atomically(recipe_path, recipe_text + "\n");
}

void check_refit(const Recipe& r, const std::string& dir) {
  const std::string recipe_path = (fs::path(dir) / "recipe.json").string();
  if (!fs::is_regular_file(recipe_path) || !fs::is_regular_file(plan_path(dir)))
    fail(dir, "--out", dir,
         "--refit needs the run folder of a pnc characterize run (it has no recipe.json and "
         "plan.json)");
  nlohmann::json stored;
  {
    std::ifstream f(recipe_path);
    stored = nlohmann::json::parse(f, nullptr, false);
  }
  if (!stored.is_object()) fail(recipe_path, "", "", "is not a JSON object (not pnc's)");
  nlohmann::json now = expanded_json(r);
  stored.erase("fit");
  now.erase("fit");
  require_same_input(recipe_path, stored, now, recipe_path, "the fit section", "--refit");
  // every MD unit done: the fit reads only what they left on disk
  const campaign::Plan p = campaign::read_plan(dir);
  std::vector<std::string> open;
  std::size_t md_units = 0;
  for (const campaign::Unit& u : p.units) {
    if (u.kind == "fit") continue;
    ++md_units;
    if (campaign::read_status(dir, u.id).state != campaign::UnitState::done) open.push_back(u.id);
  }
  if (!open.empty())
    fail(plan_path(dir), "units", open.front(),
         fmt::format("--refit fits a finished run again, and {} of its {} MD unit(s) are not done "
                     "(the first: {}; pnc status {}); finish the run with --resume first",
                     open.size(), md_units, open.front(), dir));
}

std::string replica_history(const std::string& dir) {
  const std::string path = (fs::path(dir) / "replica_history.json").string();
  if (!fs::exists(path)) return "";
  std::string s;
  for (const auto& e : read_replica_history(path))
    s += fmt::format("{}{} at first, {}-{} added by --resume ({})", s.empty() ? "" : "; ",
                     e["from"].get<int>(), e["from"].get<int>() + 1, e["to"].get<int>(),
                     e["utc"].get<std::string>());
  return s;
}

Recipe read_run_recipe(const std::string& dir) {
  const std::string path = (fs::path(dir) / "recipe.json").string();
  if (!fs::is_regular_file(path))
    fail(path, "", "", "no recipe.json: is this the --out folder of pnc characterize?");
  return read_recipe(path);
}

nlohmann::json run_md_unit(const Recipe& r, const std::string& dir, const Unit& u) {
  const std::string recipe_text = expanded_json(r).dump(2);
  const int nrep = std::max(1, r.replicas);
  const std::string source = plan_path(dir);
  if (u.kind == "equilibrate") {
    const int rep = number_after(u.id, "replica_", source);
    if (rep < 1 || rep > nrep) fail(source, "unit", u.id, "no such replica in the recipe");
    if (nrep > 1) std::cerr << fmt::format("pnc characterize [replica {}/{}]\n", rep, nrep);
    ReplicaOutcome ro;
    ro.dir = replica_dir(dir, nrep, rep);
    double sb = 0, se = 0;
    prepare_replica(replica_recipe(r, rep), ro.dir, true, recipe_text, u.ranks, sb, se, ro);
    return {{"seconds_build", sb}, {"seconds_equilibrate", se}};
  }
  if (u.kind == "phase_check") {
    if (!r.phase_check.enabled) fail(source, "unit", u.id, "the recipe has no phase check");
    std::cerr << "pnc characterize [phase check] G(t), bulk modulus, cavitation at "
              << r.deform.temperature << " K\n";
    const std::string edir = equilibrate_dir(dir, nrep, 1);
    const PhaseCheckInput pin = phase_input(r, recipe_text, read_equilibrated(edir).restart, edir);
    run_phase_check(r.phase_check, pin, (fs::path(dir) / "phase").string(), true, u.ranks);
    return nlohmann::json::object();
  }
  if (u.kind == "case") {
    const int rep = number_after(u.id, "replica_", source);
    const int id = number_after(u.id, "case_", source);
    if (rep < 1 || rep > nrep || std::find(r.cases.begin(), r.cases.end(), id) == r.cases.end())
      fail(source, "unit", u.id, "no such replica or case in the recipe");
    return run_case_unit(r, dir, recipe_text, nrep, rep, id, u.ranks);
  }
  fail(source, "unit", u.id, "is not an MD unit (equilibrate, phase_check, case)");
}

MdOutcome collect_md(const Recipe& r, const std::string& dir, const Plan& p) {
  // the fit waits for what it needs: every unit it needs must be done, else say which are not
  const Unit& fit = p.unit("fit");
  std::string missing;
  int nmissing = 0;
  MdOutcome o;
  o.started_s = epoch_seconds();
  double cases_first = 0, cases_last = 0;
  for (const auto& id : fit.needs) {
    const UnitStatus s = read_status(dir, id);
    if (s.state == UnitState::done) {
      const Unit& u = p.unit(id);
      if (s.started_s > 0) o.started_s = std::min(o.started_s, s.started_s);
      if (u.kind == "equilibrate") {
        o.seconds_build += s.detail.value("seconds_build", 0.0);
        o.seconds_equilibrate += s.detail.value("seconds_equilibrate", 0.0);
      } else if (u.kind == "phase_check") {
        o.seconds_phase += s.detail.value("seconds", 0.0);
      } else if (u.kind == "case" && s.started_s > 0) {
        cases_first = cases_first > 0 ? std::min(cases_first, s.started_s) : s.started_s;
        cases_last = std::max(cases_last, s.ended_s);
      }
      continue;
    }
    ++nmissing;
    if (nmissing <= 8) {
      missing += fmt::format("{}{} ({}", missing.empty() ? "" : "; ", id, state_name(s.state));
      if (!s.job_id.empty()) missing += ", job " + s.job_id;
      if (!s.message.empty()) missing += ": " + s.message;
      missing += ")";
    }
  }
  if (nmissing > 0)
    fail(dir, "units not done", std::to_string(nmissing),
         fmt::format("the fit needs every unit done; missing: {}{}; finished work is kept: "
                     "rerun with --resume (pnc status {} shows every unit)",
                     missing, nmissing > 8 ? fmt::format(" and {} more", nmissing - 8) : "", dir));
  o.seconds_cases = cases_last > cases_first ? cases_last - cases_first : 0.0;
  o.dir = dir;
  o.recipe_path = (fs::path(dir) / "recipe.json").string();
  const std::string recipe_text = expanded_json(r).dump(2);
  const int nrep = std::max(1, r.replicas);
  {
    // every stage is done: this only reads the records (as a resume does), without its
    // "done (resumed)" lines
    struct Quiet {
      std::ostringstream sink;
      std::streambuf* old = std::cerr.rdbuf(sink.rdbuf());
      ~Quiet() { std::cerr.rdbuf(old); }
    } quiet;
    for (int rep = 1; rep <= nrep; ++rep) {
      ReplicaOutcome ro;
      ro.dir = replica_dir(dir, nrep, rep);
      double sb = 0, se = 0;
      prepare_replica(replica_recipe(r, rep), ro.dir, true, recipe_text, 1, sb, se, ro);
      o.replicas.push_back(ro);
    }
  }
  o.data_file = o.replicas[0].data_file;
  o.build_record = o.replicas[0].build_record;
  o.equilibrated = o.replicas[0].equilibrated;
  if (r.phase_check.enabled) o.phase = read_phase_check((fs::path(dir) / "phase").string());
  std::vector<std::vector<CaseResult>> results(static_cast<std::size_t>(nrep));
  for (int rep = 1; rep <= nrep; ++rep)
    for (int id : r.cases)
      results[rep - 1].push_back(read_case(case_dir(dir, nrep, rep, id)));
  o.cases = results[0];
  o.cases_h5 = (fs::path(dir) / "cases.h5").string();
  o.statistics = write_replica_cases_h5(o.cases_h5, r, results);
  o.statistics_markdown = statistics_markdown(o.statistics);
  o.replica_history = replica_history(dir); // D418
  if (!o.replica_history.empty())
    o.statistics_markdown += fmt::format(
        "Replicas added to the run (D418): {}. The 97.5 % bounds hold for a count fixed before "
        "its data were seen; a count extended until a card passes covers less.\n\n",
        o.replica_history);
  return o;
}

} // namespace pnc::rve
