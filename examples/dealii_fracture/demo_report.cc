// examples/dealii_fracture/demo_report.cc: the demo's report.html and report.md (see
// demo_report.h; the page layout is that of every pnc run report, docs/formats.md "Run
// reports").
#include "demo_report.h"

#include <pnc/core/html_page.hpp>
#include <pnc/core/units.hpp>
#include <pnc/core/version.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>

namespace pncdemo {
namespace {
namespace fs = std::filesystem;
using pnc::html::Tone;

std::string seconds(double s) {
  return s < 100 ? fmt::format("{:.3g} s", s) : fmt::format("{:.0f} s ({:.1f} min)", s, s / 60);
}

// The value of `key` in `j`, or `fallback` when the key is absent.
template <class T> T get(const nlohmann::json& j, const char* key, T fallback) {
  return j.contains(key) ? j.at(key).get<T>() : fallback;
}

bool stop_fraction_reached(const nlohmann::json& s, double stop_fraction) {
  return stop_fraction > 0 && s.value("finished", false) && s.value("peak_is_interior", false) &&
         std::abs(s.value("final_load_over_peak", 1.0)) < stop_fraction;
}

DemoUnits units_of(const nlohmann::json& s) {
  return demo_units(s.value("dimension", 2));
}

// The summary's SI values in the page's units (D307): `key_m` in mm; `name` + the force or
// energy key suffix in N/mm or N, mJ/mm or mJ. 0 when the key is absent.
double mm(const nlohmann::json& s, const std::string& key_m) {
  return s.value(key_m, 0.0) / pnc::units::m_per_mm;
}
double force(const nlohmann::json& s, const DemoUnits& u, const std::string& name) {
  return s.value(name + u.force_key, 0.0) / u.force_to_si;
}
double energy(const nlohmann::json& s, const DemoUnits& u, const std::string& name) {
  return s.value(name + u.energy_key, 0.0) / u.energy_to_si;
}

// The warnings of a run, each with what it means.
std::vector<std::string> warnings_of(const ReportInput& in) {
  const auto& s = in.summary;
  const DemoUnits u = units_of(s);
  std::vector<std::string> w;
  if (!s.value("finished", false))
    w.push_back("The run stopped before the end of its load path: " +
                s.value("stop_reason", std::string("no reason recorded")) + ".");
  if (!s.value("peak_is_interior", false))
    w.push_back("The force still rose at the last step: the peak force shown is a lower bound, "
                "the load path ended before the peak.");
  if (const unsigned cuts = s.value("step_cuts", 0u); cuts > 0)
    w.push_back(fmt::format("{} step cut(s): a load step whose Newton iteration failed was "
                            "halved and redone.",
                            cuts));
  if (const unsigned back = s.value("dissipation_control_fallbacks", 0u); back > 0)
    w.push_back(fmt::format("{} fall-back(s) from dissipation to displacement control (a "
                            "dissipation step that could not be solved; the specimen reloaded "
                            "elastically).",
                            back));
  if (s.contains("timing")) {
    const auto& ls = s["timing"]["linear_solver"];
    if (const unsigned fb = ls.value("fallbacks", 0u); fb > 0)
      w.push_back(fmt::format("{} iterative linear solve(s) fell back to the direct solver "
                              "(UMFPACK).",
                              fb));
  }
  if (const double neg = energy(s, u, "impl_ex_negative_dissipation"); neg < 0)
    w.push_back(fmt::format("IMPL-EX: negative point-wise dissipation summed to {:.4g} {} "
                            "(the extrapolated history overshot).",
                            neg, u.energy));
  if (in.plot_requested && !in.plot_note.empty()) w.push_back("No figure: " + in.plot_note + ".");
  return w;
}

std::vector<std::string> next_steps(const ReportInput& in) {
  const auto& s = in.summary;
  std::vector<std::string> n;
  if (!s.value("finished", false)) {
    if (s.value("control", std::string()) == "displacement")
      n.push_back("Past a peak with a snap-back displacement control cannot go on: set "
                  "`Loading/Control = dissipation` (and a `Loading/Stop force fraction`).");
    n.push_back("Smaller steps (`Loading/Step`, `Loading/Dissipation step`), more `Loading/Max "
                "cuts` or `Newton/Line search = true`; `PNC_DEMO_DEBUG=1` prints every Newton "
                "iteration of the dissipation control.");
  }
  if (!s.value("peak_is_interior", false))
    n.push_back("Extend `Loading/Path` (mm) to reach the peak and the softening branch.");
  n.push_back("Check the mesh dependence of the peak: run again with one more "
              "`Mesh/Global refinements` (or `Mesh/Max adaptive levels`) and compare the peak "
              "force.");
  if (in.vtu)
    n.push_back("Open `solution.pvd` in ParaView (one frame per written step; the frame's "
                "displacement and force are its field data) to see where the damage localises.");
  return n;
}

void key_numbers(pnc::html::Page& page, const ReportInput& in) {
  const auto& s = in.summary;
  const DemoUnits u = units_of(s);
  std::vector<std::pair<std::string, std::string>> k;
  k.push_back(
      {"peak force",
       fmt::format("{:.6g} {} at u = {:.6g} mm{}", force(s, u, "peak_load"), u.force,
                   mm(s, "displacement_at_peak_m"),
                   s.value("peak_is_interior", false) ? "" : " (last step: a lower bound)")});
  k.push_back({"last step", fmt::format("u = {:.6g} mm, F = {:.6g} {} ({:.3g} % of the peak)",
                                        mm(s, "final_displacement_m"), force(s, u, "final_load"),
                                        u.force, 100 * s.value("final_load_over_peak", 0.0))});
  const double W = energy(s, u, "external_work"), Psi = energy(s, u, "elastic_energy"),
               D = energy(s, u, "dissipated_energy");
  k.push_back({"dissipated energy", fmt::format("{:.6g} {} (summed point by point)", D, u.energy)});
  k.push_back({"external work W, elastic energy Ψ",
               fmt::format("W = {:.6g} {}, Ψ = {:.6g} {}", W, u.energy, Psi, u.energy)});
  k.push_back(
      {"energy check", fmt::format("W − Ψ = {:.6g} {}; |W − Ψ − dissipated| / W = {:.2g} "
                                   "(on a fixed mesh the error of the load steps; an adaptive "
                                   "refinement moves W − Ψ, not the dissipated energy)",
                                   W - Psi, u.energy, W > 0 ? std::abs(W - Psi - D) / W : 0.0)});
  k.push_back({"damage at the last step",
               fmt::format("largest D_k = {:.4g}, largest fracture variable ω = {:.4g} "
                           "(dimensionless)",
                           s.value("max_damage", 0.0), s.value("max_fracture", 0.0))});
  const unsigned steps = s.value("steps", 0u);
  std::string control = s.value("control", std::string("displacement"));
  if (s.contains("dissipation_control_from_step"))
    control += fmt::format(", dissipation control from step {}",
                           s["dissipation_control_from_step"].get<unsigned>());
  k.push_back({"steps",
               fmt::format("{} ({} cuts); control: {}", steps, s.value("step_cuts", 0u), control)});
  if (s.contains("timing")) {
    const auto& t = s["timing"];
    const auto& ls = t["linear_solver"];
    const unsigned its = t.value("newton_iterations", 0u);
    k.push_back({"Newton iterations",
                 fmt::format("{} in all, {:.3g} per step; {} assemblies", its,
                             steps ? double(its) / steps : 0.0, t.value("assemblies", 0u))});
    k.push_back({"linear solver",
                 fmt::format("{}: {} solves, {} Krylov iterations, {} fall-backs",
                             ls.value("type", std::string()), ls.value("solves", 0u),
                             ls.value("krylov_iterations", 0u), ls.value("fallbacks", 0u))});
    k.push_back(
        {"time",
         fmt::format("assembly {} (material plugin {}), nonlocal {}, linear solves {}",
                     seconds(t.value("assembly_s", 0.0)), seconds(t.value("plugin_s", 0.0)),
                     seconds(t.value("nonlocal_s", 0.0)), seconds(t.value("solve_s", 0.0)))});
  }
  k.push_back({"mesh at the end",
               fmt::format("{} cells, {} dofs", s.value("cells", 0u), s.value("dofs", 0u))});
  page.facts(k);
  page.paragraph(
      "Uncertainty: one deterministic run, so no statistical error bar. The numbers "
      "carry the discretisation error of the load steps (the energy check above, "
      "on a fixed mesh) and of the mesh, which only a run on a finer mesh measures: in the demo's "
      "validation (docs/dealii_demo.md, \"Validation\"), halving h = l/2 to l/4 "
      "moved the peak force by 1.2 % and the post-peak dissipated energy by 12 %.");
}
} // namespace

std::string stop_text(const nlohmann::json& s, double stop_fraction) {
  const std::string at =
      fmt::format("step {}, u = {:.4g} mm", s.value("steps", 0u), mm(s, "final_displacement_m"));
  if (!s.value("finished", false))
    return "stopped early (" + at + "): " + s.value("stop_reason", std::string("no reason"));
  if (stop_fraction_reached(s, stop_fraction))
    return fmt::format("stop: force below {:.3g} % of the peak ({})", 100 * stop_fraction, at);
  return "end of the load path (" + at + ")";
}

std::string write_report(const ReportInput& in) {
  const auto& s = in.summary;
  const fs::path dir(in.directory.empty() ? "." : in.directory);
  pnc::html::Page page(fmt::format("dealii_fracture: {}-D {}", s.value("dimension", 2),
                                   s.value("geometry", std::string("specimen"))));
  const std::vector<std::string> warn = warnings_of(in);
  const unsigned steps = s.value("steps", 0u);
  if (!s.value("finished", false))
    page.verdict(fmt::format("Stopped early at step {}", steps), Tone::bad,
                 {{Tone::bad, s.value("stop_reason", std::string("no reason recorded"))}});
  else if (stop_fraction_reached(s, in.stop_fraction))
    page.verdict(fmt::format("Completed: the force fell below {:.3g} % of the peak after it "
                             "({} steps)",
                             100 * in.stop_fraction, steps),
                 Tone::good, {});
  else if (!s.value("peak_is_interior", false))
    page.verdict(fmt::format("Completed the load path ({} steps) before the peak", steps),
                 Tone::warning, {{Tone::warning, "the force still rose at the last step"}});
  else
    page.verdict(fmt::format("Completed: the whole load path ({} steps)", steps), Tone::good, {});

  page.section("What was run");
  std::string overrides;
  for (const auto& o : in.overrides)
    overrides += (overrides.empty() ? "`" : ", `") + o + "`";
  page.facts(
      {{"command", "`" + in.command + "`"},
       {"parameter file",
        in.parameter_file.empty() ? "none (the defaults)" : "`" + in.parameter_file + "`"},
       {"overrides", overrides.empty() ? "none" : overrides},
       {"specimen",
        fmt::format("{}-D {}, {} cells, {} dofs at the end", s.value("dimension", 2),
                    s.value("geometry", std::string()), s.value("cells", 0u), s.value("dofs", 0u))},
       {"material",
        s.value("material", std::string()) +
            fmt::format(", platelet angle {:.3g}°", s.value("platelet_angle_deg", 0.0))},
       {"plugin", fmt::format("`{}` (ABI {})", in.plugin, in.plugin_abi)},
       {"loading", in.loading},
       {"model choices",
        fmt::format("control {}, integration {}, fracture closure {}, regularisation {}{}",
                    s.value("control", std::string()), s.value("integration", std::string()),
                    s.value("fracture", std::string()), s.value("regularisation", std::string()),
                    s.contains("nonlocal_length_m")
                        ? fmt::format(" (length {:.3g} mm)", mm(s, "nonlocal_length_m"))
                        : std::string())},
       {"output", "`" + in.directory + "`"},
       {"software", pnc::version_string() + ", deal.II " + in.dealii_version},
       {"finished", pnc::utc_timestamp()},
       {"wall time", seconds(in.wall_s) + " (plotting " + seconds(in.plot_s) + ")"}});

  page.section("What to do next");
  page.list(next_steps(in));

  page.section("Figures");
  if (in.png.empty()) {
    page.paragraph(
        "No figure: " + (in.plot_note.empty() ? std::string("not drawn") : in.plot_note) +
            (fs::exists(dir / "force_displacement.csv")
                 ? ". The data are in `force_displacement.csv`."
                 : "."),
        in.plot_requested ? Tone::warning : Tone::neutral);
  } else {
    page.figure(in.png,
                "Force" + std::string(s.value("dimension", 2) == 2 ? " per unit thickness" : "") +
                    " and dissipated energy against the controlled displacement; marked: the " +
                    (s.value("peak_is_interior", false) ? "peak" : "largest force (no peak yet)") +
                    (s.contains("dissipation_control_from_step")
                         ? ", the switch to dissipation control (orange: dissipation-controlled "
                           "steps)"
                         : "") +
                    " and the last step: " + in.stop + ".",
                fs::path(in.png).filename().string());
    if (!in.damage_png.empty())
      page.figure(in.damage_png, "Damage (largest D_k per cell) at the last step.",
                  fs::path(in.damage_png).filename().string());
  }

  page.section("Key numbers");
  key_numbers(page, in);

  page.warnings(warn);
  return page.write_report(dir.string());
}

DemoUnits demo_units(int dim) {
  // the demo computes in mm, N/mm (2-D, per mm of thickness) or N, mJ/mm or mJ (D299, D307)
  if (dim == 2)
    return {"N/mm",
            "mJ/mm",
            "_N_per_m",
            "_J_per_m",
            1 / pnc::units::m_per_mm,
            pnc::units::joule_per_mj / pnc::units::m_per_mm};
  return {"N", "mJ", "_N", "_J", 1.0, pnc::units::joule_per_mj};
}

} // namespace pncdemo
