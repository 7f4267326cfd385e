#pragma once
// pnc/core/plot.hpp: the one runner of pnc's plot scripts (matplotlib), used by every command
// that draws a figure (`pnc fit`, `pnc characterize`, `pnc thermo`, `pnc material drive`,
// `pnc gimp run`, `pnc gimp couple`; D337). A plot is never what a command is for: when the
// interpreter cannot start or the script fails (no python3-matplotlib), the caller gets a
// warning and writes its results anyway (docs/errors.md).
//
// The interpreter: $PNC_PYTHON if set and not empty, else the python3 found at configure time.
// The scripts: <prefix>/share/pnc/scripts (found relative to the executable, locate.hpp, D151)
// or $PNC_SCRIPTS_DIR. $PNC_GIMP_SCRIPTS_DIR is a deprecated alias of $PNC_SCRIPTS_DIR (D338):
// used only when $PNC_SCRIPTS_DIR is unset or empty, with one warning line on stderr.
// Scripts run with an argument vector, never through a shell: a quote or ';' in a path or a
// title is data.
#include <string>
#include <vector>

namespace pnc {

/// What one run of a plot script gave.
struct PlotRun {
  std::string script;            ///< the script's path (the name when it was not found)
  std::vector<std::string> pngs; ///< the paths the script reported on lines "wrote <path>"
  std::string output;            ///< its stdout and stderr, or why the interpreter did not start
  std::string warning;           ///< one line naming the interpreter or script; "" on success
  bool ok() const { return warning.empty(); }
};

/// The environment variable that overrides the scripts' directory ("PNC_SCRIPTS_DIR", or the
/// deprecated "PNC_GIMP_SCRIPTS_DIR" when only that one is set; the first such use prints one
/// deprecation warning on stderr).
const char* plot_scripts_variable();

/// Runs the plot script `script_name` with `args` (see the file comment) and returns what it
/// gave; never prints. A script missing from the installation is a pnc::InputError naming
/// where it was looked for and the variable that overrides it (require_shipped).
PlotRun run_plot(const std::string& script_name, const std::vector<std::string>& args);

/// run_plot() for the commands that only need the figures: returns the reported paths. On a
/// plotting failure one line "pnc: warning: no plot: ..." carrying the script's output goes to
/// stderr and nothing is returned; with `warning` given, that line's text is stored there
/// instead of printed (the caller prints it once with its own context and puts it in its
/// report). A missing script throws as in run_plot().
std::vector<std::string> run_plot_script(const std::string& script_name,
                                         const std::vector<std::string>& args,
                                         std::string* warning = nullptr);

} // namespace pnc
