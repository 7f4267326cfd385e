// pnc rve build | pnc recipe show | pnc recipe parameters | pnc characterize: the RVE builder,
// recipes (presets and the declared keys) and the MD -> fit pipeline (docs/rve.md, docs/theory.md
// section 3). Units inside rve/: LAMMPS real; cases.h5 and cards in Pa.
#include "checks.hpp"
#include "plot.hpp"
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
  if (!o.ok) fail(s.log_path, "LAMMPS", a.input, o.error);
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
int run_recipe_parameters(const RecipeParametersArgs& a) {
  const std::string variant = a.model == "all" ? "" : a.model;
  if (a.format == "toml") {
    const std::string m = variant.empty() ? "pp" : variant;
    std::cout << rve::recipe_parameters(m).to_toml();
  } else if (a.format == "json") {
    std::cout << rve::recipe_parameters(variant).to_json().dump(2) << "\n";
  } else {
    std::cout << rve::recipe_parameters(variant).to_markdown(3);
  }
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

std::string code_block(const std::string& s) {
  return "```\n" + s + "```\n";
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
  const rve::ReplicaTrend trend = rve::replica_trend_test(md.statistics, rep, o.strain_max);
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
  std::vector<std::string> pngs;
  if (!a.no_plots)
    pngs = plot_fit(data, card.params, (fs::path(a.out) / "plots").string(),
                    fmt::format("MD ({}) and fitted NDM ({}) - card {}", r.name,
                                model_name(o.model), verdict_name(card.verdict.level)));
  const DerivedModuli dm = derive_moduli(card.params);
  const double total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // --- report
  const auto& e = md.equilibrated;
  std::string rep_md;
  rep_md += fmt::format("# pnc characterize: recipe `{}`\n\n", r.name);
  rep_md +=
      fmt::format("{} -- {} UTC. Command: `{}`.\n\n", version_string(), utc_timestamp(), command);
  rep_md += "## RVE\n\n";
  if (r.system.enabled) // your own system (rve/user_system.hpp)
    rep_md += rve::user_system_report(r.system);
  else if (r.model == "kg" || r.model == "kg_platelet")
    rep_md += fmt::format(
        "{} chains x {} beads ({} beads, {} g/mol), built at {} g/cm3, seed {}; glassy "
        "bead-spring polymer (FENE + LJ 12-6, sigma {} A, eps/k_B {:.0f} K, tau {:.0f} fs, "
        "stress unit eps/sigma^3 = {:.1f} MPa; decision D135).\n\n",
        r.build.chains, r.build.beads_per_chain, r.build.chains * r.build.beads_per_chain,
        r.kg.bead_mass, r.build.density, r.seed, r.kg.sigma, r.kg.temperature_unit(), r.kg.tau_fs(),
        r.kg.stress_unit_pa() * 1e-6);
  else
    rep_md += fmt::format("{} chains x {} beads ({} beads, 21 g/mol), built at {} g/cm3, seed {}; "
                          "force field of section 6.1 (decision D13 units).\n\n",
                          r.build.chains, r.build.beads_per_chain,
                          r.build.chains * r.build.beads_per_chain, r.build.density, r.seed);
  if (r.model == "kg_platelet") // what the builder wrote (platelet.json), decision D170
    rep_md += fmt::format(
        "Embedded platelet (decision D170): {0} x {0} x {1} beads at {2} sigma, normal x2, "
        "harmonic bond network K = {3} eps/sigma^2; platelet-polymer LJ eps_wp = {4} eps, "
        "sigma_wp = {5} sigma (record {6}).\n\n",
        r.platelet.beads_side, r.platelet.layers, r.platelet.spacing_sigma,
        r.platelet.bond_K_reduced, r.platelet.epsilon_wp_reduced, r.platelet.sigma_wp_sigma,
        (fs::path(md.build_record).parent_path() / "platelet.json").string());
  nlohmann::json clay_info; // what the builder wrote (clay.json next to build.h5), model pnc
  if (r.model == "pnc") {
    const auto cp = fs::path(md.build_record).parent_path() / "clay.json";
    std::ifstream cf(cp);
    if (cf) clay_info = nlohmann::json::parse(cf, nullptr, false);
    if (clay_info.is_object() && !clay_info.is_discarded())
      rep_md += fmt::format(
          "Montmorillonite platelet (C2/m cell, Table 3.1): {} x {} cells, {} atoms, {:.2f} x "
          "{:.2f} x {:.2f} A (aspect ratio {:.2f}); clay volume fraction {:.4f}, weight fraction "
          "{:.4f} (definitions in {}).\n\n",
          clay_info.value("cells_a", 0), clay_info.value("cells_b", 0),
          clay_info.value("clay_atoms", 0), clay_info.value("platelet_length_A", 0.0),
          clay_info.value("platelet_width_A", 0.0), clay_info.value("platelet_thickness_A", 0.0),
          clay_info.value("aspect_ratio_length_over_width", 0.0),
          clay_info.value("volume_fraction", 0.0), clay_info.value("weight_fraction", 0.0),
          fs::relative(cp, a.out).string());
    else
      rep_md += fmt::format("Clay record {} is missing or unreadable.\n\n", cp.string());
  }
  rep_md += "Equilibration (one line per stage, with the criterion that ended it):\n\n";
  for (const auto& c : e.criteria)
    rep_md += "- " + c + "\n";
  rep_md += fmt::format(
      "\n| equilibrated RVE | value |\n|---|---|\n| ensemble | {} |\n| density | {:.4f} g/cm3 |\n"
      "| pressure (with kinetic term) | {:.0f} +- {:.0f} atm |\n| pressure (virial only) | {:.0f} "
      "atm |\n"
      "| temperature | {:.1f} K |\n| void fraction (1 A grid, farther than sigma from every bead) "
      "| {:.4f} |\n"
      "| smallest pair distance | {:.3f} A |\n\n",
      r.system.enabled ? std::string("user stages") : r.equilibrate.ensemble, e.density,
      e.pressure_total, e.pressure_total_se, e.pressure_virial, e.temperature, e.void_fraction,
      e.min_distance);
  if (md.phase.done) rep_md += rve::phase_markdown(md.phase);
  rep_md += fmt::format(
      "Deformation: cases {}, strain 0 -> {} in {} steps, {}. Stress handed to the fit: {}.\n\n",
      nlohmann::json(r.cases).dump(), r.deform.strain_max, r.deform.steps,
      r.deform.temperature == 0 // static rows (decision D120)
          ? std::string("static at 0 K (no hold)")
          : fmt::format("hold {} steps of {} fs, samples every {} steps", r.deform.hold_steps,
                        r.deform.timestep_fs, r.deform.sample_every),
      data.stress_definition);
  rep_md += md.statistics_markdown; // error method, replicas, block check (D130-D134)
  rep_md += "## Fitted constants\n\n" + code_block(constants_table(card));
  rep_md += rve::replica_fits_markdown(replica_fits, rep);
  rep_md += rve::replica_trend_markdown(trend);
  rep_md += "\n## Fit quality and the dissertation's tables\n\n" +
            code_block(fit_tables(card.fit, o.model));
  rep_md +=
      fmt::format("\n## Derived moduli\n\n| quantity | this run | dissertation |\n|---|---|---|\n"
                  "| E (eq. 6.47, pure polymer) | {:.3f} GPa | 0.162 GPa (Table 6.12) |\n"
                  "| E by inversion of C0 (E1) | {:.3f} GPa | -- |\n| nu12 | {:.3f} | -- |\n"
                  "| G12 | {:.3f} GPa | 0.109 GPa (C44, Table 6.11) |\n\n",
                  dm.E_eq647 * 1e-9, dm.E1 * 1e-9, dm.nu12, dm.G12 * 1e-9);
  rep_md += fmt::format("Solver: {} after {} iterations; {}\n\n", rep.termination, rep.iterations,
                        rep.converged ? "converged" : "NOT converged");
  rep_md += fmt::format("## Verdict: {}\n\n", verdict_name(card.verdict.level));
  for (const auto& reason : card.verdict.reasons)
    rep_md += "- " + reason + "\n";
  rep_md += card.verdict.level == VerdictLevel::not_usable
                ? "\nThis card is NOT USABLE: the fe_material plugin refuses it unless the host "
                  "allows unusable cards explicitly.\n\n"
                : "\n";
  if (!pngs.empty()) {
    rep_md += "## Plots\n\n";
    for (const auto& p : pngs)
      rep_md += fmt::format("![{0}]({0})\n", fs::relative(p, a.out).string());
  }
  rep_md += fmt::format(
      "\nWall time: build {:.1f} s, equilibration {:.1f} s, phase check {:.1f} s, "
      "cases {:.1f} s, total {:.1f} s (this invocation).\n",
      md.seconds_build, md.seconds_equilibrate, md.seconds_phase, md.seconds_cases, total_s);
  const std::string report_path = (fs::path(a.out) / "report.md").string();
  write_text_atomically(report_path, rep_md);

  std::cerr << constants_table(card) << fit_tables(card.fit, o.model) << verdict_text(card.verdict);
  std::cerr << fmt::format("pnc characterize: equilibrated density {:.4f} g/cm3, P {:.0f} atm, "
                           "void fraction {:.4f}; E (eq. 6.47) {:.3f} GPa\n",
                           e.density, e.pressure_total, e.void_fraction, dm.E_eq647 * 1e-9);
  if (md.phase.done)
    std::cerr << "pnc characterize: phase check: " << md.phase.phase
              << (md.phase.solid ? "" : " -- shear and damage constants held as not identified")
              << "\n";
  std::cerr << "  cases: " << md.cases_h5 << "\n  card: " << card_path
            << "\n  report: " << report_path << "\n";
  for (const auto& p : pngs)
    std::cerr << "  plot: " << p << "\n";
  std::cerr << fmt::format("  wall time {:.1f} s\n", total_s);
  if (a.json) {
    nlohmann::json j;
    j["command"] = "characterize";
    j["recipe"] = r.name;
    j["out"] = a.out;
    j["cases_h5"] = md.cases_h5;
    j["card"] = card_path;
    j["report"] = report_path;
    j["plots"] = pngs;
    j["equilibrated"] = {
        {"ensemble", r.system.enabled ? std::string("user stages") : r.equilibrate.ensemble},
        {"density_g_cm3", e.density},
        {"pressure_atm", e.pressure_total},
        {"pressure_stderr_atm", e.pressure_total_se},
        {"pressure_virial_atm", e.pressure_virial},
        {"temperature_K", e.temperature},
        {"void_fraction", e.void_fraction},
        {"min_distance_A", e.min_distance}};
    if (clay_info.is_object() && !clay_info.is_discarded()) j["clay"] = clay_info;
    if (md.phase.done) j["phase_check"] = rve::phase_json(md.phase);
    j["constants"] = constants_json(card);
    j["fit"] = fit_json(card.fit);
    j["verdict"] = verdict_json(card.verdict);
    j["statistics"] = rve::statistics_json(md.statistics); // error model, D130-D134
    j["moduli"] = {{"E_eq647_Pa", num(dm.E_eq647)}, {"E1_Pa", num(dm.E1)}, {"G12_Pa", num(dm.G12)}};
    j["seconds"] = {{"build", md.seconds_build},
                    {"equilibrate", md.seconds_equilibrate},
                    {"phase_check", md.seconds_phase},
                    {"cases", md.seconds_cases},
                    {"total", total_s}};
    std::cout << j.dump() << std::endl;
  }
  if (card.verdict.level == VerdictLevel::not_usable) {
    std::cerr << "pnc: error: the card is NOT USABLE (reasons above); it was written, marked, "
                 "and the plugin refuses it unless the host allows unusable cards\n";
    return kExitNotUsable;
  }
  if (!rep.converged) {
    std::cerr << "pnc: error: the fit did not converge (" << rep.termination << "): " << rep.message
              << "; the card was written but check it before use\n";
    return 3;
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
