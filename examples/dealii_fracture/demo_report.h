// examples/dealii_fracture/demo_report.h
//
// The run report of the demo (D275): <Output/Directory>/report.html, a self-contained page
// (figures embedded, no network), and its plain-text twin report.md, written with pnc's one
// page writer pnc::html::Page (core/include/pnc/core/html_page.hpp; docs/formats.md "Run reports").
// No deal.II here: the page is built from the run's JSON summary (FractureProblem::summary()).
//
// Units: lengths and displacements in mm, forces in N/mm of thickness (2-D plane strain) or N
// (3-D), energies in mJ/mm (2-D) or mJ (3-D), times in s.
#ifndef PNC_EXAMPLES_DEALII_FRACTURE_DEMO_REPORT_H
#define PNC_EXAMPLES_DEALII_FRACTURE_DEMO_REPORT_H

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pncdemo {

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
  /// FractureProblem::summary() plus "material" (its source) and "platelet_angle_deg".
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

/// The `--json` object the demo prints (D299): `summary` (FractureProblem::summary() plus the
/// run's entries, in mm, MPa, N/mm or N, mJ/mm or mJ) with every dimensional value in SI under
/// a key that ends with its unit: lengths and displacements `_m`; in 2-D (per metre of
/// thickness) forces `_N_per_m` and energies `_J_per_m`, in 3-D `_N` and `_J`. The `units`
/// string is dropped (the keys say it); dimensionless entries and `_s` times are copied.
nlohmann::json si_summary(const nlohmann::json& summary);

/// Writes `in.directory`/report.html and report.md (atomically) and returns the HTML path.
/// Throws pnc::InputError naming the path when a file cannot be written.
std::string write_report(const ReportInput& in);

} // namespace pncdemo

#endif // PNC_EXAMPLES_DEALII_FRACTURE_DEMO_REPORT_H
