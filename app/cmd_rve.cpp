// pnc rve build | pnc recipe show | pnc recipe parameters | pnc characterize: the RVE builder,
// recipes (presets and the declared keys) and the MD -> fit pipeline (docs/rve.md, docs/theory.md
// section 3). Units inside rve/: LAMMPS real; cases.h5 and cards in Pa.
#include "characterize.hpp"
#include "checks.hpp"
#include "cli_parameters.hpp"
#include "figures.hpp"
#include "registrars.hpp"
#include "report.hpp"
#include "run_control.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/moduli.hpp"
#include "pnc/md/builder.hpp"
#include "pnc/md/lammps_server.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/rve/characterize.hpp"
#include "pnc/rve/recipe.hpp"
#include "pnc/rve/replica_fits.hpp"
#include "pnc/rve/replica_trend.hpp"

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
  md::BuildSpec spec;
  rve::ClaySpec clay;
  bool with_clay = false;
  std::string out;
  bool json = false;
};

int run_rve_build(const BuildArgs& a) {
  const md::PolymerForceField ff;
  a.spec.validate("<command line>");
  if (a.with_clay) a.clay.validate("<command line>");
  make_output_directory(a.out);
  rve::CompositeInfo ci;
  const md::System s =
      a.with_clay ? rve::build_composite(a.spec, ff, a.clay, &ci) : md::build_polymer(a.spec, ff);
  const std::string data = (fs::path(a.out) / "rve.data").string();
  const std::string rec = (fs::path(a.out) / "build.h5").string();
  md::write_data_file(data, s,
                      a.with_clay ? "coarse-grained polypropylene + montmorillonite RVE"
                                  : "coarse-grained polypropylene RVE");
  write_build_record(rec, s, a.spec, ff, "{}");
  const std::string ffin = (fs::path(a.out) / "forcefield.lmp").string();
  std::string cmds =
      "# force field of docs/theory.md sections 3.1 (+ 3.2 for the clay), units real "
      "(decisions D13, D14, D23)\n";
  for (const auto& c :
       a.with_clay ? rve::composite_forcefield_commands(ff) : md::polymer_forcefield_commands(ff))
    cmds += c + "\n";
  write_text_atomically(ffin, cmds);
  const double dmin = md::min_nonbonded_distance(s);
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
    // SI as every --json (D238); the data file and build.h5 stay in LAMMPS real units (Å)
    using units::kg_m3_per_g_cm3;
    constexpr double m_per_A = units::m_per_angstrom;
    j["density_kg_per_m3"] = s.density() * kg_m3_per_g_cm3;
    j["box_m"] = {L[0] * m_per_A, L[1] * m_per_A, L[2] * m_per_A};
    j["min_nonbonded_distance_m"] = dmin * m_per_A;
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
  const md::LauncherInfo li = md::launcher_from_environment();
  if (li.rank > 0) return 0; // under mpirun: rank 0 runs the input on all K ranks
  md::StageSpec s{"lammps " + a.input, a.log.empty() ? "log.lammps" : a.log, {}};
  s.ranks = a.ranks > 0 ? a.ranks : li.size;
  for (const auto& v : a.vars) {
    const auto eq = v.find('=');
    if (eq == std::string::npos || eq == 0)
      fail("<command line>", "--var", v, "must be NAME=VALUE");
    s.extra_args.insert(s.extra_args.end(), {"-var", v.substr(0, eq), v.substr(eq + 1)});
  }
  if (!fs::is_regular_file(a.input)) fail(a.input, "INPUT", a.input, "no such LAMMPS input file");
  const std::string in = fs::absolute(a.input).string();
  const auto o = md::run_stage(s, [in](md::Lammps& l) { l.file(in); });
  if (!o.ok) md::throw_stage_failure(o, "input " + a.input); // ToolError: exit code 7
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

struct RecipeParametersArgs {
  std::string format = "markdown", model;
};

// `pnc recipe parameters`: the declared recipe keys (recipe_parameters.cpp) as Markdown tables
// (the generated region of docs/rve.md), JSON or a commented TOML template of one model.
/// `pnc recipe parameters` and `pnc characterize --print-parameters` (D358): the recipe keys of
/// one model ("all": every model; toml: pp) as Markdown, JSON or a commented TOML template.
std::string recipe_parameters_text(const std::string& format, const std::string& model) {
  const std::string variant = model == "all" ? "" : model;
  if (format == "toml") return rve::recipe_parameters(variant.empty() ? "pp" : variant).to_toml();
  if (format == "json") return rve::recipe_parameters(variant).to_json().dump(2) + "\n";
  return rve::recipe_parameters(variant).to_markdown(3);
}

int run_recipe_parameters(const RecipeParametersArgs& a) {
  std::cout << recipe_parameters_text(a.format, a.model);
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
  auto rp = std::make_shared<RecipeParametersArgs>();
  auto* params = recipe->add_subcommand(
      "parameters", "Print every recipe key: type, default, range, unit, meaning");
  params
      ->add_option("--format", rp->format,
                   "markdown (tables, default), json or toml (a "
                   "commented template with the defaults)")
      ->check(CLI::IsMember({"markdown", "json", "toml"}));
  params
      ->add_option("--model", rp->model,
                   "the keys of one model (pp, pnc, kg, kg_platelet) or of a recipe with your "
                   "own system (system); default all (toml: pp)")
      ->check(CLI::IsMember({"all", "pp", "pnc", "kg", "kg_platelet", "system"}));
  params->callback([rp, &action] { action = [rp] { return run_recipe_parameters(*rp); }; });

  auto ca = std::make_shared<CharacterizeArgs>();
  auto* ch = app.add_subcommand(
      "characterize", "Recipe -> RVE build -> equilibration -> deformation cases (LAMMPS) -> "
                      "NDM fit -> card + plots + report");
  ch->add_option("recipe", ca->recipe,
                 "Recipe file (.json or .toml) or preset name (" + preset_list() + ")")
      ->required();
  ch->add_option("--out", ca->out, "Output directory")->required();
  ch->add_flag("--resume", ca->resume,
               "Continue a stopped run: only the units that are not done run (or are submitted) "
               "again, from their checkpoints");
  ch->add_flag("--refit", ca->refit,
               "Fit a finished run again with the recipe's changed fit section (fit.strain_max, "
               "fit.isotropic, ...): nothing else of the recipe may change, every MD unit must be "
               "done; no MD runs, the card, report and summary are rewritten (D400)");
  ch->add_option("--ranks", ca->ranks,
                 "MPI ranks of LAMMPS per stage (default 1; under mpirun -np K: K)")
      ->check(CLI::Range(1, 256));
  // the recipe's run.jobs: checked by its declaration (D359)
  const Parameters recipe_keys = rve::recipe_parameters("");
  const Parameter& jobs = recipe_keys.at("run.jobs");
  bind_declared_option(ch->add_option("--jobs", ca->jobs,
                                      "local: units (equilibrations, cases) run at the same time "
                                      "(default: the recipe's run.jobs); " +
                                          jobs.rule()),
                       jobs);
  const Parameter& replicas = recipe_keys.at("run.replicas");
  bind_declared_option(
      ch->add_option("--replicas", ca->replicas,
                     "independent replicas (default: the recipe's run.replicas); with --resume a "
                     "larger number adds replicas to a run of >= 2 (the ones run are kept, the new "
                     "ones get their own seeds; D418); " +
                         replicas.rule()),
      replicas);
  ch->add_option("--equilibrate-ranks", ca->equilibrate_ranks,
                 "MPI ranks of the equilibration stages (default: ranks x jobs, at most the "
                 "machine's cores, shared by the equilibrations that run at once)")
      ->check(CLI::Range(1, 256));
  ch->add_option("--executor", ca->executor,
                 "Who runs the units: local (children of this process, --jobs at a time) or "
                 "slurm (sbatch job arrays with dependencies; docs/cluster.md)")
      ->check(CLI::IsMember({"local", "slurm"}));
  add_slurm_options(ch, ca->slurm, "the recipe");
  ch->add_flag("--no-plots", ca->no_plots, "Do not draw plots");
  ch->add_flag("--json", ca->json, "Print one JSON object with the key numbers on stdout");
  add_print_parameters_option(
      ch, [](const std::string& format) { return recipe_parameters_text(format, "all"); },
      "a recipe (toml: of model pp)"); // D358
  ch->callback([ca, &action] { action = [ca] { return run_characterize(*ca); }; });
  register_campaign(app, action); // pnc run-unit, pnc status
}

} // namespace pnc::app
