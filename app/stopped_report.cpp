#include "stopped_report.hpp"

#include "run_control.hpp"

#include "pnc/core/version.hpp"

#include <exception>
#include <iostream>

namespace pnc::app {

std::string signal_reason(int sig) {
  return "interrupted by " + signal_name(sig);
}

void stopped_banner(html::Page& page, const RunStop& stop) {
  using html::Tone;
  const Tone tone = stop.failure ? Tone::bad : Tone::warning;
  std::vector<std::pair<Tone, std::string>> items;
  if (!stop.where.empty()) items.push_back({tone, "Stopped " + stop.where + "."});
  if (stop.valid.empty())
    items.push_back({Tone::neutral, "Valid in the output folder: no finished result yet "
                                    "(`pnc.log` holds what the run printed)."});
  for (const auto& v : stop.valid)
    items.push_back({Tone::neutral, "Valid in the output folder: " + v});
  if (!stop.resume.empty())
    items.push_back({Tone::neutral, "Continue it with `" + stop.resume + "`"});
  else if (!stop.instead.empty())
    items.push_back({Tone::neutral, stop.instead});
  page.verdict("Did not finish: " + stop.reason, tone, items);
}

std::string write_stopped_report(const std::string& dir, const std::string& title,
                                 const RunStop& stop,
                                 std::vector<std::pair<std::string, std::string>> facts) {
  html::Page page(title);
  stopped_banner(page, stop);
  page.section("What was run");
  facts.push_back({"software", version_string()});
  facts.push_back({"stopped", utc_timestamp()});
  page.facts(facts);
  page.section("What to do next");
  std::vector<std::string> next;
  if (!stop.resume.empty())
    next.push_back("Continue the run with `" + stop.resume +
                   "`: it starts from the last checkpoint and writes the full report at its end.");
  else if (!stop.instead.empty())
    next.push_back(stop.instead);
  next.push_back("`pnc.log` in the output folder holds everything the run printed.");
  page.list(next);
  return page.write_report(dir);
}

std::string try_write_stopped_report(const std::string& dir, const std::string& title,
                                     const RunStop& stop,
                                     std::vector<std::pair<std::string, std::string>> facts) {
  try {
    return write_stopped_report(dir, title, stop, std::move(facts));
  } catch (const std::exception& e) {
    std::cerr << "pnc: warning: no report for the stopped run: " << e.what() << "\n";
    return "";
  }
}

} // namespace pnc::app
