#pragma once
// Test helper shared by the command-line suites: run a shell command, capture its stdout and
// exit status (stderr is whatever the command line redirects).
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace pnc::test {

struct CommandResult {
  int code = -1;   ///< exit status; -1 if the command was killed by a signal
  std::string out; ///< everything written to stdout
};

inline CommandResult run_command(const std::string& cmd) {
  CommandResult r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), p))
    r.out += buf.data();
  const int st = ::pclose(p);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

} // namespace pnc::test
