#pragma once
// pnc/core/stop.hpp: a request to stop a long command at its next safe point.
//
// The request comes from SIGINT/SIGTERM; only the application installs signal handlers
// (app/run_control.hpp), and they do nothing but StopToken::request(). Libraries poll the token
// at points where their state on disk is whole (after a checkpoint, between stages) and end
// with pnc::Interrupted, or hand the stop back to the command in their summary.
//
// The process-wide token (process_stop()) lives in a shared anonymous mapping created before
// any fork: a stage child forked by pnc::rve sees a request made in the parent after the fork.
#include <stdexcept>
#include <string>

namespace pnc {

class StopToken {
public:
  /// A private token (its own shared mapping), e.g. for tests; nothing requests it but the owner.
  StopToken();
  ~StopToken();
  StopToken(const StopToken&) = delete;
  StopToken& operator=(const StopToken&) = delete;

  /// Records a request by signal `sig` (0: not a signal). Async-signal-safe (lock-free atomics).
  void request(int sig) noexcept;
  bool requested() const noexcept;
  /// The signal of the first request (0 if none or not a signal).
  int signal() const noexcept;
  /// How many requests were made (a second SIGINT may mean "stop now, not at a checkpoint").
  int count() const noexcept;
  /// Forgets all requests (a new command in the same process).
  void reset() noexcept;

private:
  struct Shared;
  Shared* s_ = nullptr;
};

/// The token the application's signal handlers request. Created at the first call; the
/// application calls it before it forks anything.
StopToken& process_stop();

/// A long command stopped on request. `signal` is the signal that asked for it (0: none);
/// `detail` says where it stopped ("after step 120 of 400; checkpoint out/checkpoint.h5").
/// The application prints one line with the command that continues the run and exits with
/// 128 + signal (130 for SIGINT, 143 for SIGTERM).
class Interrupted : public std::runtime_error {
public:
  Interrupted(int signal, std::string detail);
  int signal() const noexcept { return signal_; }
  const std::string& detail() const noexcept { return detail_; }

private:
  int signal_;
  std::string detail_;
};

/// Throws Interrupted(process_stop().signal(), detail) when a stop was requested.
void throw_if_stopped(const std::string& detail);

} // namespace pnc
