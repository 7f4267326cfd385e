#include "drive_report.hpp"
#include "stopped_report.hpp"

#include "fit_report.hpp"

#include "pnc/core/html_page.hpp"
#include "pnc/core/version.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

namespace pnc::app {

namespace {
namespace fs = std::filesystem;
using html::Tone;
const char* kStrain[6] = {"ε11", "ε22", "ε33", "γ23", "γ13", "γ12"};
const char* kStress[6] = {"σ11", "σ22", "σ33", "σ23", "σ13", "σ12"};
} // namespace

std::string write_drive_report(const DriveRun& run) {
  const DriveResult& r = run.result;
  const DriveRecord& last = r.rows.back();
  const std::string stem = fs::path(run.out).replace_extension("").string();
  const std::string html_path = stem + "_report.html";
  html::Page page("pnc material drive: " + fs::path(run.meta.card).filename().string() + " along " +
                  fs::path(run.meta.path).filename().string());
  const int steps = static_cast<int>(r.rows.size()) - 1;
  std::vector<std::string> next;
  if (!r.converged) { // the banner of every run that stopped early (stopped_report.hpp)
    stopped_banner(page,
                   {r.failure,
                    fmt::format("after {} of {} steps (the next step did not converge)", steps,
                                run.planned_steps),
                    {fmt::format("`{}`: steps 0 to {}, each converged", run.out, steps)},
                    "",
                    "There is nothing to resume: change the path (see What to do next) and run it "
                    "again.",
                    true});
    next.push_back("A stress-controlled step did not converge: the law has no state with that "
                   "stress (past its peak, softening) — drive that segment in strain, or use "
                   "smaller steps up to it.");
  } else if (!run.mismatches.empty()) {
    page.verdict(
        fmt::format("Outside the reference tolerances: {} value(s)", run.mismatches.size()),
        Tone::bad, {{Tone::bad, "reference " + run.reference}});
    next.push_back("The response differs from the reference: a changed card or plugin, or "
                   "tolerances too tight for the platform (`--tol-rel`, `--tol-stress`, ...; "
                   "docs/drive.md).");
  } else {
    page.verdict(fmt::format("Completed: {} of {} steps{}", steps, run.planned_steps,
                             run.reference.empty() ? "" : ", within the reference tolerances"),
                 Tone::good, {});
  }
  if (run.meta.verdict != "usable")
    next.push_back("The card's own verdict is \"" + run.meta.verdict +
                   "\": read its reasons with `pnc card show` before relying on the response.");
  if (next.empty())
    next.push_back("Use the same card in your solver (docs/plugin.md, docs/hosts.md); this path "
                   "and its output can serve as a reference file (`--reference`).");
  page.section("What was run");
  page.facts({{"command", "`" + run.meta.command + "`"},
              {"card", fmt::format("`{}` (model {}, verdict {})", run.meta.card, run.meta.model,
                                   run.meta.verdict)},
              {"path", "`" + run.meta.path + "`"},
              {"plugin", "`" + run.meta.plugin + "`"},
              {"output", "`" + run.out + "`"},
              {"software", version_string()},
              {"finished", utc_timestamp()},
              {"wall time", seconds_text(run.seconds)}});
  page.section("What to do next");
  page.list(next);
  page.section("Figure");
  if (run.png.empty())
    page.paragraph("Not drawn (--no-plot, or a single step).");
  else
    page.figure(run.png,
                "Response of every moving component, stress and strain per step, state "
                "and energy account.",
                fs::relative(run.png, fs::path(run.out).parent_path().empty()
                                          ? fs::path(".")
                                          : fs::path(run.out).parent_path())
                    .string());
  page.section("Key numbers");
  html::Table end;
  end.caption = fmt::format("State after step {} (strain dimensionless, engineering shear)", steps);
  end.header = {"component", "strain", "stress (MPa)"};
  end.numeric = {false, true, true};
  end.side_by_side = true;
  for (int i = 0; i < 6; ++i)
    end.rows.push_back({std::string(kStress[i]) + " / " + kStrain[i],
                        fmt::format("{:.6g}", last.strain[static_cast<std::size_t>(i)]),
                        fmt::format("{:.6g}", last.stress[static_cast<std::size_t>(i)] / 1e6)});
  page.table(end);
  html::Table en;
  en.caption = "Energy densities (J/m³)";
  en.header = {"quantity", "value"};
  en.numeric = {false, true};
  en.side_by_side = true;
  en.rows = {{"external work", fmt::format("{:.6g}", last.work)},
             {"stored", fmt::format("{:.6g}", last.stored)},
             {"dissipated", fmt::format("{:.6g}", last.dissipated)},
             {"balance error", fmt::format("{:.3g}", last.work - last.stored - last.dissipated)}};
  if (r.mixed)
    en.rows.push_back(
        {"Newton: most iterations in a step",
         fmt::format("{} (residual ≤ {:.3g} Pa)", r.max_newton_iterations, r.residual_tolerance)});
  page.table(en);
  if (!run.mismatches.empty()) {
    page.section("Values outside the reference tolerances");
    html::Table m;
    m.caption = fmt::format("First {} of {} (tolerance: abs + {:.3g} |reference|)",
                            std::min<std::size_t>(run.mismatches.size(), 20), run.mismatches.size(),
                            run.tol.rel);
    m.header = {"step", "column", "value", "reference", "|difference|", "tolerance"};
    m.numeric = {true, false, true, true, true, true};
    for (std::size_t i = 0; i < run.mismatches.size() && i < 20; ++i) {
      const Mismatch& x = run.mismatches[i];
      m.rows.push_back({std::to_string(x.step), x.column, fmt::format("{:.10g}", x.value),
                        fmt::format("{:.10g}", x.reference),
                        fmt::format("{:.3g}", std::abs(x.value - x.reference)),
                        fmt::format("{:.3g}", x.tolerance)});
    }
    page.table(m);
  }
  page.write(html_path, stem + "_report.md");
  return html_path;
}

} // namespace pnc::app
