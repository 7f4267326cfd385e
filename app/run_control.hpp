#pragma once
// The application's side of long commands (core/run_dir.hpp, core/stop.hpp): the command line
// (recorded in run-directory locks and used for the resume command) and the SIGINT/SIGTERM
// handlers. This is the only place in pnc that installs signal handlers; they only record the
// request in pnc::process_stop(), which the libraries poll at their safe points.
#include <string>

namespace pnc::app {

/// Records argv (main() calls it first).
void set_command_line(int argc, char** argv);
/// The command line as typed, words shell-quoted where needed.
const std::string& command_line();
/// The command that continues this run: the command line plus " --resume" (if not there).
std::string resume_command();

/// While alive, SIGINT and SIGTERM request a stop (pnc::process_stop(), reset on entry) instead
/// of killing pnc; a third signal kills at once (the last checkpoint stays valid). A stage child
/// forked meanwhile that receives one before it reset its handlers dies of it as by default.
/// The previous handlers come back at destruction.
class StopSignals {
public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
};

/// "SIGINT", "SIGTERM" or "signal N".
std::string signal_name(int sig);

} // namespace pnc::app
