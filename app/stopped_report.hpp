#pragma once
// The "did not finish" banner of a run report (docs/formats.md "Run reports"): a run that
// stopped early (a signal, a step limit or a simulation failure) still leaves report.html and
// report.md, and their first block says so in words: why it stopped, where (step, time and
// its unit), what in the output folder is valid, and how to continue it. Every long command
// uses this one helper, in its own report writer or, when the run ended before the data of its
// full report existed, through write_stopped_report().
#include "pnc/core/html_page.hpp"

#include <string>
#include <utility>
#include <vector>

namespace pnc::app {

struct RunStop {
  /// Why, in words: "interrupted by SIGINT", "--max-steps (20) reached", the failure message.
  std::string reason;
  /// Where: "after step 120 at t = 0.00012 s" (units in the text).
  std::string where;
  /// What in the output folder is valid, one item each ("`history.csv`: steps 0-120").
  std::vector<std::string> valid;
  /// The command that continues the run; empty: the run cannot be continued (see `instead`).
  std::string resume;
  /// Without `resume`: what to do instead (e.g. "rerun with a smaller time step").
  std::string instead;
  /// true: a failure (red); false: a stop on request (signal, step limit; amber).
  bool failure = false;
};

/// "interrupted by SIGINT" (signal_name() of run_control.hpp).
std::string signal_reason(int sig);

/// Adds the banner: a verdict "Did not finish: REASON" with the where, the valid files and the
/// resume command (or what to do instead) as its items. Call it first, before any section.
void stopped_banner(html::Page& page, const RunStop& stop);

/// A short report for a run that stopped before its full report could be assembled: the
/// banner, "What was run" (`facts`, to which software and time are appended) and "What to do
/// next". Writes `dir`/report.html and `dir`/report.md; returns the HTML path.
std::string write_stopped_report(const std::string& dir, const std::string& title,
                                 const RunStop& stop,
                                 std::vector<std::pair<std::string, std::string>> facts);

/// Writes the stopped report as write_stopped_report() does but never throws: the run's own
/// error must reach the user even when its folder cannot be written. Returns the HTML path, or
/// "" (and prints one line saying why) when the report could not be written.
std::string try_write_stopped_report(const std::string& dir, const std::string& title,
                                     const RunStop& stop,
                                     std::vector<std::pair<std::string, std::string>> facts);

} // namespace pnc::app
