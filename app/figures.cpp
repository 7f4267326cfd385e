#include "figures.hpp"

#include "pnc/core/plot.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/locate.hpp"
#include "pnc/core/progress.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <iostream>

namespace pnc::app {

namespace {

// NaN and inf become null (drawn as gaps)
nlohmann::json numbers(const std::vector<double>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (double x : v)
    a.push_back(std::isfinite(x) ? nlohmann::json(x) : nlohmann::json());
  return a;
}

nlohmann::json series_json(const Series& s) {
  const char* style = s.style == Series::Style::line          ? "line"
                      : s.style == Series::Style::line_points ? "line_points"
                                                              : "points";
  nlohmann::json j = {{"style", style},
                      {"label", s.label},
                      {"x", numbers(s.x)},
                      {"y", numbers(s.y)},
                      {"colour", s.colour}};
  if (!s.yerr.empty()) j["yerr"] = numbers(s.yerr);
  if (s.width > 0) j["width"] = s.width;
  return j;
}

// A plotting failure carries the script's whole output (a Python traceback): its first line
// and the last one (the exception) are what a user needs.
std::string one_line(const std::string& msg) {
  const auto first = msg.find('\n');
  if (first == std::string::npos) return msg;
  auto end = msg.find_last_not_of("\n ");
  const auto start = msg.rfind('\n', end);
  const std::string last = msg.substr(start + 1, end - start);
  return msg.substr(0, first) + " ... " + last;
}

} // namespace

PlotOutcome draw_figures(const std::vector<Figure>& figures, const std::string& jobs_json,
                         const std::string& who) {
  PlotOutcome out;
  if (figures.empty()) return out;
  nlohmann::json jobs = {{"format", "pnc figure jobs v1 (scripts/plot_figures.py)"},
                         {"figures", nlohmann::json::array()}};
  for (const Figure& f : figures) {
    nlohmann::json jf = {{"png", f.png},
                         {"title", f.title},
                         {"columns", f.columns},
                         {"panels", nlohmann::json::array()}};
    for (const Panel& p : f.panels) {
      nlohmann::json jp = {{"title", p.title},
                           {"xlabel", p.xlabel},
                           {"ylabel", p.ylabel},
                           {"series", nlohmann::json::array()}};
      for (const Series& s : p.series)
        jp["series"].push_back(series_json(s));
      if (std::isfinite(p.fit_limit)) jp["fit_limit"] = p.fit_limit;
      if (!p.residual.x.empty()) {
        jp["residual"] = series_json(p.residual);
        jp["residual_label"] = p.residual_label;
      }
      jf["panels"].push_back(jp);
    }
    jobs["figures"].push_back(jf);
  }
  write_text_atomically(jobs_json, jobs.dump());

  Phase phase(who, fmt::format("plotting {} figure{}", figures.size(),
                               figures.size() == 1 ? "" : "s")); // D344
  // a missing script is a broken installation (or a wrong PNC_SCRIPTS_DIR): an error
  (void)require_shipped(ShippedDir::scripts, "plot_figures.py", plot_scripts_variable());
  const auto t0 = std::chrono::steady_clock::now();
  try {
    out.pngs = run_plot_script("plot_figures.py", {jobs_json}, &out.warning);
    if (out.warning.empty() && out.pngs.size() != figures.size())
      out.warning =
          fmt::format("the plot script drew {} of {} figures", out.pngs.size(), figures.size());
  } catch (const InputError& e) {
    out.warning = one_line(e.what());
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (out.warning.empty())
    phase.done(
        fmt::format("plotted {} figure{}", out.pngs.size(), out.pngs.size() == 1 ? "" : "s"));
  else
    std::cerr << fmt::format("{}: warning: figures not drawn: {}\n", who, out.warning);
  return out;
}

} // namespace pnc::app
