#include "plot.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/locate.hpp"
#include "pnc/core/params.hpp"
#include "pnc/core/subprocess.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#ifndef PNC_PYTHON
#define PNC_PYTHON "/usr/bin/python3"
#endif

namespace pnc::app {

namespace fs = std::filesystem;

namespace {
/// One line on stderr (or in `*sink`): the results are written, only the figure is missing.
void plot_warning(const std::string& what, std::string* sink) {
  std::string line = what;
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  while (!line.empty() && line.back() == ' ')
    line.pop_back();
  if (sink)
    *sink = clip(line, 600);
  else
    std::cerr << "pnc: warning: no plot: " << clip(line, 600) << "\n";
}
} // namespace

std::vector<std::string> run_plot_script(const std::string& script_name,
                                         const std::vector<std::string>& args,
                                         std::string* warning) {
  const char* env_py = std::getenv("PNC_PYTHON");
  const std::string py = env_py && *env_py ? env_py : PNC_PYTHON;
  // share/pnc/scripts relative to the executable, or $PNC_SCRIPTS_DIR (D151)
  const std::string script = require_shipped(ShippedDir::scripts, script_name, "PNC_SCRIPTS_DIR");
  // argument vector, no shell: a quote or ';' in a path or title is data
  std::vector<std::string> argv = {py, script};
  argv.insert(argv.end(), args.begin(), args.end());
  const SubprocessResult r = run_subprocess(argv);
  if (!r.started) {
    plot_warning(py + ": cannot start the Python interpreter for plotting: " + r.error, warning);
    return {};
  }
  const std::string& out = r.output;
  if (!r.ok()) {
    const std::string how = r.signal ? "killed by signal " + std::to_string(r.signal)
                                     : "exit status " + std::to_string(r.exit_code);
    plot_warning(script + ": plotting failed (" + how + "; needs python3-matplotlib)" +
                     (out.empty() ? std::string() : ": " + out),
                 warning);
    return {};
  }
  std::vector<std::string> pngs;
  std::istringstream lines(out);
  std::string line;
  while (std::getline(lines, line))
    if (line.rfind("wrote ", 0) == 0) pngs.push_back(line.substr(6));
  return pngs;
}

} // namespace pnc::app
