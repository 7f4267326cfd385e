// pnc rve build | pnc recipe show | pnc characterize: the RVE builder, recipes and the
// MD -> fit pipeline (docs/rve.md, docs/theory.md section 3). Units inside rve/: LAMMPS real;
// cases.h5 and cards in Pa.
#include "characterize_report.hpp"
#include "checks.hpp"
#include "figures.hpp"
#include "registrars.hpp"
#include "report.hpp"
#include "run_control.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/version.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/moduli.hpp"
#include "pnc/rve/builder.hpp"
#include "pnc/rve/characterize.hpp"
#include "pnc/rve/lammps_server.hpp"
#include "pnc/rve/recipe.hpp"
#include "pnc/rve/replica_fits.hpp"
#include "pnc/rve/replica_trend.hpp"
#include "pnc/rve/runner.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <thread>

namespace pnc::app {

namespace {

namespace fs = std::filesystem;

struct BuildArgs {
  rve::BuildSpec spec;
  rve::ClaySpec clay;
  bool with_clay = false;
  std::string out;
  bool json = false;
};

int run_rve_build(const BuildArgs& a) {
  const rve::PolymerForceField ff;
  a.spec.validate("<command line>");
  if (a.with_clay) a.clay.validate("<command line>");
  make_output_directory(a.out);
  rve::CompositeInfo ci;
  const rve::System s =
      a.with_clay ? rve::build_composite(a.spec, ff, a.clay, &ci) : rve::build_polymer(a.spec, ff);
  const std::string data = (fs::path(a.out) / "rve.data").string();
  const std::string rec = (fs::path(a.out) / "build.h5").string();
  rve::write_data_file(data, s,
                       a.with_clay ? "coarse-grained polypropylene + montmorillonite RVE"
                                   : "coarse-grained polypropylene RVE");
  write_build_record(rec, s, a.spec, ff, "{}");
  const std::string ffin = (fs::path(a.out) / "forcefield.lmp").string();
  std::string cmds = "# force field of section 6.1 (+ Tables 6.2-6.5 for the clay), units real "
                     "(decisions D13, D14, D23)\n";
  for (const auto& c :
       a.with_clay ? rve::composite_forcefield_commands(ff) : rve::polymer_forcefield_commands(ff))
    cmds += c + "\n";
  write_text_atomically(ffin, cmds);
  const double dmin = rve::min_nonbonded_distance(s);
  const auto L = s.length();
  std::cerr << fmt::format("pnc rve build: {} chains x {} beads, {} particles, box {:.3f} x {:.3f} "
                           "x {:.3f} A, density {:.4f} g/cm3, min non-bonded distance {:.3f} A\n",
                           a.spec.chains, a.spec.beads_per_chain, s.x.size(), L[0], L[1], L[2],
                           s.density(), dmin);
  if (a.with_clay)
    std::cerr << fmt::format("  clay: {} x {} cells, {} atoms, aspect ratio {:.2f}, volume "
                             "fraction {:.4f}, weight fraction {:.4f}\n",
                             a.clay.cells_a, a.clay.cells_b, ci.clay_atoms, ci.aspect_ratio,
                             ci.volume_fraction, ci.weight_fraction);
  std::cerr << "  data: " << data << "\n  record: " << rec << "\n  force field: " << ffin << "\n";
  if (a.json) {
    nlohmann::json j;
    j["command"] = "rve build";
    j["data"] = data;
    j["record"] = rec;
    j["atoms"] = s.x.size();
    j["density_g_cm3"] = s.density();
    j["box_A"] = {L[0], L[1], L[2]};
    j["min_nonbonded_distance_A"] = dmin;
    if (a.with_clay)
      j["clay"] = {{"cells_a", a.clay.cells_a},
                   {"cells_b", a.clay.cells_b},
                   {"clay_atoms", ci.clay_atoms},
                   {"aspect_ratio", ci.aspect_ratio},
                   {"volume_fraction", ci.volume_fraction},
                   {"weight_fraction", ci.weight_fraction}};
    std::cout << j.dump() << std::endl;
  }
  return 0;
}

struct LammpsArgs {
  int ranks = 0;
  std::string input, log;
  std::vector<std::string> vars;
};

/// Runs a LAMMPS input file in a supervised child (the same runner as every stage).
int run_rve_lammps(const LammpsArgs& a) {
  const rve::LauncherInfo li = rve::launcher_from_environment();
  if (li.rank > 0) return 0; // under mpirun: rank 0 runs the input on all K ranks
  rve::StageSpec s{"lammps " + a.input, a.log.empty() ? "log.lammps" : a.log, {}};
  s.ranks = a.ranks > 0 ? a.ranks : li.size;
  for (const auto& v : a.vars) {
    const auto eq = v.find('=');
    if (eq == std::string::npos || eq == 0)
      fail("<command line>", "--var", v, "must be NAME=VALUE");
    s.extra_args.insert(s.extra_args.end(), {"-var", v.substr(0, eq), v.substr(eq + 1)});
  }
  if (!fs::is_regular_file(a.input)) fail(a.input, "INPUT", a.input, "no such LAMMPS input file");
  const std::string in = fs::absolute(a.input).string();
  const auto o = rve::run_stage(s, [in](rve::Lammps& l) { l.file(in); });
  if (!o.ok) rve::throw_stage_failure(o, "input " + a.input); // ToolError: exit code 7
  std::cerr << fmt::format("pnc rve lammps: {} finished in {:.2f} s on {} rank(s) (log {})\n",
                           a.input, o.seconds, s.ranks, s.log_path);
  return 0;
}

struct RecipeShowArgs {
  std::string name;
  bool expanded = false, toml = false;
};

int run_recipe_show(const RecipeShowArgs& a) {
  nlohmann::json j = rve::preset_json(a.name);
  if (a.expanded) j = rve::expanded_json(rve::parse_recipe(j, "preset " + a.name));
  if (a.toml)
    std::cout << rve::recipe_toml(j);
  else
    std::cout << j.dump(2) << "\n";
  return 0;
}

struct CharacterizeArgs {
  std::string recipe, out;
  bool resume = false, json = false, no_plots = false;
  int jobs = 0, ranks = 0, equilibrate_ranks = 0;
};

/// MPI ranks per LAMMPS stage and cases at a time. Started as `mpirun -np K pnc ...`, rank 0
/// is the supervisor and runs every stage on K ranks (a fresh mpirun per stage, so a LAMMPS
/// error still ends only that stage); ranks 1..K-1 leave at once, freeing their cores.
/// Returns false on those follower ranks.
bool plan_parallelism(int cli_ranks, int cli_jobs, int recipe_jobs, int& ranks, int& jobs) {
  const rve::LauncherInfo li = rve::launcher_from_environment();
  if (li.rank > 0) return false;
  ranks = cli_ranks > 0 ? cli_ranks : li.size;
  jobs = cli_jobs > 0 ? cli_jobs : (li.size > 1 ? 1 : recipe_jobs);
  if (li.size > 1)
    std::cerr << fmt::format("pnc: started by mpirun with {} ranks: each LAMMPS stage runs on {} "
                             "rank(s), {} case(s) at a time\n",
                             li.size, ranks, jobs);
  const unsigned cores = std::thread::hardware_concurrency();
  if (cores > 0 && static_cast<unsigned>(ranks * jobs) > cores)
    std::cerr << fmt::format("pnc: warning: {} ranks x {} jobs = {} processes on {} cores\n", ranks,
                             jobs, ranks * jobs, cores);
  return true;
}

std::string preset_list() {
  std::string s;
  for (const auto& n : rve::preset_names())
    s += (s.empty() ? "" : ", ") + n;
  return s;
}

rve::Recipe load_recipe(const std::string& arg) {
  for (const auto& n : rve::preset_names())
    if (arg == n) return rve::parse_recipe(rve::preset_json(n), "preset " + n);
  if (!fs::is_regular_file(arg))
    fail(arg, "RECIPE", arg,
         "is neither a recipe file (.json, .toml) nor a preset name (" + preset_list() + ")");
  return rve::read_recipe(arg);
}

int run_characterize(const CharacterizeArgs& a) {
  using namespace pnc::damage;
  const auto t0 = std::chrono::steady_clock::now();
  const rve::Recipe r = load_recipe(a.recipe);
  int ranks = 1, jobs = 1;
  if (!plan_parallelism(a.ranks, a.jobs, r.jobs, ranks, jobs)) return 0;
  // The equilibration is one stage: give it all the cores the cases will share (ranks x
  // jobs, at most the machine's cores) unless told otherwise.
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  const int eq_ranks = a.equilibrate_ranks > 0
                           ? a.equilibrate_ranks
                           : std::max(ranks, cores > 0 ? std::min(ranks * jobs, cores) : ranks);
  // one process per run directory for the whole command (MD, fit, report); SIGINT/SIGTERM stop
  // the stages and leave the checkpoints for --resume (run_control.hpp, core/run_dir.hpp)
  const RunDirLock lock(a.out, command_line());
  const StopSignals signals;
  const rve::MdOutcome md = rve::run_md(r, a.out, a.resume, jobs, ranks, eq_ranks);

  // --- fit
  std::cerr << "pnc characterize [fit] " << md.cases_h5 << "\n";
  FitOptions o;
  // the bead-spring glass (model kg) is a pure polymer: the pure-polymer NDM (decision D138)
  // and the glass with a platelet (kg_platelet) a nanocomposite: the nanocomposite NDM (D175)
  o.model = parse_model(r.model == "kg"            ? std::string("pp")
                        : r.model == "kg_platelet" ? std::string("pnc")
                                                   : r.model,
                        md.recipe_path + ": model");
  // recipe fit_alpha = true always fits alpha; otherwise automatic (D12b). The MD pipeline
  // writes SI stresses itself, so an implausible stiffness is a verdict, not a unit mistake.
  o.alpha_mode = r.fit_alpha    ? AlphaMode::fit
                 : r.hold_alpha ? AlphaMode::hold
                                : AlphaMode::automatic;
  if (r.fit_alpha_start > 0) o.alpha = r.fit_alpha_start; // recipe fit.alpha (decision D138)
  o.strain_max = r.fit_strain_max;                        // recipe fit.strain_max (D12h)
  o.stretch_max = r.fit_stretch_max;                      // recipe fit.stretch_max (D12m)
  o.check_units = false;
  // decision D128: a material that relaxes within a hold does not define its shear and damage
  // constants; only the normal (bulk-like) block of C0 stays fitted
  if (md.phase.done && !md.phase.solid)
    for (const auto& n : constant_names(o.model))
      if (!(n.size() == 3 && n[0] == 'C' && n[1] <= '3' && n[2] <= '3'))
        o.undefined.push_back(
            {n, fmt::format("the phase check finds that the RVE relaxes within a hold (G_hold = "
                            "{:.3g} +- {:.2g} GPa; phase/phase.h5), so shear and damage "
                            "responses are not carried over a strain hold",
                            md.phase.G_hold_Pa * 1e-9, md.phase.G_hold_se_Pa * 1e-9)});
  o.validate();
  const StressStrainData data = read_stress_strain(md.cases_h5);
  const FitReport rep = fit_ndm(data, o);
  // decision D130: with >= 2 replicas every replica is fitted on its own as well
  const rve::ReplicaFits replica_fits = rve::fit_replicas(md.statistics, o);
  Card card = card_from_fit(rep, data, "none");
  // decision D130: the joint fit treats the points of the replica-mean curves as independent,
  // but a replica's deviations are correlated along its curves; the card's standard error of a
  // constant is the larger of the joint fit's and the between-replica one (t x sd/sqrt(N) of
  // the replicas' own fits), so that no reported error is smaller than the scatter between
  // independent RVEs says
  FitReport honest = rep;
  if (replica_fits.replicas >= 2) {
    int raised = 0;
    for (std::size_t j = 0; j < card.std_error.size() && j < replica_fits.se.size(); ++j) {
      if (!card.fitted[j] || !std::isfinite(replica_fits.se[j])) continue;
      const double between = replica_fits.coverage_factor * replica_fits.se[j];
      if (!(between <= card.std_error[j])) {
        card.std_error[j] = between;
        ++raised;
      }
    }
    honest.std_error = card.std_error;
    card.fit.error_model += fmt::format(
        "; per constant the larger of that and the between-replica standard error of {} "
        "separate replica fits (Student t factor {:.3g}; D130): {} constant(s) raised",
        replica_fits.replicas, replica_fits.coverage_factor, raised);
  }
  // decision D12k: with >= 3 replicas the residuals of the mean curves are correlated along
  // the curves; misfit is tested across replicas instead of by the runs test and chi^2 p
  const rve::ReplicaTrend trend = rve::replica_trend_test(md.statistics, rep, o.strain_max, o.stretch_max);
  if (trend.applicable) {
    static const char* kVoigt[6] = {"11", "22", "33", "23", "13", "12"};
    VerdictLimits limits;
    limits.independent_residuals = false;
    card.verdict = judge_fit(honest, limits);
    if (trend.p_family < limits.p_misfit) {
      const auto worst = std::min_element(
          trend.curves.begin(), trend.curves.end(),
          [](const rve::TrendCurve& x, const rve::TrendCurve& y) { return x.p < y.p; });
      card.verdict.warn(fmt::format(
          "the model misses a trend common to the {} replicas (case {} sigma{}: Legendre "
          "coefficients of the residuals against their between-replica errors, p = {:.2g}, "
          "Bonferroni over {} curves; D12k)",
          trend.replicas, worst->case_id, kVoigt[worst->component % 6], trend.p_family,
          trend.curves.size()));
    }
  }
  // decision D12f: what "usable" means for an MD card (replicas, chi^2/dof, relative errors,
  // points in the linear range)
  MdCardGates gates;
  gates.replicas = md.statistics.replicas;
  gates.deterministic = r.deform.temperature == 0;
  judge_md_card(honest, data, gates, card.verdict);
  const std::string card_path = (fs::path(a.out) / "card.h5").string();
  const std::string command =
      fmt::format("pnc characterize {} --out {}{}", a.recipe, a.out, a.resume ? " --resume" : "");
  write_card(card_path, card, command);
  // every figure of the run in one plotting process, after the card is written (a plotting
  // failure is a warning: the run and its report are complete without figures)
  CharacterizeRun run{r,
                      md,
                      data,
                      rep,
                      card,
                      replica_fits,
                      trend,
                      o.model,
                      a.out,
                      command,
                      read_clay_info(r, md),
                      0.0,
                      !a.no_plots,
                      {}};
  if (!a.no_plots) {
    const std::string plots = (fs::path(a.out) / "plots").string();
    make_output_directory(plots, "--out");
    run.plots = draw_figures(characterize_figures(r, md, data, card, plots),
                             (fs::path(plots) / "figures.json").string(), "pnc characterize");
  }
  const double total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.seconds = total_s;
  const std::string report_path = write_characterize_report(run);
  const std::string html_path = (fs::path(a.out) / "report.html").string();

  print_characterize_summary(run, card_path, report_path, html_path);
  if (a.json)
    std::cout << characterize_json(run, card_path, report_path, html_path).dump() << std::endl;
  if (card.verdict.level == VerdictLevel::not_usable) {
    std::cerr << "pnc: error: the card is NOT USABLE (reasons above); it was written, marked, "
                 "and the plugin refuses it unless the host allows unusable cards\n";
    return kExitNotUsable;
  }
  if (!rep.converged) {
    std::cerr << "pnc: error: the fit did not converge (" << rep.termination << "): " << rep.message
              << "; the card was written but check it before use\n";
    return pnc::exit_code::not_converged;
  }
  return 0;
}

} // namespace

void register_rve(CLI::App& app, Action& action) {
  auto* rve = app.add_subcommand("rve", "Coarse-grained PP RVE tools (LAMMPS, units real)");
  rve->require_subcommand(1);
  auto ba = std::make_shared<BuildArgs>();
  auto* build = rve->add_subcommand(
      "build", "Build a polymer (or polymer + clay) RVE: LAMMPS data file + HDF5 record");
  // Ranges as in BuildSpec::validate (which also caps chains x beads at 1e6).
  build->add_option("--chains", ba->spec.chains, "Number of chains (1 to 100000)")
      ->check(CLI::Range(1, 100000));
  build->add_option("--beads", ba->spec.beads_per_chain, "Beads per chain (4 to 10000)")
      ->check(CLI::Range(4, 10000));
  build->add_option("--density", ba->spec.density, "Target density (g/cm3, 0.05 to 3)")
      ->check(FiniteRange(0.05, 3.0, true));
  build->add_option("--seed", ba->spec.seed, "Random seed (1 to 900000000)")
      ->check(CLI::Range(1, 900000000));
  build
      ->add_option("--min-distance", ba->spec.min_distance,
                   "Minimum non-bonded distance (A, 0 to 4)")
      ->check(FiniteRange(0.0, 4.0, true));
  auto* clay_a = build->add_option("--clay-cells-a", ba->clay.cells_a,
                                   "Add a montmorillonite platelet of this many cells along x1");
  clay_a->check(CLI::Range(1, 1000));
  build->add_option("--clay-cells-b", ba->clay.cells_b, "Platelet cells along x3 (default 1)")
      ->needs(clay_a);
  build->add_option("--out", ba->out, "Output directory")->required();
  build->add_flag("--json", ba->json, "Print one JSON object on stdout");
  build->callback([ba, clay_a, &action] {
    ba->with_clay = clay_a->count() > 0;
    action = [ba] { return run_rve_build(*ba); };
  });

  auto la = std::make_shared<LammpsArgs>();
  auto* lmp = rve->add_subcommand(
      "lammps", "Run a LAMMPS input file in a supervised child process (errors from its log)");
  lmp->add_option("input", la->input, "LAMMPS input file")->required();
  lmp->add_option("--log", la->log, "LAMMPS log file (default log.lammps)");
  lmp->add_option("--var", la->vars, "LAMMPS index variable NAME=VALUE (repeatable)");
  lmp->add_option("--ranks", la->ranks, "MPI ranks (default 1; under mpirun -np K: K)")
      ->check(CLI::Range(1, 256));
  lmp->callback([la, &action] { action = [la] { return run_rve_lammps(*la); }; });

  auto* recipe = app.add_subcommand("recipe", "Recipes of pnc characterize");
  recipe->require_subcommand(1);
  auto rs = std::make_shared<RecipeShowArgs>();
  auto* show = recipe->add_subcommand("show", "Print a preset recipe (JSON)");
  show->add_option("name", rs->name, "Preset: " + preset_list())
      ->required()
      ->check(CLI::IsMember(rve::preset_names()));
  show->add_flag("--expanded", rs->expanded, "Print every field with its value");
  show->add_flag("--toml", rs->toml, "Print TOML instead of JSON (pnc characterize reads both)");
  show->callback([rs, &action] { action = [rs] { return run_recipe_show(*rs); }; });

  auto ca = std::make_shared<CharacterizeArgs>();
  auto* ch = app.add_subcommand(
      "characterize", "Recipe -> RVE build -> equilibration -> deformation cases (LAMMPS) -> "
                      "NDM fit -> card + plots + report");
  ch->add_option("recipe", ca->recipe,
                 "Recipe file (.json or .toml) or preset name (" + preset_list() + ")")
      ->required();
  ch->add_option("--out", ca->out, "Output directory")->required();
  ch->add_flag("--resume", ca->resume, "Continue a stopped run without recomputing finished steps");
  ch->add_option("--ranks", ca->ranks,
                 "MPI ranks of LAMMPS per stage (default 1; under mpirun -np K: K)")
      ->check(CLI::Range(1, 256));
  ch->add_option("--jobs", ca->jobs, "Cases run at the same time (default: the recipe's run.jobs)")
      ->check(CLI::Range(1, 64));
  ch->add_option("--equilibrate-ranks", ca->equilibrate_ranks,
                 "MPI ranks of the equilibration stages (default: ranks x jobs, at most the "
                 "machine's cores)")
      ->check(CLI::Range(1, 256));
  ch->add_flag("--no-plots", ca->no_plots, "Do not draw plots");
  ch->add_flag("--json", ca->json, "Print one JSON object with the key numbers on stdout");
  ch->callback([ca, &action] { action = [ca] { return run_characterize(*ca); }; });
}

} // namespace pnc::app
