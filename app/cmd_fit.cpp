// pnc fit: joint NDM fit of stress-strain curves -> material card (+ figure, report).
#include "commands.hpp"
#include "figures.hpp"
#include "fit_report.hpp"
#include "report.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/fit.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <set>

namespace pnc::app {

namespace {
// FitOptions::validate names its fields (one rule each, in the library); on the command line
// the user typed the flags, so the error names the flag.
void validate_on_command_line(const damage::FitOptions& o, const std::set<std::string>& flags) {
  try {
    o.validate();
  } catch (const InputError& e) {
    const ErrorContext& c = e.context();
    std::string flag = "--" + c.field;
    std::replace(flag.begin(), flag.end(), '_', '-');
    if (flags.count(flag) == 0) throw; // not a field the command line sets
    fail("<command line>", flag, c.value, c.rule);
  }
}
} // namespace

int run_fit(const FitArgs& a) {
  using namespace pnc::damage;
  const auto t0 = std::chrono::steady_clock::now();
  check_output_file(a.out, "--out"); // before the fit, not after it
  FitOptions o;
  o.model = parse_model(a.model, "<command line>: --model");
  if (a.fit_alpha && a.hold_alpha)
    fail("<command line>", "--fit-alpha/--hold-alpha", "both", "choose at most one of the two");
  o.alpha_mode = a.fit_alpha    ? AlphaMode::fit
                 : a.hold_alpha ? AlphaMode::hold
                                : AlphaMode::automatic;
  o.check_units = !a.no_unit_check;
  o.alpha = a.alpha;
  o.loss = a.loss;
  o.loss_scale = a.loss_scale;
  o.strain_max = a.strain_max;
  o.stretch_max = a.stretch_max;
  o.isotropic = a.isotropic;
  o.max_iterations = a.max_iterations;
  if (!a.prior.empty()) {
    o.prior = read_card(a.prior).params;
    o.prior_source = a.prior;
  }
  validate_on_command_line(o, a.flags);
  const StressStrainData data = read_stress_strain(a.data);
  for (const auto& w : data.warnings) // legacy CSV column names (D342)
    std::cerr << "pnc: warning: " << w << "\n";
  const FitReport rep = fit_ndm(data, o);
  Card card = card_from_fit(rep, data, a.loss);
  write_card(a.out, card, a.command_line);

  // every figure of the run in one plotting process, after the card is written; a plotting
  // failure is a warning (the card and the report are still written, the exit code unchanged)
  FitRun run{a.command_line, a.data, a.out, "", 0.0, {}};
  if (!a.no_plots) {
    run.plots_dir = a.plots.empty()
                        ? (std::filesystem::path(a.out).replace_extension("").string() + "_plots")
                        : a.plots;
    make_output_directory(run.plots_dir, "--plots");
    const auto dir = std::filesystem::path(run.plots_dir);
    const Figure fig = fit_figure(data, card, (dir / "fit.png").string(),
                                  std::string("NDM fit (") + model_name(o.model) + ") of " +
                                      std::filesystem::path(a.data).filename().string() +
                                      ": card " + verdict_name(card.verdict.level));
    run.plots = draw_figures({fig}, (dir / "figures.json").string(), "pnc fit");
  }
  const std::vector<std::string>& pngs = run.plots.pngs;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string report = write_fit_report(run, data, card);

  std::cerr << fmt::format("pnc fit: {} points from {} ({} cases), model {}\n", data.points(),
                           a.data, data.cases.size(), model_name(o.model));
  std::cerr << fmt::format("  solver: {} after {} iterations in {:.3f} s; {}\n", rep.termination,
                           rep.iterations, rep.seconds, rep.message);
  if (!rep.warnings.empty()) std::cerr << "  warning: " << rep.warnings << "\n";
  std::cerr << constants_table(card) << fit_tables(card.fit, o.model) << verdict_text(card.verdict);
  std::cerr << "  card: " << a.out << "\n  report: " << report << "\n";
  for (const auto& p : pngs)
    std::cerr << "  plot: " << p << "\n";

  if (a.json) {
    nlohmann::json j;
    j["command"] = "fit";
    j["card"] = a.out;
    j["model"] = model_name(o.model);
    j["data"] = a.data;
    j["points"] = data.points();
    j["constants"] = constants_json(card);
    j["fit"] = fit_json(card.fit);
    j["verdict"] = verdict_json(card.verdict);
    j["plots"] = pngs;
    j["report"] = report;
    if (!run.plots.warning.empty()) j["plot_warning"] = run.plots.warning;
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
    return pnc::exit_code::not_converged;
  }
  return 0;
}

} // namespace pnc::app
