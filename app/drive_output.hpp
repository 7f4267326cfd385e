#pragma once
// Outputs of `pnc material drive`: the per-step table (CSV or HDF5, SI units stated in the
// file), the PNG (scripts/plot_drive.py) and the comparison with a reference table
// (docs/drive.md, docs/decisions.md D169).
#include "drive.hpp"

#include <string>
#include <vector>

namespace pnc::app {

/// The result as named columns (one value per step and column) with their units.
struct DriveTable {
  std::vector<std::string> names, units;
  std::vector<std::vector<double>> rows;
};
DriveTable drive_table(const DriveResult& r);

/// Provenance written into the file (CSV comment lines, HDF5 root attributes).
struct DriveMeta {
  std::string card, plugin, path, model, verdict, command;
};

/// Writes out.csv or out.h5 atomically (temporary file + rename).
void write_drive_output(const std::string& out, const DriveResult& r, const DriveMeta& meta);
/// The table as CSV text (header comments with the units, then one line per step).
std::string drive_csv(const DriveResult& r, const DriveMeta& meta);

/// Draws `png` from the result (scripts/plot_drive.py through run_plot_script: argument
/// vector, no shell), announcing the phase on stderr ("pnc material drive: plotting PNG ...",
/// then "... plotted PNG in T s"). Returns the PNG written, or "" when it could not be drawn
/// (a warning).
std::string plot_drive(const DriveResult& r, const DriveMeta& meta, const std::string& png);

/// Tolerances of the reference comparison: |value - reference| <= abs + rel |reference|,
/// abs by the column's kind.
struct Tolerances {
  double rel = 1e-6;
  double strain = 1e-10; ///< 1 (strain columns)
  double stress = 1.0;   ///< Pa (stress and tangent columns)
  double state = 1e-9;   ///< 1 (state variables)
  double energy = 1e-3;  ///< J/m^3 (work, stored, dissipated)
};

struct Mismatch {
  int step = 0;
  std::string column;
  double value = 0, reference = 0, tolerance = 0;
};

/// Compares the result with a reference CSV of the same layout (any subset of the output
/// columns; newton_* columns are not compared). Throws InputError when the reference cannot
/// be compared (missing file, unknown column, other number of steps); returns the values
/// outside the tolerances otherwise.
std::vector<Mismatch> compare_reference(const DriveResult& r, const std::string& reference,
                                        const Tolerances& tol);

} // namespace pnc::app
