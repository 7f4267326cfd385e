#pragma once
// pnc/gimp_coupler/run.hpp: the driver of `pnc gimp run INPUT --out DIR [--resume]`.
//
// Writes into DIR: particles.pvd + frames/particles_NNNNNN.vtu (particle fields, SI),
// history.csv (the unit ends each column name, D335: energies in J/m and reactions in N/m in 2-D,
// J and N in 3-D, per recorded step), checkpoint.h5 (restart),
// energy.png (energy balance, drawn by gimp_coupler/scripts/plot_energy.py with
// /usr/bin/python3 + matplotlib; skipped with a warning if unavailable), G.png (2-D runs with
// crack tips: J, G_I, G_II in J/m^2 versus crack length and time, gimp_coupler/scripts/plot_G.py),
// summary.json.
#include "pnc/core/stop.hpp"
#include "pnc/gimp_coupler/solver.hpp"

#include <functional>
#include <string>
#include <vector>

namespace pnc::gimp {

struct RunOptions {
  std::string input;
  std::string out_dir;
  bool resume = false;
  int threads = 0;           ///< 0: from the input file
  bool progress = true;      ///< progress lines (step, time, ETA) on stderr
  bool plot = true;          ///< energy.png
  long stop_after_steps = 0; ///< stop when the total step count reaches this (0: no limit);
                             ///< not part of the input, so the run can be resumed
  /// Polled after every step: when requested, the run stops there as with stop_after_steps
  /// (history and checkpoint written, no plots, no summary.json) and returns with `stopped`.
  const pnc::StopToken* stop = nullptr;
};

/// Growth of one crack at the end of a run (cracks with a growth law or a tip): why it is not
/// growing any more, in words, for the run report and the G plot's stop marker.
struct CrackOutcome {
  std::string name;
  double Gc = 0.0, GIIc = 0.0; ///< J/m^2 (crack area); Gc = 0: no growth law
  int max_increments = 0;
  int increments = 0;      ///< in total, including before a resume
  std::string stop_reason; ///< e.g. "max_increments (12) reached", "J < Gc at the end"
};

struct RunSummary {
  int dimension = 2;
  std::size_t particles = 0;
  long steps = 0; ///< total, including steps before a resume
  long steps_this_run = 0;
  double time = 0.0;    ///< s
  double dt_last = 0.0; ///< s
  Energies energy;
  double max_abs_balance = 0.0; ///< max |KE + SE - W_ext - W_bc| over the history, J
  double wall_seconds = 0.0;
  double particle_steps_per_second = 0.0;
  int threads = 1;
  bool resumed = false;
  int frames = 0;
  std::string pvd, history_csv, checkpoint, plot_png, plot_warning;
  std::string plot_G_png;   ///< G.png (runs with crack tips)
  int crack_increments = 0; ///< crack growth increments in this run
  std::vector<CrackOutcome> cracks;
  /// Why the run ended: "end time reached", "input max_steps (N) reached" or
  /// "--max-steps (N) reached" (a stop the run can be resumed from).
  std::string end_reason;
  std::vector<std::string> reaction_names;
  std::vector<std::vector<double>> reactions; ///< last step, N, per boundary
  bool stopped = false; ///< stopped on RunOptions::stop before the end (continue with resume)
  int stop_signal = 0;  ///< the signal that asked for it (StopToken::signal())
};

/// Without `resume`, a directory that holds a run (checkpoint.h5, history.csv or summary.json)
/// is refused (pnc::refuse_existing_run); with it, the run continues from checkpoint.h5.
RunSummary run(const RunOptions& o);

} // namespace pnc::gimp
