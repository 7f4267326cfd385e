// pnc gimp run: the explicit uGIMP solver (gimp_coupler/, docs/gimp.md); pnc gimp parameters
// and run --print-parameters: the declared keys of its input (input_parameters.cpp, D358).
#include "cli_parameters.hpp"
#include "gimp_report.hpp"
#include "registrars.hpp"
#include "run_control.hpp"
#include "stopped_report.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/run_log.hpp"
#include "pnc/core/stop.hpp"

#include "pnc/gimp_coupler/input.hpp"
#include "pnc/gimp_coupler/run.hpp"
#ifdef PNC_GIMP_HAS_ESCM
#include "pnc/gimp_coupler/escm_run.hpp"
#endif

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

namespace pnc::app {

namespace {
struct GimpRunArgs {
  std::string input, out;
  bool json = false, resume = false, no_plot = false, quiet = false;
  int threads = 0;
  long max_steps = 0;
};

namespace fs = std::filesystem;

/// The files of a stopped `pnc gimp run` / `pnc gimp couple` folder and what they hold, those
/// that exist (the "stopped early" banner, stopped_report.hpp).
std::vector<std::string> gimp_valid_files(const std::string& out, long steps) {
  std::vector<std::string> v;
  const fs::path d(out);
  if (fs::exists(d / "checkpoint.h5"))
    v.push_back(steps >= 0 ? fmt::format("`checkpoint.h5`: the whole state after step {}", steps)
                           : "`checkpoint.h5`: the state at the last checkpoint before the "
                             "failure");
  if (fs::exists(d / "history.csv"))
    v.push_back(steps >= 0 ? fmt::format("`history.csv`: steps 0 to {}", steps)
                           : "`history.csv`: the steps up to the last checkpoint");
  for (const char* pvd : {"particles.pvd", "continuum.pvd", "md.pvd"})
    if (fs::exists(d / pvd))
      v.push_back(fmt::format("`{}` and its VTU frames: the output times passed", pvd));
  if (fs::exists(d / "energy.csv")) v.push_back("`energy.csv`: the coupled steps done");
  if (fs::exists(d / "pnc.log")) v.push_back("`pnc.log`: everything the run printed");
  return v;
}

std::vector<std::pair<std::string, std::string>>
gimp_stop_facts(const std::string& input, const std::string& out, long steps_this_run) {
  std::vector<std::pair<std::string, std::string>> f = {{"command", "`" + command_line() + "`"},
                                                        {"input", "`" + input + "`"},
                                                        {"output folder", "`" + out + "`"}};
  if (steps_this_run >= 0) f.push_back({"steps in this session", std::to_string(steps_this_run)});
  return f;
}

/// gimp::run(); a simulation failure (a law that cannot take a particle's deformation) still
/// leaves report.html / report.md saying so, then reaches main() as before (exit code 6).
gimp::RunSummary run_gimp_reporting_failure(const GimpRunArgs& a, const gimp::RunOptions& o) {
  try {
    return gimp::run(o);
  } catch (const pnc::SimulationError& e) {
    const auto& c = e.context();
    std::string where;
    if (c.step >= 0) where = fmt::format("at step {}", c.step);
    if (std::isfinite(c.time))
      where += fmt::format("{}t = {:.6g} {}", where.empty() ? "at " : ", ", c.time, c.time_unit);
    RunStop stop{e.what(),
                 where,
                 gimp_valid_files(a.out, -1),
                 "",
                 "Resuming would meet the same failure: change the input (a smaller `time.cfl`, "
                 "a finer grid, gentler loading or a material that takes the deformation; "
                 "docs/gimp.md) and start again.",
                 true};
    const std::string report =
        try_write_stopped_report(a.out, "pnc gimp run: " + fs::path(a.input).filename().string(),
                                 stop, gimp_stop_facts(a.input, a.out, -1));
    if (!report.empty()) std::cerr << "pnc gimp run: report (failed): " << report << "\n";
    throw;
  }
}

int run_gimp(const GimpRunArgs& a) {
  gimp::RunOptions o;
  o.input = a.input;
  o.out_dir = a.out;
  o.resume = a.resume;
  o.threads = a.threads;
  o.progress = !a.quiet;
  o.plot = !a.no_plot;
  o.stop_after_steps = a.max_steps;
  o.stop = &pnc::process_stop();
  const RunDirLock lock(a.out, command_line());
  start_run_log(a.out, command_line()); // pnc.log: what this run printed
  const StopSignals signals;
  const gimp::RunSummary s = run_gimp_reporting_failure(a, o);
  if (s.stopped) {
    const std::string where = fmt::format("after step {} at t = {:.6g} s", s.steps, s.time);
    RunStop stop{signal_reason(s.stop_signal),
                 where,
                 gimp_valid_files(a.out, s.steps),
                 resume_command(),
                 /*instead=*/"",
                 /*failure=*/false};
    const std::string report =
        try_write_stopped_report(a.out, "pnc gimp run: " + fs::path(a.input).filename().string(),
                                 stop, gimp_stop_facts(a.input, a.out, s.steps_this_run));
    if (!report.empty()) std::cerr << "  report (stopped early): " << report << "\n";
    throw pnc::Interrupted(s.stop_signal,
                           fmt::format("{}: stopped after step {} at t = {:.6g} s; checkpoint {}",
                                       a.input, s.steps, s.time, s.checkpoint));
  }

  std::cerr << fmt::format("pnc gimp run: {} ({}-D{}), {} particles, {} threads\n", a.input,
                           s.dimension, s.dimension == 2 ? ", plane strain" : "", s.particles,
                           s.threads);
  std::cerr << fmt::format("  {} steps{} to t = {:.6g} s in {:.2f} s ({:.3g} particle-steps/s)\n",
                           s.steps, s.resumed ? " (resumed)" : "", s.time, s.wall_seconds,
                           s.particle_steps_per_second);
  std::cerr << fmt::format("  energies (J): kinetic {:.6g}, strain {:.6g}, external work {:.6g}, "
                           "boundary work {:.6g}, damping work {:.6g}; energy error {:.3g} "
                           "(max |error| {:.3g})\n",
                           s.energy.kinetic, s.energy.strain, s.energy.external_work,
                           s.energy.boundary_work, s.energy.damping_work, s.energy.balance(),
                           s.max_abs_balance);
  if (s.crack_increments > 0)
    std::cerr << "  crack growth: " << s.crack_increments << " increments in this run\n";
  for (std::size_t i = 0; i < s.reactions.size(); ++i) {
    std::string r;
    for (double v : s.reactions[i])
      r += fmt::format("{}{:.6g}", r.empty() ? "" : ", ", v);
    std::cerr << "  reaction " << s.reaction_names[i] << " (N): " << r << "\n";
  }
  std::cerr << "  frames: " << s.pvd << " (" << s.frames << ")\n";
  std::cerr << "  history: " << s.history_csv << "\n  checkpoint: " << s.checkpoint << "\n";
  if (!s.plot_png.empty()) std::cerr << "  plot: " << s.plot_png << "\n";
  if (!s.plot_G_png.empty()) std::cerr << "  G plot: " << s.plot_G_png << "\n";
  if (!s.plot_warning.empty()) std::cerr << "  warning: " << s.plot_warning << "\n";
  nlohmann::json summary;
  std::ifstream(std::filesystem::path(a.out) / "summary.json") >> summary;
  const double rel = gimp_relative_energy_error(s);
  if (rel > kEnergyErrorThreshold)
    std::cerr << fmt::format("  warning: relative energy error {:.3g} % is above {:.3g} % (D271)\n",
                             100 * rel, 100 * kEnergyErrorThreshold);
  const std::string report =
      write_gimp_run_report({command_line(), a.input, a.out, !a.no_plot}, s, summary);
  std::cerr << "  report: " << report << "\n";

  if (a.json) {
    nlohmann::json j;
    j["command"] = "gimp run";
    j["input"] = a.input;
    j["out"] = a.out;
    j["dimension"] = s.dimension;
    j["particles"] = s.particles;
    j["threads"] = s.threads;
    j["steps"] = s.steps;
    j["steps_this_run"] = s.steps_this_run;
    j["resumed"] = s.resumed;
    j["time_s"] = s.time;
    j["wall_s"] = s.wall_seconds;
    j["particle_steps_per_s"] = s.particle_steps_per_second;
    // D281: in 2-D the extensive quantities are per metre of thickness, and the keys say so
    const bool plane = s.dimension == 2;
    j[plane ? "energy_J_per_m" : "energy_J"] = {{"initial", s.energy.initial},
                                                {"kinetic", s.energy.kinetic},
                                                {"strain", s.energy.strain},
                                                {"external_work", s.energy.external_work},
                                                {"boundary_work", s.energy.boundary_work},
                                                {"damping_work", s.energy.damping_work},
                                                {"balance", s.energy.balance()},
                                                {"max_abs_balance", s.max_abs_balance}};
    nlohmann::json r = nlohmann::json::object();
    for (std::size_t i = 0; i < s.reactions.size(); ++i)
      r[s.reaction_names[i]] = s.reactions[i];
    j[plane ? "reactions_N_per_m" : "reactions_N"] = r;
    j["pvd"] = s.pvd;
    j["frames"] = s.frames;
    j["history"] = s.history_csv;
    j["checkpoint"] = s.checkpoint;
    j["plot"] = s.plot_png.empty() ? nlohmann::json() : nlohmann::json(s.plot_png);
    j["plot_G"] = s.plot_G_png.empty() ? nlohmann::json() : nlohmann::json(s.plot_G_png);
    j["crack_increments"] = s.crack_increments;
    j["relative_energy_error"] = rel;
    j["report"] = report;
    std::cout << j.dump() << std::endl;
  }
  return 0;
}
} // namespace

#ifdef PNC_GIMP_HAS_ESCM
namespace {
// pnc gimp couple (docs/escm.md): an ESCM run (Cases I-III) of an MD region in a
// 2-D GIMP continuum.
struct GimpCoupleArgs {
  std::string input, out;
  bool json = false, short_mode = false, no_plot = false, quiet = false, resume = false;
  long max_steps = 0;
};

int run_gimp_couple(const GimpCoupleArgs& a) {
  gimp::escm::CoupleOptions o;
  o.input = a.input;
  o.out_dir = a.out;
  o.short_mode = a.short_mode;
  o.progress = !a.quiet;
  o.plot = !a.no_plot;
  o.resume = a.resume;
  o.stop_after_steps = a.max_steps;
  o.stop = &pnc::process_stop();
  const RunDirLock lock(a.out, command_line());
  start_run_log(a.out, command_line()); // pnc.log: what this run printed
  const StopSignals signals;
  const gimp::escm::CoupleSummary s = gimp::escm::run_couple(o);
  if (!s.interrupted.empty()) { // checkpoint written; continue with --resume
    const std::string where =
        fmt::format("{}: stopped ({}) after {} coupled steps at {:.4g} ps; checkpoint {}", a.input,
                    s.interrupted, s.steps, s.time_s * 1e12, s.checkpoint);
    RunStop stop{s.signal ? signal_reason(s.signal)
                          : fmt::format("--max-steps ({}) reached", a.max_steps),
                 fmt::format("after coupled step {} at t = {:.4g} ps", s.steps, s.time_s * 1e12),
                 gimp_valid_files(a.out, s.steps),
                 resume_command(),
                 /*instead=*/"",
                 /*failure=*/false};
    const std::string report =
        try_write_stopped_report(a.out, "pnc gimp couple: " + fs::path(a.input).filename().string(),
                                 stop, gimp_stop_facts(a.input, a.out, s.steps - s.start_step));
    if (!report.empty()) std::cerr << "  report (stopped early): " << report << "\n";
    if (s.signal) throw pnc::Interrupted(s.signal, where);
    std::cerr << "pnc gimp couple: " << where << ": continue with --resume\n";
    return 0;
  }
  const auto& e = s.energy;
  std::cerr << fmt::format("pnc gimp couple: {}{}: {} coupled steps to {:.4g} ps in {:.2f} s "
                           "({:.1f} % outside LAMMPS)\n",
                           a.input, a.short_mode ? " (short)" : "", s.steps, s.time_s * 1e12,
                           s.wall_s, 100 * s.outside_share);
  std::cerr << fmt::format("  atoms INT {} IVC {} SVC {}; continuum particles {}\n", s.atoms[0],
                           s.atoms[1], s.atoms[2], s.particles);
  std::cerr << fmt::format("  energies (J, slab): continuum KE {:.4g} SE {:.4g}; MD KE {:.4g} "
                           "PE {:.4g}; work BC {:.4g}, continuum->MD {:.4g}, MD->continuum {:.4g}; "
                           "heat out {:.4g}; balance {:.4g}\n",
                           e.cont_kinetic, e.cont_strain, e.md_kinetic, e.md_potential,
                           e.work_boundary, e.work_cont_on_md, e.work_md_on_cont,
                           e.heat_removed_int + e.heat_removed_ivc + e.heat_removed_cont,
                           e.balance());
  std::cerr << "  energy log: " << s.energy_csv << "\n  profile: " << s.profile_csv
            << "\n  summary: " << s.summary_json << "\n";
  if (!s.plot_warning.empty()) std::cerr << "  warning: " << s.plot_warning << "\n";
  std::ifstream f(s.summary_json);
  nlohmann::json j = nlohmann::json::parse(f);
  const double rel = couple_relative_energy_error(s);
  if (rel > kCoupleEnergyErrorThreshold)
    std::cerr << fmt::format("  warning: relative energy error {:.3g} % is above {:.3g} % (D271)\n",
                             100 * rel, 100 * kCoupleEnergyErrorThreshold);
  const std::string report =
      write_gimp_couple_report({command_line(), a.input, a.out, !a.no_plot}, s, j, a.short_mode);
  std::cerr << "  report: " << report << "\n";
  if (a.json) {
    j["command"] = "gimp couple";
    j["out"] = a.out;
    j["energy_csv"] = s.energy_csv;
    j["profile_csv"] = s.profile_csv;
    j["frames"] = s.frames;
    j["plots"] = s.plots;
    j["relative_energy_error"] = rel;
    j["report"] = report;
    std::cout << j.dump() << std::endl;
  }
  return 0;
}

void register_gimp_couple(CLI::App* gimp, Action& action) {
  auto args = std::make_shared<GimpCoupleArgs>();
  auto* c = gimp->add_subcommand(
      "couple", "ESCM GIMP-MD coupling: Case I tension, Case II/III mode I/II crack growing into "
                "the MD region (docs/escm.md)");
  c->add_option("input", args->input,
                "Input file (.json or .toml; its keys: pnc gimp couple-parameters)")
      ->required()
      ->check(CLI::ExistingFile);
  c->add_option("--out", args->out, "Output folder")->required();
  c->add_flag("--short", args->short_mode, "Apply the input's \"short\" overrides");
  c->add_flag("--no-plot", args->no_plot, "Do not draw profile.png, energy.png");
  c->add_flag("--quiet", args->quiet, "No progress lines");
  c->add_flag("--json", args->json, "Print one JSON object with the key numbers on stdout");
  c->add_flag("--resume", args->resume,
              "Continue from OUT/checkpoint.h5 (the input must be unchanged; docs/escm.md)");
  c->add_option("--max-steps", args->max_steps,
                "Stop after N coupled steps in total, with a checkpoint (continue with --resume)")
      ->check(CLI::PositiveNumber);
  add_print_parameters_option(c, declared_printout(gimp::escm::couple_input_parameters),
                              "the couple input"); // D358
  c->callback([args, &action] { action = [args] { return run_gimp_couple(*args); }; });
}

// `pnc gimp couple-parameters`: the declared keys of the couple input (couple_parameters.cpp,
// D295) as Markdown tables (the generated region of docs/escm.md), JSON or a commented TOML
// template.
void register_gimp_couple_parameters(CLI::App* gimp, Action& action) {
  add_parameters_command(gimp, "couple-parameters", "of the couple input",
                         "pnc gimp couple reads it as a .toml file",
                         declared_printout(gimp::escm::couple_input_parameters), action);
}
} // namespace
#endif

namespace {
struct GimpParametersArgs {
  std::string format = "markdown", dimension = "all";
};

// `pnc gimp parameters` and `pnc gimp run --print-parameters` (D358): the declared input keys
// as Markdown tables (the generated region of docs/gimp.md), JSON or a commented TOML template
// of one dimension ("all": 2).
std::string gimp_parameters_text(const std::string& format, const std::string& dimension) {
  const int dim = dimension == "all" ? 0 : std::stoi(dimension);
  if (format == "toml") return gimp::input_parameters(dim == 0 ? 2 : dim, false).to_toml();
  if (format == "json") return gimp::input_parameters(dim).to_json().dump(2) + "\n";
  return gimp::input_parameters(dim).to_markdown(4);
}

int run_gimp_parameters(const GimpParametersArgs& a) {
  std::cout << gimp_parameters_text(a.format, a.dimension);
  return 0;
}
} // namespace

void register_gimp(CLI::App& app, Action& action) {
  auto args = std::make_shared<GimpRunArgs>();
  auto* gimp = app.add_subcommand("gimp", "GIMP material-point solver (uGIMP, explicit; SI units)");
  gimp->require_subcommand(1);
  auto* run =
      gimp->add_subcommand("run", "Run a GIMP simulation from a JSON or TOML input (docs/gimp.md)");
  run->add_option("input", args->input,
                  "Input file (.json or .toml, D357; its keys: pnc gimp parameters)")
      ->required()
      ->check(CLI::ExistingFile);
  run->add_option("--out", args->out, "Output folder (VTU/PVD frames, history.csv, checkpoint.h5)")
      ->required();
  run->add_flag("--resume", args->resume,
                "Continue from OUT/checkpoint.h5 (the input file must be unchanged)");
  // the input's `threads`: checked by its declaration (D359); --max-steps is not time.max_steps
  const Parameters declared = gimp::input_parameters(2, false);
  const Parameter& threads = declared.at("threads");
  bind_declared_option(
      run->add_option("--threads", args->threads,
                      "Threads (default: the input's `threads`); " + threads.rule()),
      threads);
  run->add_option("--max-steps", args->max_steps,
                  "Stop after this many steps in total (the run can then be resumed)")
      ->check(CLI::PositiveNumber);
  run->add_flag("--no-plot", args->no_plot, "Do not draw energy.png");
  run->add_flag("--quiet", args->quiet, "No progress lines");
  run->add_flag("--json", args->json, "Print one JSON object with the key numbers on stdout");
  add_print_parameters_option(
      run, [](const std::string& format) { return gimp_parameters_text(format, "all"); },
      "the run input (toml: of dimension 2)"); // D358
  run->callback([args, &action] { action = [args] { return run_gimp(*args); }; });
  auto pa = std::make_shared<GimpParametersArgs>();
  auto* params = gimp->add_subcommand(
      "parameters", "Print every key of the run input: type, default, range, unit, meaning");
  params
      ->add_option("--format", pa->format,
                   "markdown (tables, default), json or toml (a commented template with the "
                   "defaults; pnc gimp run reads it as a .toml file once the required keys are "
                   "given)")
      ->check(CLI::IsMember({"markdown", "json", "toml"}));
  params
      ->add_option("--dimension", pa->dimension,
                   "the keys of dimension 2 or 3; default all (toml: 2)")
      ->check(CLI::IsMember({"all", "2", "3"}));
  params->callback([pa, &action] { action = [pa] { return run_gimp_parameters(*pa); }; });
#ifdef PNC_GIMP_HAS_ESCM
  register_gimp_couple(gimp, action); // ESCM, docs/escm.md
  register_gimp_couple_parameters(gimp, action);
#endif
}

} // namespace pnc::app
