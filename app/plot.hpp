#pragma once
// The runner of pnc's plot scripts (matplotlib); the figures of fit and characterize are
// described in figures.hpp and drawn by scripts/plot_figures.py through it.
#include <string>
#include <vector>

namespace pnc::app {

/// Runs <prefix>/share/pnc/scripts/<script> (or $PNC_SCRIPTS_DIR/<script>; locate.hpp) with
/// $PNC_PYTHON (default: the python3 found at configure time) and
/// `args`; returns the paths the script reports on lines "wrote <path>". A plot is never what
/// a command is for: when the interpreter cannot start or the script fails (no
/// python3-matplotlib), one line "pnc: warning: ..." naming the interpreter or script and
/// carrying its output goes to stderr and no path is returned (docs/errors.md). A script
/// missing from the installation is a pnc::InputError naming where it was looked for.
/// With `warning` given, that line's text is stored there instead of printed (the caller
/// prints it once with its own context and puts it in its report).
std::vector<std::string> run_plot_script(const std::string& script,
                                         const std::vector<std::string>& args,
                                         std::string* warning = nullptr);

} // namespace pnc::app
