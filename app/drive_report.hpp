#pragma once
// The run report of `pnc material drive` (`<out>_report.html` and `<out>_report.md` next to the
// output table; docs/drive.md): the outcome in colour (completed, stopped early, outside the
// reference tolerances), what was run, the end state and the energy account, the figure, the
// values outside the reference tolerances, and what to do next. Written with pnc::html::Page.
#include "drive.hpp"
#include "drive_output.hpp"

#include <string>
#include <vector>

namespace pnc::app {

struct DriveRun {
  const DriveResult& result;
  const DriveMeta& meta;
  std::string out, png, reference; ///< png / reference empty: none
  long long planned_steps = 0;
  double seconds = 0; ///< wall time of the command, s
  std::vector<Mismatch> mismatches;
  Tolerances tol;
};

/// Writes the page and its twin; returns the HTML path.
std::string write_drive_report(const DriveRun& run);

} // namespace pnc::app
