#pragma once
// Test helper for the interruption and locking tests: start a shell command line in the
// background as its own process (sh -c "exec ...": the pid is the command's), wait for it with
// a time limit, wait for a file to contain a text.
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "common/temp_dir.hpp" // slurp

#include <chrono>
#include <csignal>
#include <string>
#include <thread>

namespace pnc::test {

inline pid_t spawn(const std::string& cmd) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", ("exec " + cmd).c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

struct Ended {
  bool ended = false; ///< false: still running at the time limit (then killed)
  int code = -1;      ///< exit status, -1 if killed by a signal
  int signal = 0;     ///< the signal that killed it
};

/// Waits up to `seconds` for `pid`; kills it (SIGKILL) when the time is up.
inline Ended wait_for(pid_t pid, double seconds) {
  Ended e;
  const auto t0 = std::chrono::steady_clock::now();
  int st = 0;
  while (true) {
    const pid_t r = ::waitpid(pid, &st, WNOHANG);
    if (r == pid) break;
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > seconds) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &st, 0);
      return e;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  e.ended = true;
  if (WIFEXITED(st)) e.code = WEXITSTATUS(st);
  if (WIFSIGNALED(st)) e.signal = WTERMSIG(st);
  return e;
}

/// Waits up to `seconds` until file `path` contains `text`; false if it never did.
inline bool wait_for_text(const std::string& path, const std::string& text, double seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  while (slurp(path).find(text) == std::string::npos) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > seconds)
      return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

} // namespace pnc::test
