#pragma once
// The parts of a run report that concern a fitted card, shared by `pnc fit` and
// `pnc characterize`: the fit figure (data +- standard errors, fitted curves, residuals, R^2,
// fit range), the verdict in colour, the key numbers (constants +- errors, fit quality, both
// readings of the moduli, strengths) and "what to do next" for each failed gate.
// Stresses in MPa and stiffnesses in GPa on the page; the card itself stays SI.
#include "figures.hpp"

#include "pnc/core/html_page.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/data.hpp"

#include <string>
#include <vector>

namespace pnc::app {

/// One panel per case and fitted stress component (the components the model makes non-zero):
/// the data with their stored standard errors as error bars (when present), the NDM through
/// the kernel as a line, a residual panel under it (residual / point error when errors exist,
/// else MPa), R^2 in the title, the rows beyond the fit range (card.fit.strain_max) shaded.
Figure fit_figure(const damage::StressStrainData& data, const damage::Card& card,
                  const std::string& png, const std::string& title);

html::Tone verdict_tone(damage::VerdictLevel level);
/// The verdict box: level in words, each reason coloured (red "not usable", amber "warning").
void add_verdict(html::Page& page, const damage::Verdict& v);
/// Advice for each finding of the verdict (what would fix it), without repeats. `md_run`:
/// name the recipe keys of `pnc characterize` instead of the options of `pnc fit`.
std::vector<std::string> next_steps(const damage::Verdict& v, bool md_run);
/// Key numbers: constants (value, standard error, units, status), fit quality per curve,
/// derived moduli in both readings (as `pnc card show`), strength of each case.
void add_card_numbers(html::Page& page, const damage::Card& card);
/// The "Warnings" section: the solver's and the plotting's warnings (the verdict's findings
/// are in its box at the top, referred to, not repeated).
void add_warnings(html::Page& page, const damage::Verdict& v, const std::string& solver,
                  const std::string& figures);
/// Short label of a deformation case, e.g. "extension x1", "simple shear 2-3".
std::string case_label(int case_id);
/// Wall time in words: "0.84 s", "3 min 12 s".
std::string seconds_text(double s);

struct FitRun {
  std::string command_line, data, card, plots_dir; ///< plots_dir empty: --no-plots
  double seconds = 0;                              ///< wall time of the command so far
  PlotOutcome plots;
};
/// `pnc fit`'s report: `<card>_report.html` and `<card>_report.md` next to the card.
/// Returns the HTML path.
std::string write_fit_report(const FitRun& run, const damage::StressStrainData& data,
                             const damage::Card& card);

} // namespace pnc::app
