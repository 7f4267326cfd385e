// examples/dealii_fracture/demo_report.h
//
// The run report of the demo (D275): <Output/Directory>/report.html, a self-contained page
// (figures embedded, no network), and its plain-text twin report.md, written with pnc's one
// page writer pnc::html::Page (core/include/pnc/core/html_page.hpp; docs/formats.md "Run reports").
// No deal.II here: the page is built from the run's JSON summary (FractureProblem::summary()).
//
// Units: the summary is SI, each key ending with its unit (D299, D307): lengths and
// displacements `_m`, forces `_N_per_m` (2-D plane strain, per metre of thickness) or `_N` (3-D),
// energies `_J_per_m` or `_J`, times `_s`. The page shows the demo's working units, converted
// where it prints them: lengths and displacements in mm, forces in N/mm of thickness (2-D) or N
// (3-D), energies in mJ/mm (2-D) or mJ (3-D), times in s.
#ifndef PNC_EXAMPLES_DEALII_FRACTURE_DEMO_REPORT_H
#define PNC_EXAMPLES_DEALII_FRACTURE_DEMO_REPORT_H

#include <nlohmann/json.hpp>
#include <pnc/core/units.hpp>

#include <string>
#include <vector>

namespace pncdemo {

/// The demo's working units (it computes in mm, MPa, N/mm or N, mJ/mm or mJ) and their SI keys
/// and factors (pnc/core/units.hpp; D299, D307). Lengths: `_m`, pnc::units::m_per_mm.
struct DemoUnits {
  std::string force, energy;         ///< "N/mm", "mJ/mm" (2-D) or "N", "mJ" (3-D)
  std::string force_key, energy_key; ///< the SI key suffixes: "_N_per_m", "_J_per_m" or "_N", "_J"
  double force_to_si = 1;            ///< N/mm -> N/m (1e3) in 2-D; 1 (N) in 3-D
  double energy_to_si = 1;           ///< mJ/mm -> J/m (1) in 2-D; mJ -> J (1e-3) in 3-D
  /// MPa = N/mm^2 -> Pa: 1 / m_per_mm^2 = 1e6 (the VTU stresses, D318)
  double stress_to_si = 1 / (pnc::units::m_per_mm * pnc::units::m_per_mm);
};
/// The units of a `dim`-D run (2 or 3).
DemoUnits demo_units(int dim);

struct ReportInput {
  std::string command;                ///< the command line as run
  std::string parameter_file;         ///< the .prm read (empty: the defaults)
  std::vector<std::string> overrides; ///< the --set "Section/Entry=value" in order
  std::string directory;              ///< Output/Directory: report.html and report.md go there
  std::string plugin;                 ///< path of the material plugin
  int plugin_abi = 0;                 ///< its ABI version
  std::string dealii_version;         ///< deal.II's DEAL_II_PACKAGE_VERSION
  std::string loading;                ///< Loading/Path and Step in words (mm)
  double stop_fraction = 0;           ///< Loading/Stop force fraction (0: none)
  /// FractureProblem::summary() (SI keys) plus "material" (its source) and "platelet_angle_deg".
  nlohmann::json summary;
  double wall_s = 0, plot_s = 0; ///< the whole run and the plotting share (s)
  std::string png;               ///< the force-displacement figure; empty when not drawn
  std::string damage_png;        ///< the damage map; empty when not drawn
  std::string plot_note;         ///< why there is no figure (empty when there is one)
  bool plot_requested = true;    ///< Output/Plot: a missing figure is then a warning
  std::string stop;              ///< stop_text() of the run
  bool vtu = true;               ///< VTU frames and solution.pvd were written (Output/VTU every)
};

/// Where and why the run ended, in words (also the annotation of the last point in the
/// force-displacement figure): the end of the load path, the force below the stop fraction of
/// the peak, or the reason it stopped early.
std::string stop_text(const nlohmann::json& summary, double stop_fraction);

/// Writes `in.directory`/report.html and report.md (atomically) and returns the HTML path.
/// Throws pnc::InputError naming the path when a file cannot be written.
std::string write_report(const ReportInput& in);

} // namespace pncdemo

#endif // PNC_EXAMPLES_DEALII_FRACTURE_DEMO_REPORT_H
