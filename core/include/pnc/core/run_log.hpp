#pragma once
// pnc/core/run_log.hpp: the run folder keeps what pnc printed (docs/decisions/core.md D235).
//
// While a run log is active, every line pnc writes on std::cout or std::cerr still goes to the
// terminal and is also appended to `<dir>/pnc.log`, one line per printed line:
//
//     2026-12-03T14:40:01.123Z err pnc gimp couple: 3/10 steps (30.0%), elapsed 1.8 s, ETA 4.1 s
//
// (UTC time with milliseconds, the stream `out` or `err`, the text as printed). The first line
// of a session names pnc's version, the process id, the working directory and the command line;
// the last one the exit code (`finish_run_log`). A resumed run appends a new session to the
// same file. Output of programs pnc runs (LAMMPS, python) is not copied: each keeps its own log
// in the run folder. The file is opened O_APPEND|O_NOFOLLOW|O_CLOEXEC (a symbolic link there is
// refused; executed programs do not inherit it); each line is one write(2), so forked stage
// children that print add whole lines. Text printed with C stdio (printf) is not copied.
#include <string>

namespace pnc {

/// `<dir>/pnc.log`
std::string run_log_path(const std::string& dir);

/// Starts copying std::cout and std::cerr into `<dir>/pnc.log` (the directory must exist).
/// `command_line` is recorded in the session's first line. Throws InputError (source `dir`,
/// field "pnc.log") when the file cannot be opened. Starting again replaces the previous log.
void start_run_log(const std::string& dir, const std::string& command_line);

/// Writes the session's last line ("pnc finished: exit code N") and stops copying; std::cout and
/// std::cerr print as before. Does nothing when no log is active.
void finish_run_log(int exit_code);

/// True while a run log is active.
bool run_log_active();

} // namespace pnc
