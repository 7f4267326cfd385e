// pnc thermo ti: free energy of deformation by thermodynamic integration, run as a plan of
// units (decisions D285-D289, docs/thermo.md, docs/cluster.md): one unit per (state, lambda
// node) writing <state>/lambda_<i>.h5, then the join unit `analysis` (ti.h5, plots, report,
// summary.json), by the local executor or through Slurm like `pnc characterize`. Units: LAMMPS
// real (kcal/mol, A, fs, K); moduli in Pa.
#include "campaign_driver.hpp"
#include "cli_parameters.hpp"
#include "run_control.hpp"
#include "thermo_cli.hpp"
#include "thermo_report.hpp"

#include "pnc/campaign/campaign.hpp"
#include "pnc/campaign/executor.hpp"
#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/run_log.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/units.hpp"
#include "pnc/md/builder.hpp"
#include "pnc/rve/bead_spring.hpp"
#include "pnc/rve/equilibrate.hpp"
#include "pnc/rve/recipe.hpp"
#include "pnc/thermo/ti.hpp"
#include "pnc/thermo/ti_parameters.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace pnc::app {

namespace {

namespace fs = std::filesystem;

const char* const kCommand = "thermo ti";

struct TiArgs {
  thermo::TiSpec spec; ///< the options' values (a file's keys where not given: resolve_input)
  std::string input;   ///< --input: a TI input file (thermo/ti_parameters.hpp), "" none
  std::vector<std::string> given; ///< the declared keys whose option was given (D301)
  std::string from, restart, out, vol = "0,0.00125,0.0025,0.00375,0.005",
                                  dev = "0,0.00125,0.0025,0.00375,0.005";
  bool demo = false, resume = false, json = false, no_plots = false;
  std::string executor = "local"; ///< "local" or "slurm"
  SlurmOptions slurm;
};

/// `<from>/recipe.json`: the recipe of a `--from` run.
std::string from_recipe_path(const TiArgs& a) {
  return (fs::path(a.from) / "recipe.json").string();
}

/// The recipe of a `--from` run (read once; std::nullopt without --from or when the file is
/// missing: start_state names what is missing).
std::optional<rve::Recipe> from_recipe(const TiArgs& a) {
  const std::string rp = from_recipe_path(a);
  if (a.from.empty() || !fs::is_regular_file(rp)) return std::nullopt;
  return rve::read_recipe(rp);
}

/// The equilibrated start state and the force-field commands; `recipe` is from_recipe(a).
std::pair<std::string, std::vector<std::string>>
start_state(const TiArgs& a, const std::optional<rve::Recipe>& recipe) {
  const int given = (a.from.empty() ? 0 : 1) + (a.restart.empty() ? 0 : 1) + (a.demo ? 1 : 0);
  if (given != 1)
    fail("<command line>", "--from/--restart/--demo", "",
         "give exactly one source of the equilibrated RVE");
  if (!a.restart.empty()) {
    if (!fs::is_regular_file(a.restart))
      fail(a.restart, "--restart", a.restart, "no such LAMMPS restart file");
    return {a.restart, md::polymer_forcefield_commands({})};
  }
  if (!a.from.empty()) {
    const std::string rp = from_recipe_path(a);
    const std::string rs = (fs::path(a.from) / "equilibrate" / "final.restart").string();
    if (!recipe)
      fail(a.from, "--from", a.from, "is not a `pnc characterize` output (no recipe.json)");
    if (!fs::is_regular_file(rs))
      fail(rs, "--from", a.from, "has no equilibrated state (equilibrate/final.restart)");
    const rve::Recipe& r = *recipe;
    if (r.model != "pp" && r.model != "kg")
      fail(rp, "model", r.model,
           "thermo ti ramps a single-type LJ (models pp and kg); the composites (models pnc and "
           "kg_platelet) are not supported yet");
    if (r.system.enabled) { // the built-in force field would be applied to the user's atoms
      std::string field = "system", value = r.system.input_file;
      std::string why = "thermo ti works on the built-in polymer force field; a run of your own "
                        "system (recipe \"system\", docs/rve.md) is not supported yet";
      for (const auto& c : r.system.forcefield) // D394: name a Coulomb pair and the rule
        if (c.rfind("kspace_style", 0) == 0 ||
            (c.rfind("pair_style", 0) == 0 && c.find("coul") != std::string::npos)) {
          field = "system.forcefield";
          value = c;
          why = "thermo ti replaces the pair style by one lj/cut ramped over lambda (D62); "
                "long-range Coulomb (a kspace partner) cannot be scaled by it (D394); system " +
                r.system.input_file;
          break;
        }
      fail(rp, field, value, why);
    }
    if (r.model == "kg") return {rs, rve::bead_spring_commands(r.kg)}; // D393
    return {rs, md::polymer_forcefield_commands(r.ff)};
  }
  // --demo: build and equilibrate the demo RVE (rve/ API) under <out>/rve
  const rve::Recipe r = rve::parse_recipe(rve::preset_json("demo"), "preset demo");
  const fs::path d = fs::path(a.out) / "rve";
  make_output_directory(d.string());
  const std::string data = (d / "rve.data").string();
  if (!(a.resume && fs::exists(data))) {
    std::cerr << fmt::format("pnc thermo ti [demo RVE] building {} chains x {} beads\n",
                             r.build.chains, r.build.beads_per_chain);
    const md::System s = md::build_polymer(r.build, r.ff);
    md::write_data_file(data, s, "pnc thermo ti demo");
  }
  std::cerr << "pnc thermo ti [demo RVE] equilibrating (recipe demo)\n";
  const auto e = rve::equilibrate(data, r.ff, r.equilibrate, (d / "equilibrate").string(), a.resume,
                                  rve::expanded_json(r).dump(), false);
  std::cerr << fmt::format("  equilibrated: density {:.4f} g/cm3, P {:.0f} atm\n", e.density,
                           e.pressure_total);
  return {e.restart, md::polymer_forcefield_commands(r.ff)};
}

nlohmann::json spec_json(const thermo::TiSpec& s) {
  return {{"rule", s.rule},
          {"points", s.points},
          {"vol", s.vol},
          {"dev", s.dev},
          {"eps0_kcal_mol", s.path.eps0},
          {"eps1_kcal_mol", s.path.eps1},
          {"sig0_A", s.path.sig0},
          {"sig1_A", s.path.sig1},
          {"cutoff_A", s.path.cutoff},
          {"timestep_fs", s.sampling.timestep_fs},
          {"equil_steps", s.sampling.equil_steps},
          {"prod_steps", s.sampling.prod_steps},
          {"sample_every", s.sampling.sample_every},
          {"blocks", s.sampling.blocks},
          {"temperature_K", s.sampling.temperature},
          {"damp_fs", s.damp_fs},
          {"seed", s.seed},
          {"fd_h", s.fd_h},
          {"dhdl_method", s.dhdl_method}};
}

/// The spec a run folder holds (ti_spec.json, written by spec_json): what every unit runs.
thermo::TiSpec spec_from_json(const nlohmann::json& j, const std::string& source) {
  thermo::TiSpec s;
  try {
    s.rule = j.at("rule").get<std::string>();
    s.points = j.at("points").get<int>();
    s.vol = j.at("vol").get<std::vector<double>>();
    s.dev = j.at("dev").get<std::vector<double>>();
    s.path.eps0 = j.at("eps0_kcal_mol").get<double>();
    s.path.eps1 = j.at("eps1_kcal_mol").get<double>();
    s.path.sig0 = j.at("sig0_A").get<double>();
    s.path.sig1 = j.at("sig1_A").get<double>();
    s.path.cutoff = j.at("cutoff_A").get<double>();
    s.sampling.timestep_fs = j.at("timestep_fs").get<double>();
    s.sampling.equil_steps = j.at("equil_steps").get<long>();
    s.sampling.prod_steps = j.at("prod_steps").get<long>();
    s.sampling.sample_every = j.at("sample_every").get<int>();
    s.sampling.blocks = j.at("blocks").get<int>();
    s.sampling.temperature = j.at("temperature_K").get<double>();
    s.damp_fs = j.at("damp_fs").get<double>();
    s.seed = j.at("seed").get<std::uint64_t>();
    s.fd_h = j.at("fd_h").get<double>();
    s.dhdl_method = j.at("dhdl_method").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    fail(source, "", "", std::string("is not a pnc thermo ti spec: ") + e.what());
  }
  s.validate(source);
  return s;
}

std::string spec_path(const std::string& dir) {
  return (fs::path(dir) / "ti_spec.json").string();
}

std::string read_text(const std::string& path) {
  std::ifstream f(path);
  if (!f) fail(path, "", "", "cannot read the file");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string summary_file(const std::string& dir) {
  return (fs::path(dir) / "summary.json").string();
}

/// The unit id of a point: "<state id>/lambda_<i>" with the state id's '.' as 'p' and '-' as
/// 'm' (unit ids are [a-z0-9_] parts), e.g. "vol_0p00125/lambda_1" (D285).
std::string point_unit_id(const thermo::TiPoint& p) {
  std::string s;
  for (char c : p.state.id) {
    const char l = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    s += l == '.' ? 'p' : l == '-' ? 'm' : l == '+' ? 'p' : (std::isalnum(l) ? l : '_');
  }
  return fmt::format("{}/lambda_{}", s, p.node);
}

std::string relative_to(const std::string& path, const std::string& dir) {
  return fs::path(path).lexically_relative(dir).string();
}

/// The plan: every point (one group, one Slurm array), then the join unit `analysis`.
campaign::Plan ti_plan(const thermo::TiSpec& spec, const std::string& dir,
                       const nlohmann::json& parameters) {
  campaign::Plan p;
  p.command = kCommand;
  p.parameters = parameters;
  campaign::Unit an{"analysis", "analysis", "analysis", {}, true, 1, {}, {}};
  for (const auto& pt : thermo::ti_points(spec, dir)) {
    // D324: each point's LAMMPS on spec.ranks MPI ranks (Slurm: --ntasks of its job)
    campaign::Unit u{
        point_unit_id(pt), "lambda_point", "lambda_points", {}, false, spec.ranks, {}, {}};
    u.inputs = {"ti_spec.json"};
    u.outputs = {relative_to(pt.job.h5, dir)};
    an.needs.push_back(u.id);
    an.inputs.push_back(u.outputs.front());
    p.units.push_back(u);
  }
  an.outputs = {"ti.h5", "report.html", "summary.json"};
  p.units.push_back(an);
  return p;
}

/// D286: a point is done exactly when its file exists (the file is its checkpoint, written
/// atomically, as --resume has always read it): a point file without a done state (an earlier
/// run, a unit that ended between writing it and its state) is recorded done, a done state
/// whose file is gone is cleared, so the point runs again.
void sync_point_states(const std::string& dir, const thermo::TiSpec& spec) {
  for (const auto& pt : thermo::ti_points(spec, dir)) {
    const std::string id = point_unit_id(pt);
    campaign::UnitStatus s = campaign::read_status(dir, id);
    const bool have = fs::exists(pt.job.h5);
    if (have && s.state != campaign::UnitState::done &&
        !(s.state == campaign::UnitState::running && !s.job_id.empty())) {
      s.state = campaign::UnitState::done;
      s.message = "its lambda file exists (reused)";
      s.detail = {{"h5", pt.job.h5}, {"reused", true}};
      campaign::write_status(dir, id, s);
    } else if (!have && s.state == campaign::UnitState::done) {
      campaign::clear_status(dir, id);
    }
  }
}

struct TiReportArgs {
  thermo::TiSpec spec;
  std::string out, command_line;
  bool no_plots = false;
};

/// The report of a finished TI (stderr lines, plots, report.html); returns the --json object.
nlohmann::json report_ti(const TiReportArgs& a, const thermo::TiResult& r) {
  std::cerr << "\n  state            dA = A(1) - A(0) (kcal/mol)     <dH/dl> at the nodes\n";
  double worst_fd = 0;
  for (const auto& st : r.states) {
    std::string nodes;
    for (const auto& p : st.ti.points) {
      nodes += fmt::format(" {:.3f}+-{:.3f}", p.dhdl.value, p.dhdl.se);
      if (p.checks.count("fd_dhdl_lammps"))
        worst_fd =
            std::max(worst_fd, std::fabs(p.checks.at("fd_dhdl_lammps") - p.checks.at("dhdl_pnc")) /
                                   std::max(1e-12, std::fabs(p.checks.at("dhdl_pnc"))));
    }
    std::cerr << fmt::format("  {:<14} {:>10.4f} +- {:.4f}          {}\n", st.state.id,
                             st.ti.dA.value, st.ti.dA.se, nodes);
  }
  std::cerr << fmt::format("  finite-difference check of dH/dl against LAMMPS's pair energy: "
                           "largest relative difference {:.2e}\n",
                           worst_fd);
  for (const auto& f : r.fits)
    if (std::isfinite(f.modulus))
      std::cerr << fmt::format(
          "  {} response (docs/theory.md §4.4, of A(1) - A(0)): {} = {:.3g} +- {:.2g} "
          "GPa (quadratic fit, V0 {:.0f} A^3)\n",
          f.kind, f.kind == "vol" ? "K" : "mu", f.modulus * 1e-9, f.modulus_se * 1e-9, f.v0);
  std::vector<std::string> pngs;
  ThermoRun rep{a.command_line, a.out, r.h5, 0, !a.no_plots, {}, {}, {}};
  if (!a.no_plots) {
    std::ostringstream c1, c2;
    c1.precision(12);
    c2.precision(12);
    // SI by the unit rule of every CSV (docs/formats.md): energies of the whole box in J
    const double J = units::joule_per_kcal_mol;
    c1 << "state,lambda,dhdl_J,dhdl_se_J\n";
    c2 << "kind,strain,strain_measure,dA_J,dA_se_J\n";
    for (const auto& st : r.states) {
      for (const auto& p : st.ti.points)
        c1 << st.state.id << ',' << p.lambda << ',' << p.dhdl.value * J << ',' << p.dhdl.se * J
           << '\n';
      for (const char* k : {"vol", "dev"})
        if (st.state.kind == k || st.state.kind == "ref") {
          const bool in = st.state.kind == "ref"
                              ? !(std::string(k) == "vol" ? a.spec.vol : a.spec.dev).empty()
                              : true;
          if (!in) continue;
          const double m = std::string(k) == "vol" ? 3 * st.state.strain : st.state.strain;
          c2 << k << ',' << st.state.strain << ',' << m << ',' << st.ti.dA.value * J << ','
             << st.ti.dA.se * J << '\n';
        }
    }
    const fs::path pd = fs::path(a.out) / "plots";
    make_output_directory(pd.string());
    write_text_atomically((pd / "dhdl.csv").string(), c1.str());
    write_text_atomically((pd / "dA.csv").string(), c2.str());
    pngs = run_plot({"ti", (pd / "dhdl.csv").string(), (pd / "dA.csv").string(), pd.string()}, rep);
  }
  std::cerr << "  results: " << r.h5 << "\n";
  for (const auto& p : pngs)
    std::cerr << "  plot: " << p << "\n";
  rep.seconds = r.seconds;
  const std::string report = write_ti_report(rep, a.spec, r, worst_fd);
  std::cerr << "  report: " << report << "\n";
  std::cerr << fmt::format("  wall time {:.1f} s\n", r.seconds);
  return ti_json(rep, a.spec, r, report, worst_fd); // SI keys (D280)
}

/// Runs one unit of a `thermo ti` plan in this process (PlanUnitRunner).
int ti_unit_main(const std::string& dir, const campaign::Plan& p, const campaign::Unit& u,
                 bool print_errors) {
  return guarded_unit(u, print_errors, [&] {
    const std::string sj = read_text(spec_path(dir));
    const auto j = nlohmann::json::parse(sj, nullptr, false);
    if (j.is_discarded()) fail(spec_path(dir), "", "", "is not valid JSON");
    thermo::TiSpec spec = spec_from_json(j, spec_path(dir));
    spec.ranks = u.ranks; // the plan's, not ti_spec.json's (D324)
    const auto restart = p.parameters.value("restart", std::string());
    const auto ff = p.parameters.value("ff", std::vector<std::string>{});
    if (u.kind == "lambda_point") {
      for (const auto& pt : thermo::ti_points(spec, dir))
        if (point_unit_id(pt) == u.id) {
          fs::path log(pt.job.h5);
          log.replace_extension(".log");
          campaign::run_unit_recorded(
              dir, u,
              [&] {
                thermo::run_ti_point(spec, pt, restart, ff, pnc::print_progress);
                const thermo::PointResult r = thermo::read_point(pt.job.h5);
                return nlohmann::json{{"h5", pt.job.h5},
                                      {"dhdl_kcal_mol", jnum(r.dhdl.value)},
                                      {"dhdl_stderr_kcal_mol", jnum(r.dhdl.se)}};
              },
              log.string());
          return 0;
        }
      fail(campaign::plan_path(dir), "unit", u.id, "names no point of the spec in ti_spec.json");
    }
    if (u.kind != "analysis")
      fail(campaign::plan_path(dir), u.id + ".kind", u.kind, "unknown kind");
    campaign::run_unit_recorded(dir, u, [&] {
      std::vector<std::string> missing;
      for (const auto& pt : thermo::ti_points(spec, dir))
        if (!fs::exists(pt.job.h5))
          missing.push_back(point_unit_id(pt) + " (" + relative_to(pt.job.h5, dir) + ")");
      if (!missing.empty())
        fail(dir, "analysis", fmt::format("{} missing", missing.size()),
             fmt::format("the lambda point(s) {} did not finish: rerun with --resume (pnc status "
                         "{} says why)",
                         fmt::join(missing, ", "), dir));
      const double t0 = p.parameters.value("started_s", campaign::epoch_seconds());
      const thermo::TiResult r =
          thermo::finish_ti(spec, dir, sj, std::max(0.0, campaign::epoch_seconds() - t0));
      const TiReportArgs ra{spec, dir, p.parameters.value("command_line", std::string()),
                            p.parameters.value("no_plots", false)};
      write_text_atomically(summary_file(dir), report_ti(ra, r).dump() + "\n");
      return nlohmann::json{{"exit_code", 0}, {"summary", summary_file(dir)}, {"h5", r.h5}};
    });
    return 0;
  });
}

/// After the executor: the analysis's summary (--json), or the failures.
int conclude_ti(const TiArgs& a, const campaign::Plan& p, const std::vector<std::string>& failed,
                const std::vector<std::string>& not_run) {
  throw_unless_final_done({kCommand, a.out, "analysis", a.json}, p, failed, not_run);
  if (a.json) std::cout << read_text(summary_file(a.out)) << std::flush;
  return 0;
}

/// D301: the TI settings of this run: the --input file's keys (defaults without one), each
/// key whose option was given explicitly taken from the command line instead.
thermo::TiInput resolve_input(const TiArgs& a) {
  thermo::TiInput cli;
  cli.spec = a.spec;
  cli.spec.vol = parse_list(a.vol, "--vol");
  cli.spec.dev = parse_list(a.dev, "--dev");
  cli.executor = a.executor;
  cli.slurm.partition = a.slurm.partition;
  cli.slurm.account = a.slurm.account;
  cli.slurm.time = a.slurm.time;
  cli.slurm.template_path = a.slurm.sbatch_template;
  cli.slurm.mpi = a.slurm.mpi; // D332
  thermo::TiInput in = a.input.empty() ? thermo::TiInput{} : thermo::read_ti_input(a.input);
  thermo::override_ti_input(in, cli, a.given);
  in.spec.validate(a.input.empty() ? "<command line>" : a.input + " with the command line");
  return in;
}

/// Whether `key` was set on the command line or in the --input file (not defaulted).
bool key_set(const TiArgs& a, const thermo::TiInput& in, const std::string& key) {
  const auto has = [&](const std::vector<std::string>& v) {
    return std::find(v.begin(), v.end(), key) != v.end();
  };
  return has(a.given) || has(in.file_keys);
}

/// D393: a glass (`--from` a run of model kg): the lambda = 1 end is the glass's own pair and
/// the TI runs at the glass's temperature. The keys eps1, sig1, cutoff and temperature not set
/// (option or file) take the recipe's values, eps0 and sig0 the dissertation's ratios to them
/// (LjPath defaults: eps0/eps1 = 0.1, sig0/sig1 = 0.95/2.95); a set eps1, sig1 or cutoff that
/// differs from the glass's pair is refused (the TI would end on another system).
void adapt_to_glass(TiArgs& a, const thermo::TiInput& in,
                    const std::optional<rve::Recipe>& recipe) {
  if (!recipe || recipe->model != "kg") return; // start_state names what is missing
  const rve::Recipe& r = *recipe;
  const std::string rp = from_recipe_path(a);
  const thermo::LjPath d; // the dissertation's path, for the ratios
  auto end = [&](const char* key, double& v, double glass, const char* unit) {
    if (!key_set(a, in, key)) {
      v = glass;
      return;
    }
    if (std::fabs(v - glass) > 1e-9 * std::fabs(glass))
      fail(a.input.empty() ? "<command line>" : a.input + " with the command line", key,
           fmt::format("{}", v),
           fmt::format("must be the glass's own value {:.10g} {} ({}: forcefield of model kg): "
                       "lambda = 1 is the glass (D393); leave the key out",
                       glass, unit, rp));
  };
  end("eps1", a.spec.path.eps1, r.kg.epsilon, "kcal/mol");
  end("sig1", a.spec.path.sig1, r.kg.sigma, "A");
  end("cutoff", a.spec.path.cutoff, r.kg.cutoff(), "A");
  if (!key_set(a, in, "eps0")) a.spec.path.eps0 = a.spec.path.eps1 * d.eps0 / d.eps1;
  if (!key_set(a, in, "sig0")) a.spec.path.sig0 = a.spec.path.sig1 * d.sig0 / d.sig1;
  if (!key_set(a, in, "temperature")) a.spec.sampling.temperature = r.equilibrate.temperature;
  a.spec.validate(rp + " with the TI settings");
}

int run_thermo_ti(TiArgs a) {
  const thermo::TiInput in = resolve_input(a);
  a.spec = in.spec;
  const std::optional<rve::Recipe> recipe = from_recipe(a); // read once (--from)
  adapt_to_glass(a, in, recipe);
  a.executor = in.executor;
  // D333: as pnc characterize: under `mpirun -np K` rank 0 supervises with --ranks K and
  // --jobs 1 unless set (option or file key), the other ranks leave; ranks x jobs > cores warns
  if (!plan_parallelism(key_set(a, in, "ranks") ? in.spec.ranks : 0,
                        key_set(a, in, "jobs") ? in.spec.jobs : 0, in.spec.jobs, a.spec.ranks,
                        a.spec.jobs))
    return 0;
  const RunDirLock lock(a.out, command_line()); // one process per run directory
  start_run_log(a.out, command_line());         // pnc.log: what this run printed
  const StopSignals signals;                    // SIGINT/SIGTERM: finished points are kept
  // one spec per output directory: --resume must not mix protocols
  const std::string sj = spec_json(a.spec).dump(2) + "\n";
  const std::string sp = spec_path(a.out);
  if (fs::exists(sp)) {
    if (read_text(sp) != sj)
      fail(sp, "--out", a.out,
           "holds a TI with other settings; use a new --out directory (or the same settings)");
    refuse_existing_run(a.out, a.resume, {"ti_spec.json"});
  }
  if (fs::exists(campaign::plan_path(a.out)) && campaign::read_plan(a.out).command != kCommand)
    fail(campaign::plan_path(a.out), "--out", a.out,
         "holds the plan of another command; use a new --out directory");
  const auto [restart, ff] = start_state(a, recipe);
  thermo::check_ti_start(a.spec, restart);
  thermo::check_ti_pair_style(restart, a.out, a.spec.ranks); // D394: before any point runs
  const double started = campaign::epoch_seconds(); // the wall time of the TI, as before the plan
  write_text_atomically(sp, sj);
  const auto states = thermo::ti_states(a.spec);
  std::cerr << fmt::format("pnc thermo ti: {} state(s) x {} lambda point(s) ({} rule), {} + {} "
                           "steps of {} fs per point, dH/dl every {} steps; start state {}\n",
                           states.size(), a.spec.points, a.spec.rule, a.spec.sampling.equil_steps,
                           a.spec.sampling.prod_steps, a.spec.sampling.timestep_fs,
                           a.spec.sampling.sample_every, restart);
  const nlohmann::json params = {{"restart", fs::absolute(restart).string()},
                                 {"ff", ff},
                                 {"no_plots", a.no_plots},
                                 {"executor", a.executor},
                                 {"jobs", a.spec.jobs},
                                 {"ranks", a.spec.ranks}, // D324; also each point unit's ranks
                                 {"command_line", command_line()},
                                 // D302: --resume reads the same file again
                                 {"input", a.input.empty() ? "" : fs::absolute(a.input).string()},
                                 {"started_s", started}};
  const campaign::Plan p = ti_plan(a.spec, a.out, params);
  sync_point_states(a.out, a.spec);
  campaign::clear_status(a.out, "analysis"); // the analysis runs again on every --resume (seconds)
  campaign::write_plan(a.out, p);
  if (a.executor == "slurm") { // the file's slurm section, the options merged in (D301)
    SlurmOptions o;
    o.wait = a.slurm.wait;
    o.job_name = a.slurm.job_name;
    return run_plan_slurm(
        {kCommand, a.out, "analysis", a.json}, p, in.slurm, o, job_prefix_of("ti"),
        [&](const std::vector<std::string>& failed) { return conclude_ti(a, p, failed, {}); });
  }
  std::cerr << fmt::format("pnc thermo ti: {} unit(s), {} at a time on {} MPI rank(s) each; "
                           "states in {}/state, pnc status {} shows them\n",
                           p.units.size(), a.spec.jobs, a.spec.ranks, a.out, a.out);
  return run_local_reported(
      {kCommand, a.out, "analysis", a.json}, p, "pnc thermo ti: " + a.out, [&] {
        const campaign::LocalRun lr =
            campaign::run_local(a.out, p, a.spec.jobs, [&](const campaign::Unit& u) {
              return ti_unit_main(a.out, p, u, false);
            });
        return conclude_ti(a, p, lr.failed, lr.not_run);
      });
}

} // namespace

void register_thermo_ti(CLI::App* th, Action& action) {
  register_plan_command(kCommand, ti_unit_main);
  // `pnc thermo ti-parameters`: the declared keys (thermo/src/ti_parameters.cpp) as Markdown
  // tables (the generated region of docs/thermo.md), JSON or a commented TOML template
  add_parameters_command(
      th, "ti-parameters", "of a `pnc thermo ti --input` file", "pnc thermo ti --input reads it",
      [] { return thermo::ti_input_parameters(); }, action);
  auto ta = std::make_shared<TiArgs>();
  auto* ti = th->add_subcommand(
      "ti", "Thermodynamic integration of the LJ coupling over deformation states -> ti.h5");
  ti->add_option("--from", ta->from,
                 "`pnc characterize` output directory (model pp, or kg: the glass, D393)");
  ti->add_option("--restart", ta->restart, "Equilibrated LAMMPS restart (default PP force field)");
  ti->add_flag("--demo", ta->demo, "Build and equilibrate the demo RVE (600 beads) under OUT/rve");
  ti->add_option("--out", ta->out, "Output directory")->required();
  ti->add_option("--input", ta->input,
                 "TI input file (.toml or .json; its keys: pnc thermo ti-parameters): the "
                 "settings below and a slurm section; an option given here overrides the "
                 "file's key (D301)");
  // the declared keys' options: their checks, help and shown defaults are the declarations'
  // (bind_declared_options below, D320)
  ti->add_option("--rule", ta->spec.rule, "");
  ti->add_option("--points", ta->spec.points, "");
  ti->add_option("--vol", ta->vol, "");
  ti->add_option("--dev", ta->dev, "");
  ti->add_option("--eps0", ta->spec.path.eps0, "");
  ti->add_option("--eps1", ta->spec.path.eps1, "");
  ti->add_option("--sig0", ta->spec.path.sig0, "");
  ti->add_option("--sig1", ta->spec.path.sig1, "");
  ti->add_option("--cutoff", ta->spec.path.cutoff, "");
  ti->add_option("--dhdl", ta->spec.dhdl_method, "");
  ti->add_option("--timestep", ta->spec.sampling.timestep_fs, "");
  ti->add_option("--equil-steps", ta->spec.sampling.equil_steps, "");
  ti->add_option("--prod-steps", ta->spec.sampling.prod_steps, "");
  ti->add_option("--sample-every", ta->spec.sampling.sample_every, "");
  ti->add_option("--blocks", ta->spec.sampling.blocks, "");
  ti->add_option("--temperature", ta->spec.sampling.temperature, "");
  ti->add_option("--seed", ta->spec.seed, "");
  ti->add_option("--jobs", ta->spec.jobs, "");
  ti->add_option("--ranks", ta->spec.ranks, "");
  ti->add_flag("--resume", ta->resume,
               "Continue: finished (state, lambda) points are reused, the others run (or are "
               "submitted) again");
  ti->add_option("--executor", ta->executor, "");
  add_slurm_options(ti, ta->slurm, "the input file");
  ti->add_flag("--no-plots", ta->no_plots, "Do not draw plots");
  ti->add_flag("--json", ta->json, "Print one JSON object with the key numbers on stdout");
  // D301, D320: every declared key has its option (pnc refuses to start otherwise), checked by
  // its declaration; the ones given explicitly override the file
  const auto keyed = bind_declared_options(ti, thermo::ti_input_parameters(), thermo::ti_option_of);
  add_print_parameters_option(ti, declared_printout([] { return thermo::ti_input_parameters(); }),
                              "a TI input file"); // D358
  ti->callback([ta, keyed, &action] {
    ta->given = given_keys(keyed);
    action = [ta] { return run_thermo_ti(*ta); };
  });
}

} // namespace pnc::app
