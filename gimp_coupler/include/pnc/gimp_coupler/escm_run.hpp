#pragma once
// pnc/gimp_coupler/escm_run.hpp: `pnc gimp couple INPUT --out DIR [--short]`: an ESCM run of an
// LJ FCC crystal MD region at the centre of a 2-D continuum calibrated to it, from a JSON input
// (keys in docs/escm.md, "Input file"): tension (Case I analogue), or with an edge pre-crack
// in the continuum growing toward the block under tension normal to it (Case II, mode I) or
// shear parallel to it (Case III, mode II), escm_crack.hpp, decisions D80-D84.
// Outputs in DIR: energy.csv, profile.csv, atoms_<k>.vtu, particles_<k>.vtu (both with the
// displacement gradients of docs/theory.md §6.3, escm_gradient.hpp), lammps.log, summary.json and,
// with /usr/bin/python3 + matplotlib, profile.png and energy.png; with a crack also crack.csv
// (continuum tip, J, G_I, G_II, crack-face opening and sliding, atomistic separation) and
// crack.png. Units: input in LAMMPS real for
// the MD (kcal/mol, Angstrom, g/mol, fs) and ps for the schedule; outputs as in formats.md.
#include "pnc/core/parameters.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/gimp_coupler/escm.hpp"

#include <array>
#include <string>
#include <vector>

namespace pnc::gimp::escm {

struct CoupleOptions {
  std::string input;
  std::string out_dir;
  bool short_mode = false; ///< apply the input's "short" overrides
  bool progress = true;    ///< progress lines (step, time, ETA) on stderr
  bool plot = true;
  /// Continue from DIR/checkpoint.h5 (the input must be the same; docs/escm.md "Checkpoint
  /// and resume"). Without it, a DIR that already holds a run is refused.
  bool resume = false;
  /// > 0: stop after this many coupled steps in total, writing a checkpoint (the run is then
  /// continued with `resume`).
  long stop_after_steps = 0;
  /// Polled after every coupled step. A request stops the run, with a checkpoint, at the next
  /// step of the checkpoint schedule (checkpoint_every_ps), so that the resumed run is bit for
  /// bit the uninterrupted one; a second request, or a run without a schedule, stops after the
  /// current step (resumable, equal to round-off only: docs/escm.md "Checkpoint and resume").
  const pnc::StopToken* stop = nullptr;
};

struct CoupleSummary {
  long steps = 0;
  double time_s = 0.0;
  double wall_s = 0.0;
  double outside_share = 0.0; ///< of the coupled steps' wall time, outside LAMMPS
  std::array<int, 3> atoms{}; ///< INT, IVC, SVC
  std::size_t particles = 0;  ///< continuum particles (after removing INT)
  EnergyRow energy;           ///< last row of the energy log
  double reaction_left = 0.0; ///< reaction of the fixed edge along the load, N per m (last step)
  double strain_modulus_pa = 0.0; ///< C11 - C12^2/C11 of the crystal (expected slope)
  std::string energy_csv, profile_csv, summary_json, lammps_log, plot_warning;
  std::string crack_csv; ///< Cases II/III only
  std::vector<std::string> frames, plots;
  std::vector<std::string> particle_frames; ///< particles_<k>.vtu (continuum particles)
  // Checkpoints (docs/escm.md "Checkpoint and resume")
  std::string checkpoint;           ///< DIR/checkpoint.h5
  bool resumed = false;             ///< continued from a checkpoint
  long start_step = 0;              ///< coupled steps done before this session
  int checkpoints = 0;              ///< written in this session
  double checkpoint_s = 0.0;        ///< wall time of writing them, s
  std::size_t checkpoint_bytes = 0; ///< size of the last one (both files)
  /// Empty when the run finished; "max_steps" (stop_after_steps reached) or "signal N" (a stop
  /// request, CoupleOptions::stop): stopped after a checkpoint, summary.json and plots not
  /// written.
  std::string interrupted;
  int signal = 0; ///< the signal that stopped the run, 0 if none
};

/// Validates the input (throws pnc::InputError naming file, key, value, rule) before LAMMPS
/// starts, then runs. Without `resume`, a directory that holds a run (checkpoint.h5 or
/// summary.json) is refused (pnc::refuse_existing_run). Throws std::runtime_error for failures
/// during the run.
CoupleSummary run_couple(const CoupleOptions& o);

/// The declared keys of the input (type, default, range, unit, text; D293), bound to an input
/// of defaults it holds: for printing (`pnc gimp couple-parameters`). Units as stated per key:
/// LAMMPS real for the MD keys (kcal/mol, A, g/mol, fs, K), ps for the schedule, J/m^2, Pa.
pnc::Parameters couple_input_parameters();

} // namespace pnc::gimp::escm
