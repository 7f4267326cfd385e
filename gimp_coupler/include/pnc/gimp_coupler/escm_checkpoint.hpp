#pragma once
// pnc/gimp_coupler/escm_checkpoint.hpp: checkpoint files of a coupled ESCM run (`pnc gimp couple`,
// docs/escm.md "Checkpoint and resume", layout in docs/formats.md "ESCM checkpoint").
//
// Two HDF5 files in the run directory, each written atomically (temporary file + rename):
//  - checkpoint_continuum_<0|1>.h5: the GIMP solver's own checkpoint (output.hpp
//    write_checkpoint<2>: particles, time, steps, energies, cracks as grown), alternately into
//    the two names so that the previous one stays intact while the next is written;
//  - checkpoint.h5: the coupler's state (CouplerState: IVC averages, accumulators, energy log,
//    atoms' positions, velocities, forces, image flags, types), the driver's bookkeeping
//    (stored input, step counters, named texts and tables) and the name of its continuum file.
//    Renaming it into place is the commit: a crash while writing leaves the previous pair.
#include "pnc/gimp_coupler/escm.hpp"

#include <Eigen/Core>

#include <map>
#include <string>

namespace pnc::gimp::escm {

using CheckpointTable = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// A coupled checkpoint without the solver's particles (those are in the continuum file).
struct CoupledCheckpoint {
  CouplerState coupler;
  std::string input_path;  ///< the input file of the run (information)
  std::string input_text;  ///< its contents when the run started (compared on --resume)
  bool short_mode = false; ///< started with --short
  long step = 0;           ///< coupled steps done
  long nsteps = 0;         ///< coupled steps of the whole run
  double time_s = 0.0;     ///< continuum time, s
  double wall_s = 0.0;     ///< wall time of the coupled steps so far (all sessions), s
  std::map<std::string, std::string> texts;      ///< driver bookkeeping (e.g. CSV so far)
  std::map<std::string, CheckpointTable> tables; ///< driver bookkeeping (numbers)
  std::string continuum_file;                    ///< set by read/write: the continuum part
};

/// DIR/checkpoint.h5.
std::string checkpoint_path(const std::string& dir);

/// Writes the continuum part (the solver) and then DIR/checkpoint.h5, each atomically.
/// Returns the bytes of the two files.
std::size_t write_coupled_checkpoint(const std::string& dir, const Solver<2>& s,
                                     CoupledCheckpoint& c);

/// Reads DIR/checkpoint.h5 (not the solver). Throws pnc::InputError naming the file and the
/// dataset if it is not a pnc ESCM checkpoint.
CoupledCheckpoint read_coupled_checkpoint(const std::string& dir);

/// Restores the solver (set up from the same input, Coupler::setup() done) from the continuum
/// file of `c`, checks that it belongs to `c` (same step), and re-initialises it
/// (Solver::initialize(false)).
void restore_continuum(const std::string& dir, const CoupledCheckpoint& c, Solver<2>& s);

} // namespace pnc::gimp::escm
