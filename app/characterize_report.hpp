#pragma once
// The report of a `pnc characterize` run (report.html and its plain-text twin report.md in the
// run folder) and its figures: the fit of the MD data (fit_report.hpp) and the MD stresses of
// every case, all six components, as measured next to relative to the reference state, with
// error bars on every averaged point. Stresses in MPa on the page; cases.h5 stays SI.
#include "figures.hpp"

#include "pnc/damage/card.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/rve/characterize.hpp"
#include "pnc/rve/recipe.hpp"
#include "pnc/rve/replica_bootstrap.hpp"
#include "pnc/rve/replica_fits.hpp"
#include "pnc/rve/replica_trend.hpp"
#include "pnc/rve/sense_pairs.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pnc::app {

struct CharacterizeRun {
  const rve::Recipe& recipe;
  const rve::MdOutcome& md;
  const damage::StressStrainData& data; ///< cases.h5 as fitted
  const damage::FitReport& rep;         ///< the joint fit
  const damage::Card& card;             ///< as written (errors and verdict of the MD gates)
  const rve::ReplicaFits& replica_fits;
  const rve::ReplicaBootstrap& bootstrap; ///< calibration check of the card's errors (D431)
  const rve::ReplicaTrend& trend;
  const std::vector<rve::SensePair>& senses; ///< shears run both ways (D428); empty: none
  double max_shape_error; ///< the tolerance of the shape error the verdict used (D417)
  damage::Model model;
  std::string out, command;
  nlohmann::json clay_info; ///< read_clay_info
  double seconds = 0;       ///< wall time of this invocation, s
  bool plots_requested = true;
  PlotOutcome plots;
};

/// clay.json next to the build record (model pnc), or null.
nlohmann::json read_clay_info(const rve::Recipe& r, const rve::MdOutcome& md);

/// The figures of a run, to be drawn in `plots_dir`: fit.png (fit_figure) and stress.png (per
/// case: the stress as measured, including the zero-strain reference state, and relative to
/// the reference, as fitted; every component, so the normal stresses of the shear cases too).
std::vector<Figure> characterize_figures(const rve::Recipe& r, const rve::MdOutcome& md,
                                         const damage::StressStrainData& data,
                                         const damage::Card& card,
                                         const std::vector<rve::SensePair>& senses,
                                         const std::string& plots_dir);

/// Writes report.md and report.html in the run folder; returns the path of report.md.
std::string write_characterize_report(const CharacterizeRun& c);

/// The summary on stderr: constants, fit quality, verdict, RVE state, where the outputs are.
void print_characterize_summary(const CharacterizeRun& c, const std::string& card_path,
                                const std::string& report_path, const std::string& html_path);
/// The `--json` summary of `pnc characterize` (keys state their units).
nlohmann::json characterize_json(const CharacterizeRun& c, const std::string& card_path,
                                 const std::string& report_path, const std::string& html_path);

} // namespace pnc::app
