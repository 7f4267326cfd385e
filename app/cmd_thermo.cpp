// pnc thermo ti | persistence | work: free energy of deformation by thermodynamic
// integration, persistence length by steered bending, free energy from the stress work
// (docs/theory.md section 4). Units: LAMMPS real (kcal/mol, A, fs, K) inside thermo/; moduli in Pa
// and EI also in N m^2 where named.
#include "cli_parameters.hpp"
#include "pnc/core/plot.hpp"
#include "registrars.hpp"
#include "report.hpp"
#include "run_control.hpp"
#include "stopped_report.hpp"
#include "thermo_cli.hpp"
#include "thermo_report.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/progress.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/run_log.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"
#include "pnc/md/builder.hpp"
#include "pnc/rve/equilibrate.hpp"
#include "pnc/rve/recipe.hpp"
#include "pnc/thermo/persistence.hpp"
#include "pnc/thermo/persistence_parameters.hpp"
#include "pnc/thermo/ti.hpp"
#include "pnc/thermo/work.hpp"
#include "pnc/thermo/work_parameters.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace pnc::app {

namespace fs = std::filesystem;

nlohmann::json jnum(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

/// Draws with plot_thermo.py; a failure is printed once and kept for the report.
std::vector<std::string> run_plot(const std::vector<std::string>& args, ThermoRun& run) {
  // announced: no silent seconds after ETA 0 s (D344)
  Phase phase("pnc thermo", "plotting (" + args.front() + ")");
  run.pngs = run_plot_script("plot_thermo.py", args, &run.plot_warning);
  if (!run.plot_warning.empty())
    std::cerr << "pnc: warning: no plot: " << run.plot_warning << "\n";
  else
    phase.done(fmt::format("plotted {} figure(s)", run.pngs.size()));
  return run.pngs;
}

std::vector<double> parse_list(const std::string& text, const char* field) {
  std::vector<double> v;
  for (const auto& item : split_list(text)) {
    try {
      std::size_t pos = 0;
      v.push_back(std::stod(item, &pos));
      if (pos != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      fail("<command line>", field, item, "must be a comma-separated list of numbers (or none)");
    }
  }
  return v;
}

namespace {

// ---------------------------------------------------------------------- persistence

struct PersistenceArgs {
  thermo::PersistenceSpec spec; ///< the options' values (the file's keys where not given)
  std::string input; ///< --input: a persistence input file (thermo/persistence_parameters.hpp)
  std::vector<std::string> given; ///< the declared keys whose option was given (D301)
  std::string out, rates = "0.01,0.025,0.05,0.075,0.1";
  bool resume = false, json = false, no_plots = false;
};

/// A persistence run that stopped (a signal, a failed LAMMPS rate) still leaves report.html /
/// report.md saying so first (stopped_report.hpp): the finished rates (OUT/rate_<i>.h5, kept and
/// reused by --resume) and the resume command.
void persistence_stopped(const PersistenceArgs& a, const std::string& reason, bool failure) {
  RunStop stop;
  std::size_t done = 0;
  for (std::size_t i = 0; i < a.spec.rates.size(); ++i)
    if (fs::exists(fs::path(a.out) / fmt::format("rate_{}.h5", i))) {
      ++done;
      stop.valid.push_back(
          fmt::format("`rate_{}.h5`: the rate {:.6g} A/fs, finished", i, a.spec.rates[i]));
    }
  stop.reason = reason;
  stop.where = fmt::format("with {} of {} bending rates done", done, a.spec.rates.size());
  stop.resume = resume_command(); // finished rates are reused
  stop.failure = failure;
  const std::string html = try_write_stopped_report(
      a.out, "pnc thermo persistence: " + a.out, stop,
      {{"command", "`" + command_line() + "`"}, {"output folder", "`" + a.out + "`"}});
  if (!html.empty())
    std::cerr << "pnc thermo persistence: report (stopped early): " << html << "\n";
}

thermo::PersistenceResult run_persistence_reported(const PersistenceArgs& a) {
  try {
    return thermo::run_persistence(a.spec, a.out, a.resume, pnc::print_progress);
  } catch (const pnc::Interrupted& e) {
    persistence_stopped(a, signal_reason(e.signal()), false);
    throw;
  } catch (const pnc::Error& e) {
    persistence_stopped(a, e.what(), true);
    throw;
  }
}

/// D301, D321: the settings of this run: the --input file's keys (defaults without one), each
/// key whose option was given explicitly taken from the command line instead.
thermo::PersistenceSpec resolve_persistence(const PersistenceArgs& a) {
  thermo::PersistenceSpec cli = a.spec;
  cli.rates = parse_list(a.rates, "--rates");
  thermo::PersistenceSpec s =
      a.input.empty() ? thermo::PersistenceSpec{} : thermo::read_persistence_input(a.input);
  thermo::override_persistence_input(s, cli, a.given);
  s.validate(a.input.empty() ? "<command line>" : a.input + " with the command line");
  return s;
}

int run_thermo_persistence(PersistenceArgs a) {
  a.spec = resolve_persistence(a);
  const RunDirLock lock(a.out, command_line()); // one process per run directory
  start_run_log(a.out, command_line());         // pnc.log: what this run printed
  const StopSignals signals;                    // SIGINT/SIGTERM: finished rates are kept
  std::cerr << fmt::format("pnc thermo persistence: {} chain of {} beads, supports {}, spring {} "
                           "kcal/mol/A^2, {} rates, pull {} A at {} fs steps, T {} K\n",
                           a.spec.chain, a.spec.beads, a.spec.supports, a.spec.spring_k,
                           a.spec.rates.size(), a.spec.pull_distance, a.spec.timestep_fs,
                           a.spec.temperature);
  const auto t0 = std::chrono::steady_clock::now();
  const thermo::PersistenceResult r = run_persistence_reported(a);
  ThermoRun rep{command_line(), a.out, r.h5, 0, !a.no_plots, {}, {}, {}};
  const double si = units::j_m_per_kcal_mol_A;
  std::cerr << fmt::format(
      "  L = {:.3f} A; EI(rate) = {:.4g} + {:.4g} rate (kcal/mol A, rate A/fs)\n", r.length,
      r.line.c[0], r.line.c[1]);
  std::cerr << fmt::format("  EI(0) = {:.4g} +- {:.2g} kcal/mol A (95 % CI), = {:.4g} +- {:.2g} N "
                           "m^2; xi_p = EI/kT = {:.2f} +- {:.2f} A at {} K\n",
                           r.ei0.value, r.ei0_ci95, r.ei0.value * si, r.ei0_ci95 * si, r.xi_p,
                           r.xi_p_ci95, a.spec.temperature);
  if (a.spec.chain == "harmonic")
    std::cerr << fmt::format("  by construction: EI = {:.4g} (discrete chain, this loading), "
                             "{:.4g} (continuum k_theta l0) kcal/mol A\n",
                             r.expected_ei, r.expected_ei_continuum);
  else
    std::cerr << "  dissertation (published values, docs/theory.md §4.5): EI(0) = 2.433e-29 N m^2, "
                 "xi_p = 58.74 A\n";
  std::vector<std::string> pngs;
  if (!a.no_plots) {
    std::ostringstream c;
    c.precision(12);
    // SI by the unit rule of every CSV (docs/formats.md): rate m/s, EI N m^2; on the "fit"
    // row EI is EI(0), EI_err its 95 % half-width and EI_end the fit's slope (N m^2 per m/s)
    const double mps = units::m_per_s_per_angstrom_per_fs;
    c << "kind,rate_m_per_s,EI_N_m2,EI_err_N_m2,EI_end_N_m2\n";
    for (const auto& rr : r.rates)
      c << "rate," << rr.rate * mps << ',' << rr.ei.value * si << ',' << rr.ei.se * si << ','
        << rr.ei_end * si << '\n';
    c << "fit,0," << r.line.c[0] * si << ',' << r.ei0_ci95 * si << ',' << r.line.c[1] * si / mps
      << '\n';
    const std::string csv = (fs::path(a.out) / "EI_vs_rate.csv").string();
    write_text_atomically(csv, c.str());
    pngs = run_plot({"persistence", csv, a.out}, rep);
  }
  std::cerr << "  results: " << r.h5 << "\n";
  for (const auto& p : pngs)
    std::cerr << "  plot: " << p << "\n";
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string report = write_persistence_report(rep, a.spec, r);
  std::cerr << "  report: " << report << "\n";
  if (a.json) std::cout << persistence_json(rep, a.spec, r, report).dump() << std::endl;
  return 0;
}

// ----------------------------------------------------------------------------- work

struct WorkArgs {
  std::vector<std::string> from;  ///< --from (relative to the current directory)
  std::string input;              ///< --input: a work input file (thermo/work_parameters.hpp)
  std::vector<std::string> given; ///< the declared keys whose option was given (D301)
  std::string out;
  bool json = false, no_plots = false;
};

nlohmann::json integral_json(const thermo::WorkIntegral& w, std::size_t k, double v0) {
  // SI keys (D238, D280): J/m^3 and J of the box; work.h5/work.csv keep kcal/mol beside J
  return {{"da_J_per_m3", jnum(w.value[k])},
          {"da_stderr_indep_J_per_m3", jnum(w.se_indep[k])},
          {"da_stderr_bound_J_per_m3", jnum(w.se_bound[k])},
          {"dA_J", jnum(w.value[k] * v0)},
          {"dA_stderr_indep_J", jnum(w.se_indep[k] * v0)},
          {"dA_stderr_bound_J", jnum(w.se_bound[k] * v0)}};
}

/// D301, D322: the run directories: --from when given, else the --input file's `from`.
std::vector<std::string> resolve_work_runs(const WorkArgs& a) {
  thermo::WorkInput cli,
      in = a.input.empty() ? thermo::WorkInput{} : thermo::read_work_input(a.input);
  cli.from = a.from;
  thermo::override_work_input(in, cli, a.given);
  if (in.from.empty() || in.from.size() > 2)
    fail(a.input.empty() ? "<command line>" : a.input + " with the command line", "--from",
         fmt::format("{} given", in.from.size()),
         "give one run directory, or two at different temperatures");
  return in.from;
}

int run_thermo_work(WorkArgs a) {
  a.from = resolve_work_runs(a);
  const RunDirLock lock(a.out, command_line()); // one process per output directory
  start_run_log(a.out, command_line());         // pnc.log: what this run printed
  const auto t0 = std::chrono::steady_clock::now();
  const thermo::WorkRun r1 = thermo::read_work_run(a.from[0]);
  std::unique_ptr<thermo::WorkRun> r2;
  if (a.from.size() == 2) r2 = std::make_unique<thermo::WorkRun>(thermo::read_work_run(a.from[1]));
  const thermo::WorkResult r = thermo::stress_work(r1, r2.get());
  const std::string h5 = (fs::path(a.out) / "work.h5").string();
  const std::string csv = (fs::path(a.out) / "work.csv").string();
  thermo::write_work_h5(h5, r);
  thermo::write_work_csv(csv, r);
  std::cerr << fmt::format("pnc thermo work: {} run(s), T {} K, V0 {:.6g} m^3 ({:.0f} A^3)\n",
                           r.runs, r.temperature, r.volume, r.volume * 1e30);
  const double kc = r.volume * units::kcal_mol_per_joule;
  for (const auto& c : r.cases) {
    const std::size_t k = c.da.value.size() - 1;
    std::string line = fmt::format(
        "  case {}: at max strain {:.4g}: da = {:.4g} J/m^3 (+-{:.2g} indep, <= {:.2g} any "
        "correlation), dA = {:.4g} kcal/mol",
        c.id, c.strain.row(static_cast<Eigen::Index>(k)).cwiseAbs().maxCoeff(), c.da.value[k],
        c.da.se_indep[k], c.da.se_bound[k], c.da.value[k] * kc);
    if (r.runs == 2)
      line += fmt::format("; entropic {:.4g} +- {:.2g}, energetic {:.4g} +- {:.2g} J/m^3",
                          c.da_s.value[k], c.da_s.se_indep[k], c.da_u.value[k], c.da_u.se_indep[k]);
    if (work_is_noise(c.da)) line += "  [NOISE: |da| < 2 x its error bound]";
    if (r.runs == 2 && work_is_noise(c.da_s) && work_is_noise(c.da_u))
      line += "  [SPLIT NOISE: entropic and energetic parts < 2 x their error bounds]";
    if (c.softening) line += "  [SOFTENING: yield/damage, the integral is work, not free energy]";
    std::cerr << line << "\n";
  }
  for (const auto& n : r.notes)
    std::cerr << "  note: " << n << "\n";
  std::cerr << "  results: " << h5 << ", " << csv << "\n";
  // exit 4 (outputs written) when no case resolves what was asked: the total, or the split
  bool all_noise = true;
  for (const auto& c : r.cases)
    all_noise = all_noise && work_case_is_noise(c, r.runs);
  if (all_noise)
    std::cerr << "  NO RESULT: every case is noise (exit code 4); longer or replicated runs are "
                 "needed\n";
  ThermoRun rep{command_line(), a.out, h5, 0, !a.no_plots, {}, {}, {}};
  if (!a.no_plots) run_plot({"work", csv, a.out}, rep);
  for (const auto& p : rep.pngs)
    std::cerr << "  plot: " << p << "\n";
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string report = write_work_report(rep, r);
  std::cerr << "  report: " << report << "\n";
  if (a.json) {
    nlohmann::json j;
    j["command"] = "thermo work";
    j["h5"] = h5;
    j["csv"] = csv;
    j["plots"] = rep.pngs;
    j["report"] = report;
    j["wall_s"] = rep.seconds;
    j["runs"] = r.runs;
    j["temperature_K"] = r.temperature;
    if (r.runs == 2) {
      j["temperature_1_K"] = r.t1;
      j["temperature_2_K"] = r.t2;
      j["volume_1_m3"] = r.volume1;
      j["volume_2_m3"] = r.volume2;
    }
    j["volume_m3"] = r.volume;
    j["notes"] = r.notes;
    nlohmann::json cs = nlohmann::json::array();
    for (const auto& c : r.cases) {
      const std::size_t k = c.da.value.size() - 1;
      nlohmann::json o;
      o["case"] = c.id;
      o["strain_max_1"] = c.strain.row(static_cast<Eigen::Index>(k)).cwiseAbs().maxCoeff();
      o["total"] = integral_json(c.da, k, r.volume);
      if (r.runs == 2) {
        o["entropic"] = integral_json(c.da_s, k, r.volume);
        o["energetic"] = integral_json(c.da_u, k, r.volume);
      }
      o["softening"] = c.softening;
      o["noise"] = work_is_noise(c.da);
      if (r.runs == 2) {
        o["entropic"]["noise"] = work_is_noise(c.da_s);
        o["energetic"]["noise"] = work_is_noise(c.da_u);
      }
      cs.push_back(o);
    }
    j["cases"] = cs;
    j["all_noise"] = all_noise;
    std::cout << j.dump() << std::endl;
  }
  return all_noise ? kExitNotUsable : 0;
}

} // namespace

void register_thermo(CLI::App& app, Action& action) {
  auto* th = app.add_subcommand(
      "thermo", "Free energy of deformation (TI) and persistence length (LAMMPS, units real)");
  th->require_subcommand(1);

  register_thermo_ti(th, action); // app/cmd_thermo_ti.cpp

  add_parameters_command(
      th, "persistence-parameters", "of a `pnc thermo persistence --input` file",
      "pnc thermo persistence --input reads it",
      [] { return thermo::persistence_input_parameters(); }, action);
  auto pa = std::make_shared<PersistenceArgs>();
  auto* pe = th->add_subcommand(
      "persistence", "Bending stiffness EI and persistence length by steered bending of a chain");
  pe->add_option("--input", pa->input,
                 "Persistence input file (.toml or .json; its keys: pnc thermo "
                 "persistence-parameters): the settings below; an option given here overrides "
                 "the file's key (D301)");
  // the declared keys' options: their checks, help and shown defaults are the declarations'
  // (bind_declared_options below, D320)
  pe->add_option("--chain", pa->spec.chain, "");
  pe->add_option("--beads", pa->spec.beads, "");
  pe->add_option("--angle-k", pa->spec.angle_K, "");
  pe->add_option("--bond-k", pa->spec.bond_K, "");
  pe->add_option("--supports", pa->spec.supports, "");
  pe->add_option("--spring-k", pa->spec.spring_k, "");
  pe->add_option("--rates", pa->rates, "");
  pe->add_option("--pull-distance", pa->spec.pull_distance, "");
  pe->add_option("--timestep", pa->spec.timestep_fs, "");
  pe->add_option("--hold-steps", pa->spec.hold_steps, "");
  pe->add_option("--sample-every", pa->spec.sample_every, "");
  pe->add_option("--blocks", pa->spec.blocks, "");
  pe->add_option("--temperature", pa->spec.temperature, "");
  pe->add_option("--seed", pa->spec.seed, "");
  pe->add_option("--out", pa->out, "Output directory")->required();
  pe->add_flag("--resume", pa->resume, "Reuse finished rates");
  pe->add_flag("--no-plots", pa->no_plots, "Do not draw plots");
  pe->add_flag("--json", pa->json, "Print one JSON object with the key numbers on stdout");
  const auto pkeys =
      bind_declared_options(pe, thermo::persistence_input_parameters(), option_of_key);
  add_print_parameters_option(
      pe, declared_printout([] { return thermo::persistence_input_parameters(); }),
      "a persistence input file"); // D358
  pe->callback([pa, pkeys, &action] {
    pa->given = given_keys(pkeys);
    action = [pa] { return run_thermo_persistence(*pa); };
  });
  add_parameters_command(
      th, "work-parameters", "of a `pnc thermo work --input` file",
      "pnc thermo work --input reads it, once `from` is set",
      [] { return thermo::work_input_parameters(); }, action);
  auto wa = std::make_shared<WorkArgs>();
  auto* wk = th->add_subcommand(
      "work", "Free energy of deformation from the stress work of `pnc characterize` cases "
              "(post-processing; two runs at T1 != T2 add the energetic/entropic split)");
  wk->add_option("--input", wa->input,
                 "Work input file (.toml or .json; its keys: pnc thermo work-parameters); "
                 "--from given here overrides the file's from (D301, D322)");
  wk->add_option("--from", wa->from, "")->take_all(); // D320: checked by its declaration
  wk->add_option("--out", wa->out, "Output directory (work.h5, work.csv, work.png, report.html)")
      ->required();
  wk->add_flag("--no-plots", wa->no_plots, "Do not draw work.png");
  wk->add_flag("--json", wa->json, "Print one JSON object with the key numbers on stdout");
  const auto wkeys = bind_declared_options(wk, thermo::work_input_parameters(), option_of_key);
  wk->callback([wa, wkeys, &action] {
    wa->given = given_keys(wkeys);
    action = [wa] { return run_thermo_work(*wa); };
  });
}

} // namespace pnc::app
