#pragma once
// pnc/core/subprocess.hpp: run a program with an argument vector, never through a shell.
//
// The program is started with fork + execvp (PATH lookup when `argv[0]` has no '/'); each
// argument reaches it as one argv entry, byte for byte, so quotes, blanks, ';', '$' or '`'
// in user input are data, not syntax. Standard input is /dev/null; standard output and
// standard error are captured together through a pipe.
#include <string>
#include <vector>

namespace pnc {

struct SubprocessResult {
  bool started = false; ///< false: the program could not be executed (not found, no permission)
  int exit_code = -1;   ///< exit status when it exited normally, else -1
  int signal = 0;       ///< the signal that ended it, else 0
  std::string output;   ///< everything it wrote to stdout and stderr, interleaved
  std::string error;    ///< why it could not be started (strerror of execvp), when !started
  bool ok() const { return started && exit_code == 0; }
};

/// Runs `argv` (argv[0] = program) and waits for it. Throws InputError only when `argv` is
/// empty or fork/pipe fail; a program that cannot be executed gives started == false.
SubprocessResult run_subprocess(const std::vector<std::string>& argv);

} // namespace pnc
