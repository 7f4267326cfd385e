#pragma once
// Plots of fitted NDM curves against the data, drawn by scripts/plot_fit.py (matplotlib).
#include "pnc/damage/data.hpp"
#include "pnc/damage/ndm.hpp"

#include <string>
#include <vector>

namespace pnc::app {

/// One PNG per case in `dir` (created if needed): each active stress component against the
/// driven strain, data as points, the NDM (through the kernel) as a line. Stresses in MPa.
/// Returns the PNG paths. Throws pnc::InputError naming the interpreter or script on failure.
/// Runs <prefix>/share/pnc/scripts/<script> (or $PNC_SCRIPTS_DIR/<script>; locate.hpp) with
/// $PNC_PYTHON (default: the python3 found at configure time) and
/// `args`; returns the paths the script reports on lines "wrote <path>". Throws
/// pnc::InputError naming the script and carrying its output when it fails.
std::vector<std::string> run_plot_script(const std::string& script,
                                         const std::vector<std::string>& args);

std::vector<std::string> plot_fit(const damage::StressStrainData& data,
                                  const damage::NdmParameters& p, const std::string& dir,
                                  const std::string& title);

} // namespace pnc::app
