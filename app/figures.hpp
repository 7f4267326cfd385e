#pragma once
// Figures of a run, drawn in ONE plotting process after the results are written: the command
// describes its figures (panels of series, with an optional residual panel under each) in C++,
// draw_figures() writes them as a JSON job list and runs scripts/plot_figures.py once
// (matplotlib). A plotting failure (no python3, no matplotlib) is a warning the caller prints
// and puts in its report; it never changes the command's exit code. Units are in the labels
// (stress in MPa, strain dimensionless).
#include <limits>
#include <string>
#include <vector>

namespace pnc::app {

struct Series {
  /// points (markers, error bars when yerr is given), line, or both (markers joined by a
  /// thin line, for short MD curves)
  enum class Style { points, line, line_points } style = Style::points;
  std::string label;
  std::vector<double> x, y;
  std::vector<double> yerr; ///< empty, or one standard error per point (same units as y)
  int colour = -1;          ///< index into the script's palette; -1 = next
  double width = 0;         ///< line width (points); 0 = the script's default
};

struct Panel {
  std::string title, xlabel, ylabel;
  std::vector<Series> series;
  /// x beyond this is shaded and labelled "not fitted" (the fit range); NaN = none
  double fit_limit = std::numeric_limits<double>::quiet_NaN();
  /// residual panel under the main one when residual.x is not empty; zero line drawn
  Series residual;
  std::string residual_label;
};

struct Figure {
  std::string png, title;
  int columns = 3;
  std::vector<Panel> panels;
};

struct PlotOutcome {
  std::vector<std::string> pngs; ///< the PNGs the script reports, in job order
  std::string warning;           ///< empty when every figure was drawn
  double seconds = 0;            ///< wall time of the plotting process
};

/// Writes `figures` as a JSON job list to `jobs_json` (atomically; kept next to the figures:
/// the plotted numbers) and draws them all in one run of plot_figures.py (run_plot_script,
/// pnc/core/plot.hpp). Prints "<who>: plotting N figure(s) ..." and then the time taken on stderr.
/// Never throws for a plotting failure (no interpreter, no matplotlib, a script error): it
/// comes back as `warning` (also printed). A missing plot_figures.py (a broken installation
/// or a wrong $PNC_SCRIPTS_DIR) is a pnc::InputError naming the variable.
PlotOutcome draw_figures(const std::vector<Figure>& figures, const std::string& jobs_json,
                         const std::string& who);

} // namespace pnc::app
