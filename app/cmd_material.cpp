// pnc material drive: the material law driven point-wise through the plugin (docs/drive.md).
// Exit codes beyond main.cpp's: 3 a Newton solve that did not converge (the steps before it
// are written), 5 a response outside the reference tolerances (docs/decisions.md D169).
#include "checks.hpp"
#include "drive.hpp"
#include "drive_output.hpp"
#include "drive_report.hpp"
#include "material_plugin.hpp"
#include "registrars.hpp"
#include "run_control.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

namespace pnc::app {

namespace {

constexpr int kExitNotConverged = pnc::exit_code::not_converged;         // 3, docs/errors.md
constexpr int kExitOutsideReference = pnc::exit_code::outside_reference; // 5
constexpr std::size_t kMismatchesShown = 10;

struct DriveArgs {
  std::string card, path, out, plot, plugin, reference;
  bool no_plot = false, allow_not_usable = false, json = false;
  Tolerances tol;
};

int run_drive(const DriveArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string ext = std::filesystem::path(a.out).extension().string();
  if (ext != ".csv" && ext != ".h5")
    fail("<command line>", "--out", a.out, "the output file ends in .csv or .h5");
  check_output_file(a.out, "--out");
  const std::string png =
      a.no_plot ? ""
                : (a.plot.empty() ? std::filesystem::path(a.out).replace_extension(".png").string()
                                  : a.plot);
  if (!png.empty()) check_output_file(png, "--plot");
  const DrivePath path = read_drive_path(a.path);
  const pnc::fe_material::Plugin plugin = load_material_plugin(a.plugin);
  const pnc::fe_material::Material card = load_card(plugin, a.card, a.allow_not_usable);
  std::unique_ptr<pnc::fe_material::Material> turned;
  if (path.rotated)
    turned = std::make_unique<pnc::fe_material::Material>(driven_material(plugin, card, path));
  const pnc::fe_material::Material& mat = turned ? *turned : card;

  const DriveResult r = drive(mat, path);
  const DriveMeta meta{a.card, plugin.path(), a.path, mat.model(), card.verdict(), command_line()};
  write_drive_output(a.out, r, meta);
  std::string wrote_png;
  if (!png.empty() && r.rows.size() > 1) wrote_png = plot_drive(r, meta, png);

  const DriveRecord& last = r.rows.back();
  std::cerr << fmt::format("pnc material drive: {} (model {}, {}) along {}: {} of {} steps{}\n",
                           a.card, mat.model(), card.verdict(), a.path, r.rows.size() - 1,
                           path.total_steps(), path.rotated ? ", platelet frame turned" : "");
  std::cerr << fmt::format("  plugin: {}\n", plugin.path());
  if (r.mixed)
    std::cerr << fmt::format("  Newton (stress control): at most {} iterations per step, "
                             "residual <= {:.3g} Pa\n",
                             r.max_newton_iterations, r.residual_tolerance);
  std::cerr << fmt::format("  end: stress {:.6g} {:.6g} {:.6g} {:.6g} {:.6g} {:.6g} Pa\n",
                           last.stress[0], last.stress[1], last.stress[2], last.stress[3],
                           last.stress[4], last.stress[5]);
  std::cerr << fmt::format("  energy densities (J/m^3): external work {:.6g}, stored {:.6g}, "
                           "dissipated {:.6g}; balance error {:.3g}\n",
                           last.work, last.stored, last.dissipated,
                           last.work - last.stored - last.dissipated);
  std::cerr << "  output: " << a.out << (wrote_png.empty() ? "" : ", plot: " + wrote_png) << "\n";

  std::vector<Mismatch> bad;
  if (!a.reference.empty() && r.converged) bad = compare_reference(r, a.reference, a.tol);
  const std::string report = write_drive_report(
      {r, meta, a.out, wrote_png, a.reference, path.total_steps(),
       std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), bad, a.tol});
  std::cerr << "  report: " << report << "\n";
  if (a.json) {
    nlohmann::json j;
    j["command"] = "material drive";
    j["card"] = a.card;
    j["plugin"] = plugin.path();
    j["path"] = a.path;
    j["out"] = a.out;
    j["plot"] = wrote_png;
    j["report"] = report;
    j["steps"] = r.rows.size() - 1;
    j["converged"] = r.converged;
    if (!r.converged) j["failure"] = r.failure;
    j["newton"] = {{"mixed_control", r.mixed},
                   {"max_iterations", r.max_newton_iterations},
                   {"residual_tolerance_Pa", r.residual_tolerance}};
    j["final"] = {{"strain", last.strain},
                  {"stress_Pa", last.stress},
                  {"work_J_per_m3", last.work},
                  {"stored_J_per_m3", last.stored},
                  {"dissipated_J_per_m3", last.dissipated}};
    if (!a.reference.empty()) {
      j["reference"] = {{"file", a.reference}, {"outside_tolerance", bad.size()}};
    }
    std::cout << j.dump() << std::endl;
  }
  if (!r.converged) {
    std::cerr << "pnc: error: " << r.failure << "; the steps before it are in " << a.out << "\n";
    return kExitNotConverged;
  }
  if (!bad.empty()) {
    for (std::size_t i = 0; i < bad.size() && i < kMismatchesShown; ++i)
      std::cerr << fmt::format("pnc: error: reference {}: step {}, column {}: value {:.10g}, "
                               "reference {:.10g}: |difference| {:.3g} > tolerance {:.3g}\n",
                               a.reference, bad[i].step, bad[i].column, bad[i].value,
                               bad[i].reference, std::abs(bad[i].value - bad[i].reference),
                               bad[i].tolerance);
    std::cerr << fmt::format("pnc: error: reference {}: {} values outside the tolerances "
                             "(rel {:.3g}, strain {:.3g}, stress {:.3g} Pa, state {:.3g}, energy "
                             "{:.3g} J/m^3)\n",
                             a.reference, bad.size(), a.tol.rel, a.tol.strain, a.tol.stress,
                             a.tol.state, a.tol.energy);
    return kExitOutsideReference;
  }
  if (!a.reference.empty()) std::cerr << "  reference " << a.reference << ": within tolerances\n";
  return 0;
}

} // namespace

void register_material(CLI::App& app, Action& action) {
  auto* mat = app.add_subcommand("material", "Drive the material law through the plugin");
  mat->require_subcommand(1);
  auto a = std::make_shared<DriveArgs>();
  auto* d = mat->add_subcommand(
      "drive", "Point driver: strain, stress or mixed control along a path file -> CSV/HDF5 + PNG");
  d->add_option("card", a->card, "Material card (HDF5)")->required();
  d->add_option("--path", a->path, "Path file (.toml, .json or .csv; SI units, docs/drive.md)")
      ->required();
  d->add_option("--out", a->out, "Result per step (.csv or .h5; SI units)")->required();
  d->add_option("--plot", a->plot, "PNG to draw (default: the output with .png)");
  d->add_flag("--no-plot", a->no_plot, "Do not draw the PNG");
  d->add_option("--plugin", a->plugin,
                "libpnc_material.so to load (default: $PNC_MATERIAL_PLUGIN, else next to pnc)");
  d->add_flag("--allow-not-usable", a->allow_not_usable,
              "Load a card whose verdict is 'not usable' (to look at it, never for a design)");
  d->add_option("--reference", a->reference,
                "Reference CSV (a previous output, or any of its columns): exit 5 when the "
                "response leaves the tolerances");
  d->add_option("--tol-rel", a->tol.rel, "Relative tolerance (default 1e-6)")
      ->check(FiniteRange(0.0, 1.0));
  d->add_option("--tol-strain", a->tol.strain, "Absolute tolerance of strains (default 1e-10)")
      ->check(FiniteRange(0.0, 1.0));
  d->add_option("--tol-stress", a->tol.stress,
                "Absolute tolerance of stresses and tangents, Pa (default 1)")
      ->check(FiniteRange(0.0, 1e12));
  d->add_option("--tol-state", a->tol.state, "Absolute tolerance of state variables (1e-9)")
      ->check(FiniteRange(0.0, 1e3));
  d->add_option("--tol-energy", a->tol.energy,
                "Absolute tolerance of energy densities, J/m^3 (default 1e-3)")
      ->check(FiniteRange(0.0, 1e12));
  d->add_flag("--json", a->json, "Print one JSON object on stdout");
  d->callback([a, &action] { action = [a] { return run_drive(*a); }; });
}

} // namespace pnc::app
