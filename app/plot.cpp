#include "plot.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/locate.hpp"
#include "pnc/core/params.hpp"
#include "pnc/core/subprocess.hpp"
#include "pnc/damage/reference.hpp"

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
/// One line on stderr: the results are written, only the figure is missing.
void plot_warning(const std::string& what) {
  std::string line = what;
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  while (!line.empty() && line.back() == ' ')
    line.pop_back();
  std::cerr << "pnc: warning: no plot: " << clip(line, 600) << "\n";
}
} // namespace

std::vector<std::string> run_plot_script(const std::string& script_name,
                                         const std::vector<std::string>& args) {
  const char* env_py = std::getenv("PNC_PYTHON");
  const std::string py = env_py && *env_py ? env_py : PNC_PYTHON;
  // share/pnc/scripts relative to the executable, or $PNC_SCRIPTS_DIR (D151)
  const std::string script = require_shipped(ShippedDir::scripts, script_name, "PNC_SCRIPTS_DIR");
  // argument vector, no shell: a quote or ';' in a path or title is data
  std::vector<std::string> argv = {py, script};
  argv.insert(argv.end(), args.begin(), args.end());
  const SubprocessResult r = run_subprocess(argv);
  if (!r.started) {
    plot_warning(py + ": cannot start the Python interpreter for plotting: " + r.error);
    return {};
  }
  const std::string& out = r.output;
  if (!r.ok()) {
    const std::string how = r.signal ? "killed by signal " + std::to_string(r.signal)
                                     : "exit status " + std::to_string(r.exit_code);
    plot_warning(script + ": plotting failed (" + how + "; needs python3-matplotlib)" +
                 (out.empty() ? std::string() : ": " + out));
    return {};
  }
  std::vector<std::string> pngs;
  std::istringstream lines(out);
  std::string line;
  while (std::getline(lines, line))
    if (line.rfind("wrote ", 0) == 0) pngs.push_back(line.substr(6));
  return pngs;
}

std::vector<std::string> plot_fit(const damage::StressStrainData& data,
                                  const damage::NdmParameters& p, const std::string& dir,
                                  const std::string& title) {
  make_output_directory(dir, "--plots");
  // Model curve on a fine grid of the driven strain (a monotonic path from zero) and the
  // data points, for every case and active component.
  std::ostringstream csv;
  csv.precision(10);
  csv << "kind,case,component,strain,stress_mpa\n";
  for (const auto& c : data.cases) {
    const auto& dc = damage::deformation_case(c.id);
    for (Eigen::Index k = 0; k < c.strain.rows(); ++k)
      for (int comp : dc.active)
        csv << "data," << c.id << ',' << comp << ',' << c.strain(k, dc.driven) << ','
            << c.stress(k, comp) / 1e6 << '\n';
    const double top = c.strain.col(dc.driven).maxCoeff();
    const int n = 400;
    damage::PathMatrix path(n + 1, 6);
    for (int i = 0; i <= n; ++i)
      path.row(i) = damage::case_strain(c.id, top * i / n).transpose();
    const auto s = damage::stress_path(p, path);
    for (int i = 0; i <= n; ++i)
      for (int comp : dc.active)
        csv << "model," << c.id << ',' << comp << ',' << path(i, dc.driven) << ','
            << s(i, comp) / 1e6 << '\n';
  }
  const std::string curves = (fs::path(dir) / "curves.csv").string();
  write_text_atomically(curves, csv.str());

  return run_plot_script("plot_fit.py", {curves, dir, title});
}

} // namespace pnc::app
