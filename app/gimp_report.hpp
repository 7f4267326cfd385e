#pragma once
// The run reports of `pnc gimp run` and `pnc gimp couple` (`<out>/report.html` and its
// plain-text twin `<out>/report.md`; docs/formats.md "Run reports"): what was run, the verdict
// in words, the key numbers (energies, relative energy error against its threshold, reactions,
// cracks: G against Gc, increments and why growth stopped), the figures the solver drew, the
// warnings and what to do next. Written with pnc::html::Page.
// Units: SI. 2-D quantities are per metre of thickness (energies J/m, forces N/m); G in J/m²;
// `pnc gimp couple` energies are those of the MD slab (J), its reactions N/m (docs/escm.md).
#include "pnc/gimp_coupler/run.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace pnc::gimp::escm {
struct CoupleSummary;
}

namespace pnc::app {

/// D271: a `pnc gimp run` whose relative energy error exceeds this is reported with a warning.
inline constexpr double kEnergyErrorThreshold = 0.01;
/// D271: the same for `pnc gimp couple`, whose staggered handshake is not energy-exact: the
/// tolerance of its tested energy log (docs/escm.md, escm.LjCrystalTensionMatchesContinuum).
inline constexpr double kCoupleEnergyErrorThreshold = 0.15;

/// Relative energy error of `pnc gimp run` (D271): the largest |energy error| over the history
/// over the energy scale of the run, max(|E0|, |W_ext| + |W_bc|, KE + SE) at the end; 0 when
/// the scale is 0.
double gimp_relative_energy_error(const gimp::RunSummary& s);

struct GimpRunInfo {
  std::string command_line, input, out;
  bool plot = true; ///< false: --no-plot
};

/// `pnc gimp run`. `summary`: the run's summary.json (cracks, tips). Returns the HTML path.
std::string write_gimp_run_report(const GimpRunInfo& run, const gimp::RunSummary& s,
                                  const nlohmann::json& summary);

#ifdef PNC_GIMP_HAS_ESCM
/// Relative energy error of `pnc gimp couple` (D271): the part of the balance the handshake
/// does not account for, |balance - created| with created = W_c->MD + W_MD->c, over
/// max(|W_bc|, |created|) of the last energy row; 0 when that is 0.
double couple_relative_energy_error(const gimp::escm::CoupleSummary& s);
/// `pnc gimp couple`. `summary`: its summary.json. Returns the HTML path.
std::string write_gimp_couple_report(const GimpRunInfo& run, const gimp::escm::CoupleSummary& s,
                                     const nlohmann::json& summary, bool short_mode);
#endif

} // namespace pnc::app
