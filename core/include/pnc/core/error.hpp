#pragma once
// pnc/core/error.hpp: errors that name what broke, and the exit codes of `pnc`.
//
// Every failure pnc reports is one of three kinds, each a pnc::Error with its exit code:
//  - InputError: the input is wrong. It names the file (or other source), the field (column,
//    key, dataset), the offending value and the rule it broke, so that the one-line message
//    printed by the CLI is enough to fix the input. Exit code 1.
//  - SimulationError: the input was accepted but the simulation it describes failed (a box
//    that cavitates where that is fatal, a particle that left the grid). It names the entity
//    that failed, the step and the simulated time with its unit. Exit code 6.
//  - ToolError: an external program pnc drives failed (LAMMPS, mpirun, python3). It names the
//    tool, what pnc was doing, the tool's own message and the tool's log file. Exit code 7.
// Anything else that escapes a command is a bug in pnc (exit code 2, "internal error").
// The table of exit codes with what the user does for each: docs/errors.md.
#include <limits>
#include <stdexcept>
#include <string>

namespace pnc {

/// The exit codes of `pnc`, stable across versions (docs/errors.md). Codes 3-5 are not
/// exceptions: the command finished, wrote its result and judged it (the result is on disk).
namespace exit_code {
inline constexpr int ok = 0;                ///< success
inline constexpr int bad_input = 1;         ///< InputError, or a command-line parse error
inline constexpr int internal_error = 2;    ///< a bug in pnc (any other exception)
inline constexpr int not_converged = 3;     ///< a fit or a stress-controlled step did not converge
inline constexpr int card_not_usable = 4;   ///< a card was written with the verdict "not usable"
inline constexpr int outside_reference = 5; ///< `pnc material drive` left a reference's tolerances
inline constexpr int simulation_failed = 6; ///< SimulationError
inline constexpr int tool_failed = 7;       ///< ToolError (LAMMPS, mpirun, python3, ...)
inline constexpr int signal_base = 128;     ///< 128 + N: stopped by signal N (pnc::Interrupted)
/// 128 + sig (130 for SIGINT, 143 for SIGTERM); a stop that came from no signal counts as SIGINT.
constexpr int stopped_by_signal(int sig) {
  return signal_base + (sig > 0 ? sig : 2);
}
} // namespace exit_code

/// The common base of pnc's error kinds: what() is one line; exit_code() the code `pnc` exits
/// with when the error ends a command.
class Error : public std::runtime_error {
public:
  int exit_code() const noexcept { return code_; }

protected:
  Error(const std::string& what, int code) : std::runtime_error(what), code_(code) {}

private:
  int code_;
};

struct ErrorContext {
  std::string source; ///< file path or other origin ("<command line>", "<card>")
  std::string field;  ///< column, key or dataset name; may be empty
  std::string value;  ///< offending value as text; may be empty
  std::string rule;   ///< the rule that was broken
};

/// what(): "SOURCE: field 'F': value 'V': RULE" (empty parts left out). Exit code 1.
class InputError : public Error {
public:
  explicit InputError(ErrorContext ctx);
  const ErrorContext& context() const noexcept { return ctx_; }

private:
  ErrorContext ctx_;
};

/// Throws InputError built from the four parts.
[[noreturn]] void fail(std::string source, std::string field, std::string value, std::string rule);

struct SimulationContext {
  std::string entity;  ///< what failed: "RVE box", "particle 12", "crack 1", "case 3"
  long long step = -1; ///< time step (or load step) at which it failed; < 0: not known
  double time = std::numeric_limits<double>::quiet_NaN(); ///< simulated time; NaN: not known
  std::string time_unit; ///< unit of `time` ("fs", "ps", "s"); required when time is given
  std::string message;   ///< what happened, with the numbers that show it
};

/// what(): "ENTITY: step N, t = T UNIT: MESSAGE" (unknown step/time left out). Exit code 6.
class SimulationError : public Error {
public:
  explicit SimulationError(SimulationContext ctx);
  const SimulationContext& context() const noexcept { return ctx_; }

private:
  SimulationContext ctx_;
};

struct ToolContext {
  std::string tool;     ///< "LAMMPS", "mpirun", "python3"
  std::string doing;    ///< what pnc was doing: "running stage equilibrate/hot"
  std::string message;  ///< the tool's own message (LAMMPS's ERROR line), or how it ended
  std::string log_path; ///< the tool's log file; may be empty
};

/// what(): "TOOL failed while DOING: MESSAGE (log LOG)" (log left out when empty).
/// Exit code 7.
class ToolError : public Error {
public:
  explicit ToolError(ToolContext ctx);
  const ToolContext& context() const noexcept { return ctx_; }

private:
  ToolContext ctx_;
};

/// Throws ToolError built from the four parts.
[[noreturn]] void fail_tool(std::string tool, std::string doing, std::string message,
                            std::string log_path);

/// Throws SimulationError; `time` in `time_unit` (NaN and "" when not known; step < 0 likewise).
[[noreturn]] void fail_simulation(std::string entity, long long step, double time,
                                  std::string time_unit, std::string message);

/// `message` followed by " (log LOG)", unless `log` is empty or the message already names that
/// log that way (a ToolError's what() does): a failure names its log once.
std::string with_log(const std::string& message, const std::string& log);

/// The exit code for an exception that ended a command: a pnc::Error's own code, else
/// exit_code::internal_error. (pnc::Interrupted, core/stop.hpp, is mapped by the application.)
int exit_code_of(const std::exception& e) noexcept;

} // namespace pnc
