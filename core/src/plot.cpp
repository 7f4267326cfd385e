// The runner of pnc's plot scripts (plot.hpp, D337, D338).
#include "pnc/core/plot.hpp"

#include "pnc/core/locate.hpp"
#include "pnc/core/params.hpp"
#include "pnc/core/subprocess.hpp"

#include <atomic>
#include <cstdlib>
#include <iostream>
#include <sstream>

#ifndef PNC_PYTHON
#define PNC_PYTHON "/usr/bin/python3"
#endif

namespace pnc {

namespace {

/// `what` on one line, clipped (a Python traceback becomes one warning line).
std::string one_line(const std::string& what) {
  std::string line = what;
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  while (!line.empty() && line.back() == ' ')
    line.pop_back();
  return clip(line, 600);
}

bool set(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0';
}

} // namespace

const char* plot_scripts_variable() {
  if (set("PNC_SCRIPTS_DIR") || !set("PNC_GIMP_SCRIPTS_DIR")) return "PNC_SCRIPTS_DIR";
  static std::atomic<bool> told{false};
  if (!told.exchange(true))
    std::cerr << "pnc: warning: PNC_GIMP_SCRIPTS_DIR is deprecated; set PNC_SCRIPTS_DIR "
                 "instead (docs/install.md)\n";
  return "PNC_GIMP_SCRIPTS_DIR";
}

PlotRun run_plot(const std::string& script_name, const std::vector<std::string>& args) {
  PlotRun out;
  const char* env_py = std::getenv("PNC_PYTHON");
  const std::string py = env_py && *env_py ? env_py : PNC_PYTHON;
  out.script = require_shipped(ShippedDir::scripts, script_name, plot_scripts_variable());
  std::vector<std::string> argv = {py, out.script};
  argv.insert(argv.end(), args.begin(), args.end());
  const SubprocessResult r = run_subprocess(argv);
  if (!r.started) {
    out.output = r.error;
    out.warning = one_line(py + ": cannot start the Python interpreter for plotting: " + r.error);
    return out;
  }
  out.output = r.output;
  if (!r.ok()) {
    const std::string how = r.signal ? "killed by signal " + std::to_string(r.signal)
                                     : "exit status " + std::to_string(r.exit_code);
    out.warning =
        one_line(out.script + ": plotting failed (" + how + "; needs python3-matplotlib)" +
                 (r.output.empty() ? std::string() : ": " + r.output));
    return out;
  }
  std::istringstream lines(r.output);
  std::string line;
  while (std::getline(lines, line))
    if (line.rfind("wrote ", 0) == 0) out.pngs.push_back(line.substr(6));
  return out;
}

std::vector<std::string> run_plot_script(const std::string& script_name,
                                         const std::vector<std::string>& args,
                                         std::string* warning) {
  PlotRun r = run_plot(script_name, args);
  if (r.ok()) return std::move(r.pngs);
  if (warning)
    *warning = r.warning;
  else
    std::cerr << "pnc: warning: no plot: " << r.warning << "\n";
  return {};
}

} // namespace pnc
