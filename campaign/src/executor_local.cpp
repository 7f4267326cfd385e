// The local executor: units as child processes, at most `jobs` at a time (executor.hpp, D241).
#include "pnc/campaign/executor.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/progress.hpp"
#include "pnc/core/stop.hpp"

#include <fmt/format.h>

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <map>
#include <set>

namespace pnc::campaign {

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

pid_t start_unit(const Unit& u, const UnitMain& unit_main) {
  std::fflush(nullptr); // no duplicated stdio buffers in the child
  const pid_t pid = fork();
  if (pid < 0) fail("<executor>", u.id, "", "fork() failed");
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL); // a unit never outlives the command that runs it
    int code = 2;
    try {
      code = unit_main(u);
    } catch (...) {
      code = 2;
    }
    std::fflush(nullptr);
    _exit(code);
  }
  return pid;
}

} // namespace

double remaining_seconds(const std::vector<UnitSeconds>& finished,
                         const std::vector<UnitSeconds>& left, int jobs) {
  if (left.empty()) return 0.0;
  if (finished.empty()) return std::nan("");
  // the last kRecent of each kind, newest first: they follow a change of the machine's load
  constexpr int kRecent = 8;
  std::map<std::string, std::pair<double, int>> by_kind; // sum of seconds, count
  double all = 0;
  int n_all = 0;
  for (auto f = finished.rbegin(); f != finished.rend(); ++f) {
    auto& k = by_kind[f->kind];
    if (k.second == kRecent) continue;
    k.first += f->seconds;
    ++k.second;
    all += f->seconds;
    ++n_all;
  }
  const double mean_all = all / n_all;
  double work = 0;
  for (const auto& u : left) {
    const auto it = by_kind.find(u.kind);
    const double mean = it == by_kind.end() ? mean_all : it->second.first / it->second.second;
    work += std::max(mean - u.seconds, 0.0);
  }
  const auto lanes =
      std::min<std::size_t>(static_cast<std::size_t>(std::max(jobs, 1)), left.size());
  return work / static_cast<double>(lanes);
}

LocalRun run_local(const std::string& dir, const Plan& p, int jobs, const UnitMain& unit_main) {
  LocalRun out;
  const double t0 = now();
  if (jobs < 1) jobs = 1;
  enum class S { waiting, running, done, failed, skipped };
  std::map<std::string, S> st;
  for (const auto& u : p.units)
    st[u.id] = read_status(dir, u.id).state == UnitState::done ? S::done : S::waiting;
  std::map<pid_t, std::pair<const Unit*, double>> running;
  pnc::StopToken& stop = pnc::process_stop();
  // the run's progress line (D344) with an ETA by the units' kinds (D429)
  std::vector<UnitSeconds> finished;
  const auto ended = [&] {
    return std::count_if(st.begin(), st.end(), [](const auto& kv) {
      return kv.second != S::waiting && kv.second != S::running;
    });
  };
  const auto report = [&](const std::string& detail) {
    std::vector<UnitSeconds> left;
    const double t = now();
    for (const auto& u : p.units)
      if (st[u.id] == S::waiting) left.push_back({u.kind, 0.0});
    for (const auto& [pid, r] : running)
      left.push_back({r.first->kind, t - r.second});
    ProgressState s;
    s.what = "pnc " + (p.command.empty() ? std::string("run") : p.command);
    s.unit = "units";
    s.done = static_cast<double>(ended());
    s.total = static_cast<double>(p.units.size());
    s.elapsed_s = t - t0;
    s.eta_s = remaining_seconds(finished, left, jobs);
    s.detail = detail;
    print_progress(s);
  };
  for (;;) {
    // start what is ready, in plan order (equilibrations first, then the phase check, ...)
    bool progress = true;
    while (progress) {
      progress = false;
      for (const auto& u : p.units) {
        if (st[u.id] != S::waiting) continue;
        bool ready = true, blocked = false;
        std::string why;
        for (const auto& n : u.needs) {
          const S s = st[n];
          if (s == S::waiting || s == S::running) ready = false;
          if (!u.join && (s == S::failed || s == S::skipped)) {
            blocked = true;
            why = n;
          }
        }
        if (blocked) { // a need failed: this unit cannot run; its dependents neither
          st[u.id] = S::skipped;
          out.not_run.push_back(fmt::format("{} (needs {}, which did not finish)", u.id, why));
          progress = true;
          continue;
        }
        if (!ready || static_cast<int>(running.size()) >= jobs || stop.requested()) continue;
        running[start_unit(u, unit_main)] = {&u, now()};
        st[u.id] = S::running;
        out.ran.push_back(u.id);
        progress = true;
      }
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == ECHILD) break;
      continue;
    }
    auto it = running.find(pid);
    if (it == running.end()) continue;
    const Unit& u = *it->second.first;
    const double secs = now() - it->second.second;
    running.erase(it);
    UnitStatus s = read_status(dir, u.id);
    const bool exited = WIFEXITED(status);
    if (s.state == UnitState::done) {
      st[u.id] = S::done;
      finished.push_back({u.kind, secs});
      report(fmt::format("unit {} done in {}", u.id, format_duration(secs)));
      continue;
    }
    if (stop.requested()) { // stopped: pending again, continued by --resume
      st[u.id] = S::skipped;
      if (s.state == UnitState::running) {
        s.state = UnitState::pending;
        s.message = "stopped";
        s.pid = 0;
        write_status(dir, u.id, s);
      }
      continue;
    }
    if (s.state != UnitState::failed) { // it ended without recording why: say how it ended
      s.state = UnitState::failed;
      s.message = exited
                      ? fmt::format("the unit's process exited with status {} before "
                                    "recording its state",
                                    WEXITSTATUS(status))
                      : fmt::format("the unit's process was killed by signal {}", WTERMSIG(status));
      s.pid = 0;
      s.ended_s = epoch_seconds();
      write_status(dir, u.id, s);
    }
    st[u.id] = S::failed;
    const std::string line = u.id + ": " + with_log(s.message, s.log_path);
    out.failed.push_back(line);
    std::cerr << "pnc: unit " << line << " -- FAILED; the other units keep going\n";
    report(fmt::format("unit {} failed", u.id));
  }
  out.seconds = now() - t0;
  pnc::throw_if_stopped("the running units stopped at their last checkpoint; finished units "
                        "are kept");
  return out;
}

} // namespace pnc::campaign
