#pragma once
// Plots of fitted NDM curves against the data, drawn by scripts/plot_fit.py (matplotlib).
#include "pnc/damage/data.hpp"
#include "pnc/damage/ndm.hpp"

#include <string>
#include <vector>

namespace pnc::app {

/// One PNG per case in `dir` (created if needed): each active stress component against the
/// driven strain, data as points, the NDM (through the kernel) as a line. Stresses in MPa.
/// Returns the PNG paths (none when the plot could not be drawn: a warning, see below).
/// Runs <prefix>/share/pnc/scripts/<script> (or $PNC_SCRIPTS_DIR/<script>; locate.hpp) with
/// $PNC_PYTHON (default: the python3 found at configure time) and
/// `args`; returns the paths the script reports on lines "wrote <path>". A plot is never what
/// a command is for: when the interpreter cannot start or the script fails (no
/// python3-matplotlib), one line "pnc: warning: ..." naming the interpreter or script and
/// carrying its output goes to stderr and no path is returned (docs/errors.md). A script
/// missing from the installation is a pnc::InputError naming where it was looked for.
std::vector<std::string> run_plot_script(const std::string& script,
                                         const std::vector<std::string>& args);

std::vector<std::string> plot_fit(const damage::StressStrainData& data,
                                  const damage::NdmParameters& p, const std::string& dir,
                                  const std::string& title);

} // namespace pnc::app
