#include "gimp_report.hpp"

#include "fit_report.hpp" // seconds_text
#include "run_control.hpp"
#include "stopped_report.hpp"

#include "pnc/core/html_page.hpp"
#include "pnc/core/version.hpp"
#ifdef PNC_GIMP_HAS_ESCM
#include "pnc/gimp_coupler/escm_run.hpp"
#endif

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>

namespace pnc::app {

namespace {
namespace fs = std::filesystem;
using html::Tone;
using Rows = std::vector<std::pair<std::string, std::string>>;

std::string num(double v) {
  return std::isfinite(v) ? fmt::format("{:.6g}", v) : "—";
}

double jnum(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : std::nan("");
}

/// The energy-error line of the key numbers and, above the threshold, its warning.
std::string energy_error_text(double rel, double threshold) {
  return fmt::format("{:.3g} % (threshold {:.3g} %, D271)", 100 * rel, 100 * threshold);
}

void add_figures(html::Page& page, const GimpRunInfo& run,
                 const std::vector<std::pair<std::string, std::string>>& figs,
                 const std::string& warning) {
  page.section("Figures");
  if (!run.plot) {
    page.paragraph("Not drawn (--no-plot).");
    return;
  }
  bool any = false;
  for (const auto& [png, caption] : figs)
    if (!png.empty() && fs::exists(png)) {
      page.figure(png, caption, fs::relative(png, run.out).string());
      any = true;
    }
  if (!any) page.paragraph("Not drawn: " + warning, Tone::warning);
}

/// Polyline length of a 2-D crack (summary.json points_m), m.
double polyline_length(const nlohmann::json& pts) {
  double l = 0;
  for (std::size_t i = 1; i < pts.size(); ++i)
    l += std::hypot(pts[i][0].get<double>() - pts[i - 1][0].get<double>(),
                    pts[i][1].get<double>() - pts[i - 1][1].get<double>());
  return l;
}

/// The page's warnings: the relative energy error when above `threshold` (also the verdict's
/// first reason, appended to `reasons`), then a plotting failure.
std::vector<std::string> energy_warnings(double rel, double threshold,
                                         const std::string& plot_warning,
                                         std::vector<std::pair<Tone, std::string>>& reasons) {
  std::vector<std::string> warnings;
  if (rel > threshold) {
    warnings.push_back(fmt::format("relative energy error {} is above the threshold: the "
                                   "energy account does not close",
                                   energy_error_text(rel, threshold)));
    reasons.push_back({Tone::warning, warnings.back()});
  }
  if (!plot_warning.empty()) warnings.push_back("plotting: " + plot_warning);
  return warnings;
}
} // namespace

double gimp_relative_energy_error(const gimp::RunSummary& s) {
  const auto& e = s.energy;
  const double scale =
      std::max({std::fabs(e.initial), std::fabs(e.external_work) + std::fabs(e.boundary_work),
                e.kinetic + e.strain});
  return scale > 0 ? s.max_abs_balance / scale : 0.0;
}

std::string write_gimp_run_report(const GimpRunInfo& run, const gimp::RunSummary& s,
                                  const nlohmann::json& summary) {
  const bool two = s.dimension == 2;
  const std::string eu = two ? "J/m" : "J", fu = two ? "N/m" : "N";
  html::Page page("pnc gimp run: " + fs::path(run.input).filename().string());
  const double rel = gimp_relative_energy_error(s);
  const bool high = rel > kEnergyErrorThreshold;
  const bool partial = s.end_reason.rfind("--max-steps", 0) == 0;
  std::vector<std::string> next;
  std::vector<std::pair<Tone, std::string>> reasons;
  const std::vector<std::string> warnings =
      energy_warnings(rel, kEnergyErrorThreshold, s.plot_warning, reasons);
  for (const auto& c : s.cracks)
    if (c.Gc > 0)
      reasons.push_back({Tone::neutral, fmt::format("crack '{}': {} increment(s); growth "
                                                    "stopped: {}",
                                                    c.name, c.increments, c.stop_reason)});
  const std::string how = fmt::format("{} steps to t = {:.6g} s", s.steps, s.time);
  if (partial) { // the banner of every run that stopped early, then the run's own reasons
    RunStop stop{s.end_reason,
                 fmt::format("after step {} at t = {:.6g} s", s.steps, s.time),
                 {fmt::format("`checkpoint.h5`: the whole state after step {}", s.steps),
                  fmt::format("`history.csv`: steps 0 to {}", s.steps),
                  "`" + fs::path(s.pvd).filename().string() +
                      "` and its VTU frames: the output times passed"},
                 resume_command(),
                 /*instead=*/"",
                 /*failure=*/false};
    stopped_banner(page, stop);
    std::vector<std::string> notes; // energy warning, crack outcomes
    for (const auto& x : reasons)
      notes.push_back(x.second);
    if (!notes.empty()) page.list(notes);
  } else
    page.verdict((high ? "Completed with a warning: " : "Completed: ") + how + " (" + s.end_reason +
                     ")",
                 high ? Tone::warning : Tone::good, reasons);
  page.section("What was run");
  page.facts({{"command", "`" + run.command_line + "`"},
              {"input", "`" + run.input + "`"},
              {"output folder", "`" + run.out + "`"},
              {"model", two ? "2-D, plane strain, per metre of thickness (energies J/m, forces "
                              "N/m)"
                            : "3-D"},
              {"particles", std::to_string(s.particles)},
              {"threads", std::to_string(s.threads)},
              {"steps", fmt::format("{} ({} in this run{})", s.steps, s.steps_this_run,
                                    s.resumed ? ", resumed" : "")},
              {"end", s.end_reason},
              {"software", version_string()},
              {"finished", utc_timestamp()},
              {"wall time", seconds_text(s.wall_seconds)}});
  page.section("What to do next");
  if (partial) next.push_back("Continue the run with `--resume` (same input, same `--out`).");
  if (high)
    next.push_back("A large energy error: check the time step (a smaller `time.cfl`), the "
                   "resolution (more cells) and contacts or impacts (docs/gimp.md); with crack "
                   "growth part of the released energy is lost numerically (no cohesive law).");
  for (const auto& c : s.cracks)
    if (c.Gc > 0 && c.increments >= c.max_increments)
      next.push_back(fmt::format("Crack '{}' stopped at its `max_increments` ({}): raise it in "
                                 "the input to let it grow further.",
                                 c.name, c.max_increments));
  next.push_back("Open `" + s.pvd +
                 "` in ParaView for the fields; `history.csv` holds every "
                 "recorded step (docs/gimp.md).");
  page.list(next);
  page.section("Key numbers");
  const auto& e = s.energy;
  html::Table en;
  en.caption = "Energies at the end (" + eu + ")";
  en.header = {"quantity", "value (" + eu + ")"};
  en.numeric = {false, true};
  en.side_by_side = true;
  en.rows = {{"initial E0", num(e.initial)},
             {"kinetic KE", num(e.kinetic)},
             {"strain SE", num(e.strain)},
             {"external work W_ext", num(e.external_work)},
             {"boundary work W_bc", num(e.boundary_work)},
             {"damping work W_damp", num(e.damping_work)},
             {"energy error at the end", num(e.balance())},
             {"largest |energy error|", num(s.max_abs_balance)}};
  page.table(en);
  if (!s.reactions.empty()) {
    html::Table rt;
    rt.caption = "Reactions at the last step (" + fu + ", force of the boundary on the body)";
    rt.header = {"boundary", "x", "y"};
    if (!two) rt.header.push_back("z");
    rt.numeric = {false, true, true, true};
    rt.side_by_side = true;
    for (std::size_t i = 0; i < s.reactions.size(); ++i) {
      std::vector<std::string> row = {s.reaction_names[i]};
      for (double v : s.reactions[i])
        row.push_back(num(v));
      rt.rows.push_back(row);
    }
    page.table(rt);
  }
  page.facts(
      {{"relative energy error (largest |error| / max(|E0|, |W_ext| + |W_bc|, KE + SE))",
        energy_error_text(rel, kEnergyErrorThreshold) + (high ? " — above the threshold" : "")},
       {"time step (last)", fmt::format("{:.4g} s", s.dt_last)},
       {"speed", fmt::format("{:.3g} particle-steps/s", s.particle_steps_per_second)}});
  if (!s.cracks.empty()) {
    html::Table ct;
    ct.caption = "Cracks at the end (G, Gc in J/m² of crack area)";
    ct.header = {"crack",      two ? "length (m)" : "front(s)", "largest J (J/m²)", "Gc (J/m²)",
                 "increments", "growth stopped because"};
    ct.numeric = {false, true, true, true, true, false};
    for (const auto& c : s.cracks) {
      double jmax = std::nan(""), length = std::nan("");
      for (const auto& cj : summary.value("cracks", nlohmann::json::array()))
        if (cj.value("name", "") == c.name) {
          for (const auto& t : cj.value(two ? "tips" : "fronts", nlohmann::json::array())) {
            const double j = jnum(t, "J_J_per_m2");
            if (std::isfinite(j)) jmax = std::isfinite(jmax) ? std::max(jmax, j) : j;
          }
          if (two && cj.contains("points_m")) length = polyline_length(cj["points_m"]);
        }
      ct.rows.push_back({c.name, num(length), num(jmax), c.Gc > 0 ? num(c.Gc) : "no growth",
                         c.Gc > 0 ? fmt::format("{} of {}", c.increments, c.max_increments)
                                  : std::to_string(c.increments),
                         c.stop_reason});
    }
    page.table(ct);
  }
  add_figures(page, run,
              {{s.plot_png, "Energy balance against time (" + eu +
                                "): kinetic, strain, works and the energy error."},
               {s.plot_G_png, "Energy release rates J, G_I, G_II (J/m²) against crack length "
                              "and time; dash-dotted: the critical Gc; ✕: where growth "
                              "stopped, and why."}},
              s.plot_warning);
  page.warnings(warnings);
  return page.write_report(run.out);
}

#ifdef PNC_GIMP_HAS_ESCM
double couple_relative_energy_error(const gimp::escm::CoupleSummary& s) {
  const auto& e = s.energy;
  const double created = e.work_cont_on_md + e.work_md_on_cont;
  const double scale = std::max(std::fabs(e.work_boundary), std::fabs(created));
  return scale > 0 ? std::fabs(e.balance() - created) / scale : 0.0;
}

std::string write_gimp_couple_report(const GimpRunInfo& run, const gimp::escm::CoupleSummary& s,
                                     const nlohmann::json& summary, bool short_mode) {
  html::Page page("pnc gimp couple: " + fs::path(run.input).filename().string());
  const auto& e = s.energy;
  const double rel = couple_relative_energy_error(s);
  const bool high = rel > kCoupleEnergyErrorThreshold;
  std::vector<std::string> next;
  std::vector<std::pair<Tone, std::string>> reasons;
  const std::vector<std::string> warnings =
      energy_warnings(rel, kCoupleEnergyErrorThreshold, s.plot_warning, reasons);
  const nlohmann::json crack = summary.value("crack", nlohmann::json());
  std::string stop;
  if (crack.is_object()) {
    const nlohmann::json last = crack.value("last", nlohmann::json::object());
    const double J = jnum(last, "J_J_per_m2"), gc = jnum(crack, "Gc_J_per_m2");
    const double ts = jnum(crack, "time_tip_reached_stop_s");
    if (std::isfinite(ts))
      stop = fmt::format("max_increments ({}) reached at {:.4g} ps: the continuum tip stops one "
                         "cell before the MD block (D81)",
                         crack.value("max_increments", 0), ts * 1e12);
    else if (std::isfinite(J) && J < gc)
      stop = fmt::format("J = {:.4g} < Gc = {:.4g} J/m² at the end", J, gc);
    else
      stop = "still growing at the end of the run";
    reasons.push_back({Tone::neutral, "continuum crack: " + stop});
  }
  page.verdict(fmt::format("{}{} coupled steps to {:.4g} ps",
                           high ? "Completed with a warning: " : "Completed: ", s.steps,
                           s.time_s * 1e12),
               high ? Tone::warning : Tone::good, reasons);
  page.section("What was run");
  page.facts({{"command", "`" + run.command_line + "`"},
              {"input", "`" + run.input + "`" + (short_mode ? " (--short)" : "")},
              {"output folder", "`" + run.out + "`"},
              {"load", summary.value("load", std::string("?"))},
              {"model", "2-D GIMP continuum (per metre of thickness) around an MD slab "
                        "(docs/escm.md)"},
              {"atoms", fmt::format("INT {}, IVC {}, SVC {}", s.atoms[0], s.atoms[1], s.atoms[2])},
              {"continuum particles", std::to_string(s.particles)},
              {"coupled steps", fmt::format("{}{}", s.steps, s.resumed ? " (resumed)" : "")},
              {"software", version_string()},
              {"finished", utc_timestamp()},
              {"wall time", seconds_text(s.wall_s) +
                                fmt::format(" ({:.1f} % outside LAMMPS)", 100 * s.outside_share)}});
  page.section("What to do next");
  if (high)
    next.push_back("A large energy error beyond what the handshake creates: check the MD "
                   "potential (an unshifted LJ cut-off makes its energy jump, D93), the time "
                   "step and the continuum resolution (docs/escm.md).");
  next.push_back("Open the frames in ParaView; `energy.csv` and `profile.csv` hold the curves "
                 "(docs/escm.md).");
  page.list(next);
  page.section("Key numbers");
  html::Table en;
  en.caption = "Energies at the end (J, for the MD slab thickness)";
  en.header = {"quantity", "value (J)"};
  en.numeric = {false, true};
  en.side_by_side = true;
  en.rows = {{"continuum kinetic", num(e.cont_kinetic)},
             {"continuum strain", num(e.cont_strain)},
             {"MD kinetic", num(e.md_kinetic)},
             {"MD potential (from setup)", num(e.md_potential)},
             {"work of the boundary", num(e.work_boundary)},
             {"work continuum → MD (W_c→MD)", num(e.work_cont_on_md)},
             {"work MD → continuum (W_MD→c)", num(e.work_md_on_cont)},
             {"heat removed", num(e.heat_removed_int + e.heat_removed_ivc + e.heat_removed_cont)},
             {"balance", num(e.balance())}};
  page.table(en);
  const double created = e.work_cont_on_md + e.work_md_on_cont;
  Rows facts = {{"energy the handshake creates, W_c→MD + W_MD→c", num(created) + " J"},
                {"relative energy error (|balance − created| / max(|W_bc|, |created|))",
                 energy_error_text(rel, kCoupleEnergyErrorThreshold) +
                     (high ? " — above the threshold" : "")},
                {"reaction of the fixed edge along the load",
                 num(jnum(summary, "reaction_fixed_N_per_m")) + " N/m"}};
  if (summary.contains("expected_reaction_N_per_m"))
    facts.push_back({"expected reaction (strip modulus × strain × height)",
                     num(jnum(summary, "expected_reaction_N_per_m")) + " N/m"});
  if (crack.is_object()) {
    const nlohmann::json last = crack.value("last", nlohmann::json::object());
    facts.push_back({"continuum crack length", num(jnum(last, "crack_length_m")) + " m"});
    facts.push_back({"J, G_I, G_II at the last evaluation",
                     fmt::format("{}, {}, {} J/m²", num(jnum(last, "J_J_per_m2")),
                                 num(jnum(last, "GI_J_per_m2")), num(jnum(last, "GII_J_per_m2")))});
    facts.push_back({"Gc", num(jnum(crack, "Gc_J_per_m2")) + " J/m²"});
    facts.push_back({"increments", fmt::format("{} of {}", last.value("increments", 0),
                                               crack.value("max_increments", 0))});
    facts.push_back({"growth stopped because", stop});
  }
  page.facts(facts);
  std::vector<std::pair<std::string, std::string>> figs;
  for (const auto& p : s.plots) {
    const std::string n = fs::path(p).filename().string();
    figs.push_back({p, n == "profile.png"  ? "Displacement (and its gradient) across the "
                                             "handshake, continuum lines and MD cells (Å)."
                       : n == "energy.png" ? "Energy log against time (J, MD slab)."
                                           : "Crack: continuum tip, atomistic separation, "
                                             "openings against time."});
  }
  add_figures(page, run, figs, s.plot_warning);
  page.warnings(warnings);
  return page.write_report(run.out);
}
#endif

} // namespace pnc::app
