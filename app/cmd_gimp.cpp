// pnc gimp run: the explicit uGIMP solver (gimp_coupler/, docs/gimp.md).
#include "registrars.hpp"

#include "pnc/gimp_coupler/run.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

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

int run_gimp(const GimpRunArgs& a) {
  gimp::RunOptions o;
  o.input = a.input;
  o.out_dir = a.out;
  o.resume = a.resume;
  o.threads = a.threads;
  o.progress = !a.quiet;
  o.plot = !a.no_plot;
  o.stop_after_steps = a.max_steps;
  const gimp::RunSummary s = gimp::run(o);

  std::cerr << fmt::format("pnc gimp run: {} ({}-D{}), {} particles, {} threads\n", a.input,
                           s.dimension, s.dimension == 2 ? ", plane strain" : "", s.particles,
                           s.threads);
  std::cerr << fmt::format("  {} steps{} to t = {:.6g} s in {:.2f} s ({:.3g} particle-steps/s)\n",
                           s.steps, s.resumed ? " (resumed)" : "", s.time, s.wall_seconds,
                           s.particle_steps_per_second);
  std::cerr << fmt::format("  energies (J): kinetic {:.6g}, strain {:.6g}, external work {:.6g}, "
                           "boundary work {:.6g}; energy error {:.3g} (max |error| {:.3g})\n",
                           s.energy.kinetic, s.energy.strain, s.energy.external_work,
                           s.energy.boundary_work, s.energy.balance(), s.max_abs_balance);
  for (std::size_t i = 0; i < s.reactions.size(); ++i) {
    std::string r;
    for (double v : s.reactions[i])
      r += fmt::format("{}{:.6g}", r.empty() ? "" : ", ", v);
    std::cerr << "  reaction " << s.reaction_names[i] << " (N): " << r << "\n";
  }
  std::cerr << "  frames: " << s.pvd << " (" << s.frames << ")\n";
  std::cerr << "  history: " << s.history_csv << "\n  checkpoint: " << s.checkpoint << "\n";
  if (!s.plot_png.empty()) std::cerr << "  plot: " << s.plot_png << "\n";
  if (!s.plot_warning.empty()) std::cerr << "  warning: " << s.plot_warning << "\n";

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
    j["energy_J"] = {{"initial", s.energy.initial},
                     {"kinetic", s.energy.kinetic},
                     {"strain", s.energy.strain},
                     {"external_work", s.energy.external_work},
                     {"boundary_work", s.energy.boundary_work},
                     {"balance", s.energy.balance()},
                     {"max_abs_balance", s.max_abs_balance}};
    nlohmann::json r = nlohmann::json::object();
    for (std::size_t i = 0; i < s.reactions.size(); ++i)
      r[s.reaction_names[i]] = s.reactions[i];
    j["reactions_N"] = r;
    j["pvd"] = s.pvd;
    j["frames"] = s.frames;
    j["history"] = s.history_csv;
    j["checkpoint"] = s.checkpoint;
    j["plot"] = s.plot_png.empty() ? nlohmann::json() : nlohmann::json(s.plot_png);
    std::cout << j.dump() << std::endl;
  }
  return 0;
}
} // namespace

void register_gimp(CLI::App& app, Action& action) {
  auto args = std::make_shared<GimpRunArgs>();
  auto* gimp = app.add_subcommand("gimp", "GIMP material-point solver (uGIMP, explicit; SI units)");
  gimp->require_subcommand(1);
  auto* run = gimp->add_subcommand("run", "Run a GIMP simulation from a JSON input (docs/gimp.md)");
  run->add_option("input", args->input, "Input file (JSON)")->required()->check(CLI::ExistingFile);
  run->add_option("--out", args->out, "Output folder (VTU/PVD frames, history.csv, checkpoint.h5)")
      ->required();
  run->add_flag("--resume", args->resume,
                "Continue from OUT/checkpoint.h5 (the input file must be unchanged)");
  run->add_option("--threads", args->threads, "Threads (default: the input's `threads`)")
      ->check(CLI::Range(1, 256));
  run->add_option("--max-steps", args->max_steps,
                  "Stop after this many steps in total (the run can then be resumed)")
      ->check(CLI::PositiveNumber);
  run->add_flag("--no-plot", args->no_plot, "Do not draw energy.png");
  run->add_flag("--quiet", args->quiet, "No progress lines");
  run->add_flag("--json", args->json, "Print one JSON object with the key numbers on stdout");
  run->callback([args, &action] { action = [args] { return run_gimp(*args); }; });
}

} // namespace pnc::app
