#pragma once
// pnc/gimp_coupler/output.hpp: particle frames (VTU + PVD index), histories (CSV) and
// checkpoints (HDF5) of the GIMP solver. All files are written atomically.
//
// VTU (pnc/core/vtu.hpp: VTK XML UnstructuredGrid, one VTK_VERTEX cell per particle;
// ParaView-readable; D236): points in m; point data, SI units, the unit in each name:
// displacement_m, velocity_m_per_s (3 components), stress_Pa (Cauchy) and strain_1
// (Green-Lagrange E = (F^T F - I)/2) as symmetric tensors (6 components, XX YY ZZ XY YZ XZ),
// density_kg_per_m3, volume_m3, mass_kg, strain_energy_density_J_per_m3, material_index
// (Int32; names in the file's comment), and one array <state name>_1 per material state
// variable (the damage laws' kappa and D, dimensionless; 0 for particles of other laws).
// Field data: time_s and the "units" list. 2-D frames have z = 0 and 3-component vectors.
#include "pnc/gimp_coupler/solver.hpp"

#include <string>
#include <vector>

namespace pnc::gimp {

/// Writes one VTU frame (ASCII, or base64-encoded binary when `binary`).
template <int D>
void write_vtu(const std::string& path, const Solver<D>& s, bool binary,
               const std::vector<std::string>& material_names);

/// Writes the PVD index of frames (file names relative to the PVD's folder); the timestep is
/// the time (s), which must increase strictly (pnc::InputError otherwise).
void write_pvd(const std::string& path, const std::vector<std::string>& files,
               const std::vector<double>& times);

/// Base64 of a byte buffer (RFC 4648, with padding).
std::string base64(const unsigned char* data, std::size_t n);

/// Run history: one row per recorded step.
struct History {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  void write_csv(const std::string& path) const;
};

/// What a checkpoint holds besides the solver: output bookkeeping and the history.
struct CheckpointExtra {
  /// The input as read, every default filled in (RunConfig::expanded_input): a resume with
  /// another input fails naming the first key that differs; whitespace, key order and number
  /// spelling do not count (D339). Empty: not checked (the ESCM continuum checkpoints).
  std::string input;
  std::string input_source; ///< the input file (the source named by that error)
  /// FNV-1a of the input file's bytes: compared only for a checkpoint without /input (written
  /// before D339)
  std::string input_hash;
  double next_output_time = 0.0;
  std::vector<std::string> frame_files;
  std::vector<double> frame_times;
  History history;
  /// The history columns' cracks: 2-D, 2 per crack, the ends that were tips at t = 0; 3-D, 1
  /// per edge, crack by crack, the fronts of t = 0 (D43).
  std::vector<int> initial_tips;
};

template <int D>
void write_checkpoint(const std::string& path, const Solver<D>& s, const CheckpointExtra& x);
/// Restores particles, time, steps and energies into a solver built from the same input,
/// and the extra data. Throws pnc::InputError if the checkpoint does not match.
template <int D> void read_checkpoint(const std::string& path, Solver<D>& s, CheckpointExtra& x);

} // namespace pnc::gimp
