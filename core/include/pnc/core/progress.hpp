#pragma once
// pnc/core/progress.hpp: the one progress/ETA line of every long command (D344, D345).
//
// A command that works through a known amount of work makes a Progress with the total (and
// the unit it is counted in) and tells it how much is done; the lines look alike everywhere:
//
//     pnc gimp: 2.4e-05/5e-05 s simulated (48.0%), elapsed 1 min 04 s, ETA 1 min 09 s; step 812
//
// (`<what>: <done>/<total> <unit> (<percent>%), elapsed <time>, ETA <time>[; <detail>]`).
// Times are wall-clock seconds written as "4.2 s", "37 s", "12 min 05 s" or "3 h 07 min"
// (format_duration). The ETA is (work left) / (rate of the work done since the Progress was
// made): work reused from an earlier session (skip) counts as done but not in the rate; before
// any work of this session is done it reads "ETA unknown". A quiet phase that follows (plotting,
// writing) is announced by a Phase, so no silent minutes follow "ETA 0 s".
//
// Lines go to std::cerr, flushed, one write per line: while a run log is active they are also
// in the run folder's pnc.log (run_log.hpp).
#include <functional>
#include <string>

namespace pnc {

/// One report of a Progress.
struct ProgressState {
  std::string what;     ///< who works, e.g. "pnc thermo ti"
  std::string unit;     ///< the unit of done and total, e.g. "lambda points", "s simulated"
  double done = 0;      ///< work done, [unit], including reused work
  double total = 0;     ///< all the work, [unit]
  double elapsed_s = 0; ///< wall time since the Progress was made, s
  double eta_s = 0;     ///< wall time left, s; NaN: unknown (no work of this session done yet)
  std::string detail;   ///< what the caller adds (the step, the last result); may be empty
};

/// "4.2 s" (under 10 s), "37 s", "12 min 05 s", "3 h 07 min"; "unknown" when not finite.
std::string format_duration(double seconds);
/// The line (no newline), format above (D344).
std::string format_progress(const ProgressState& s);
/// format_progress(s) and a newline on std::cerr, flushed.
void print_progress(const ProgressState& s);

/// Receives each line a Progress prints.
using ProgressSink = std::function<void(const ProgressState&)>;
/// A monotone clock, seconds (any origin).
using ProgressClock = std::function<double()>;

struct ProgressOptions {
  /// At most one line per every_s seconds of wall time (0: a line at each call); the line that
  /// completes the work is always printed (D345).
  double every_s = 0;
  /// Units of work run `lanes` at a time and end together (parallel batches): the ETA counts
  /// rounds of `lanes` units (D345). 1: one at a time.
  int lanes = 1;
  bool enabled = true; ///< false: nothing is printed (a --quiet run)
  ProgressSink sink;   ///< where lines go; empty: print_progress
  ProgressClock clock; ///< empty: std::chrono::steady_clock
};

class Progress {
public:
  /// `total` (>= 0, finite) of `unit`. Throws InputError (source "<progress>") otherwise.
  Progress(std::string what, double total, std::string unit, ProgressOptions o = {});

  /// `amount` more work done in this session; prints a line when one is due. True if printed.
  bool advance(double amount, const std::string& detail = {});
  /// The work done is now `done` (absolute, >= the previous value); like advance.
  bool set(double done, const std::string& detail = {});
  /// `amount` of work reused from an earlier session (a resume): done, not in the rate.
  bool skip(double amount, const std::string& detail = {});

  double done() const { return done_; }
  double total() const { return total_; }
  /// Wall time since construction, s.
  double elapsed_s() const;
  /// Wall time left, s (D345); 0 when all is done, NaN before any work of this session.
  double eta_s() const;
  /// The state now, with `detail`.
  ProgressState state(const std::string& detail = {}) const;

private:
  bool add(double amount, bool reused, const std::string& detail);
  double now() const;

  std::string what_, unit_;
  double total_ = 0, done_ = 0, reused_ = 0;
  ProgressOptions o_;
  double t0_ = 0, last_line_ = 0;
  bool printed_complete_ = false;
};

/// A quiet phase (plotting, writing): "<what>: <doing> ..." when made, "<what>: <result> in
/// <time>" by done(). Both lines go where print_progress writes (or to `print`).
class Phase {
public:
  Phase(std::string what, const std::string& doing, bool enabled = true,
        std::function<void(const std::string&)> print = {}, ProgressClock clock = {});
  /// Prints "<what>: <result> in <time>" (once; later calls do nothing).
  void done(const std::string& result);
  /// Wall time since construction, s.
  double seconds() const;

private:
  std::string what_;
  bool enabled_ = true, finished_ = false;
  std::function<void(const std::string&)> print_;
  ProgressClock clock_;
  double t0_ = 0;
};

} // namespace pnc
