// The stopped report of a planned command (pnc characterize, pnc thermo ti) that did not
// finish: on the local executor (run_local_reported), on the Slurm executor after --wait, and
// from `pnc status DIR` once the Slurm jobs of the plan ended without its final unit
// (decisions D297, D300; docs/rve.md "Slurm").
#include "campaign_driver.hpp"
#include "run_control.hpp"
#include "stopped_report.hpp"

#include "pnc/core/error.hpp"
#include "pnc/rve/characterize.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iostream>

namespace pnc::app {

namespace {
/// "a, b, c" of at most `n` ids, then "and K more".
std::string some_ids(const std::vector<std::string>& ids, std::size_t n = 6) {
  std::string t;
  for (std::size_t i = 0; i < ids.size() && i < n; ++i)
    t += (i ? ", " : "") + ids[i];
  if (ids.size() > n) t += fmt::format(" and {} more", ids.size() - n);
  return t;
}

/// "id", or for a Slurm unit "id (job J: message)" ("id: message" when the message names the
/// job): where to look and why it stopped.
std::string unit_note(const std::string& id, const campaign::UnitStatus& s) {
  if (s.job_id.empty()) return id;
  if (s.message.find("job " + s.job_id + " ") != std::string::npos) return id + ": " + s.message;
  return fmt::format("{} (job {}{})", id, s.job_id, s.message.empty() ? "" : ": " + s.message);
}

const campaign::UnitStatus& status_of(const UnitStates& states, const std::string& id) {
  static const campaign::UnitStatus pending;
  const auto it = states.find(id);
  return it == states.end() ? pending : it->second;
}
} // namespace

UnitStates recorded_states(const std::string& dir, const campaign::Plan& p) {
  UnitStates s;
  for (const auto& u : p.units)
    s[u.id] = campaign::read_status(dir, u.id);
  return s;
}

UnitStates slurm_states(const std::string& dir, const campaign::Plan& p, bool& have_queue) {
  std::map<std::string, std::string> q;
  have_queue = false;
  try {
    q = campaign::slurm_queue();
    have_queue = true;
  } catch (const pnc::InputError& e) {
    std::cerr << "pnc: warning: " << e.what() << "; states as recorded\n";
  }
  UnitStates s;
  for (const auto& u : p.units)
    s[u.id] = campaign::effective_status(dir, u.id, have_queue ? &q : nullptr);
  return s;
}

std::string plan_report_title(const std::string& dir, const campaign::Plan& p) {
  if (p.command == "characterize") try {
      return "pnc characterize: " + rve::read_run_recipe(dir).name;
    } catch (const std::exception&) { // the page names the folder instead
    }
  return "pnc " + p.command + ": " + dir;
}

std::string write_plan_stopped_report(const PlanDriver& d, const campaign::Plan& p,
                                      const UnitStates& states, const std::string& title,
                                      RunStop stop) {
  std::vector<std::string> done, failed, open;
  for (const auto& u : p.units) {
    const campaign::UnitStatus& s = status_of(states, u.id);
    if (s.state == campaign::UnitState::done) {
      done.push_back(u.id);
      if (!u.outputs.empty() && stop.valid.size() < 8)
        stop.valid.push_back(
            fmt::format("unit `{}` (done): `{}`", u.id, fmt::join(u.outputs, "`, `")));
    } else {
      (s.state == campaign::UnitState::failed ? failed : open).push_back(unit_note(u.id, s));
    }
  }
  if (done.size() > stop.valid.size())
    stop.valid.push_back(
        fmt::format("{} finished unit(s) in all: {}", done.size(), some_ids(done)));
  stop.where = fmt::format("with {} of {} units done{}{}", done.size(), p.units.size(),
                           failed.empty() ? "" : "; failed: " + some_ids(failed),
                           open.empty() ? "" : "; not finished: " + some_ids(open));
  const std::string html = try_write_stopped_report(
      d.dir, title, stop,
      {{"command", "`" + p.parameters.value("command_line", command_line()) + "`"},
       {"run folder", "`" + d.dir + "`"},
       {"unit states", "`pnc status " + d.dir + "` shows every unit and its log"}});
  if (!html.empty())
    std::cerr << "pnc " << d.command << ": report (stopped early): " << html << "\n";
  return html;
}

std::string write_plan_stopped_report(const PlanDriver& d, const campaign::Plan& p,
                                      const std::string& title, const std::string& reason,
                                      bool failure) {
  RunStop stop;
  stop.reason = reason;
  stop.resume = resume_command(); // finished units are kept and not run again
  stop.failure = failure;
  return write_plan_stopped_report(d, p, recorded_states(d.dir, p), title, stop);
}

std::string ended_slurm_plan_report(const std::string& dir, const campaign::Plan& p,
                                    const UnitStates& states, const std::string& final_unit) {
  if (status_of(states, final_unit).state == campaign::UnitState::done) return "";
  std::vector<std::string> failed;
  std::string
      first; // the first failure that is not the final unit's (it only names what it missed)
  for (const auto& u : p.units) {
    const campaign::UnitStatus& s = status_of(states, u.id);
    if (s.state == campaign::UnitState::queued || s.state == campaign::UnitState::running)
      return "";
    if (s.state != campaign::UnitState::failed) continue;
    failed.push_back(unit_note(u.id, s));
    if (first.empty() && u.id != final_unit) first = failed.back();
  }
  if (first.empty() && !failed.empty()) first = failed.front();
  RunStop stop;
  stop.reason = failed.empty()
                    ? fmt::format("the Slurm jobs ended before the {} unit ran", final_unit)
                    : fmt::format("{} unit(s) failed, first {}", failed.size(), first);
  stop.failure = !failed.empty();
  // the command that made the folder (recorded in its plan) continues it with --resume
  std::string cmd = p.parameters.value("command_line", std::string());
  if (!cmd.empty() && (" " + cmd + " ").find(" --resume ") == std::string::npos) cmd += " --resume";
  stop.resume = cmd;
  if (cmd.empty())
    stop.instead = "Run the command that made this folder again with `--resume`: the finished "
                   "units are kept and only the others are submitted.";
  return write_plan_stopped_report({"status", dir, final_unit, false}, p, states,
                                   plan_report_title(dir, p), stop);
}

int slurm_wait_interrupted(const PlanDriver& d, const campaign::Plan& p, int sig) {
  bool have_queue = false;
  const UnitStates states = slurm_states(d.dir, p, have_queue);
  std::vector<std::string> jobs; // the live jobs, an array once by its id (scancel takes it whole)
  for (const auto& u : p.units) {
    const campaign::UnitStatus& s = status_of(states, u.id);
    if (s.job_id.empty() ||
        (s.state != campaign::UnitState::queued && s.state != campaign::UnitState::running))
      continue;
    const std::string job = s.job_id.substr(0, s.job_id.find('_'));
    if (std::find(jobs.begin(), jobs.end(), job) == jobs.end()) jobs.push_back(job);
  }
  // D306: only the waiting stops; the jobs are the user's, cancelled only by the user
  const std::string ids = fmt::format("{}", fmt::join(jobs, " "));
  const std::string follow = fmt::format("`pnc status {}`", d.dir);
  RunStop stop;
  stop.reason = signal_reason(sig) + " while waiting: only the waiting stopped, the Slurm jobs " +
                "keep running";
  stop.failure = false;
  stop.instead = fmt::format(
      "The Slurm jobs of this run were not cancelled{}. Follow them with {}: when the {} unit "
      "ends, its job writes the full report over this page; when the jobs end without it, {} "
      "rewrites this page with the command that continues the run. {}",
      jobs.empty() ? "" : " (jobs " + ids + ")", follow, d.final_unit, follow,
      jobs.empty() ? "No job of the run is queued or running any more."
                   : "To stop the jobs too, cancel them with `scancel " + ids + "`.");
  write_plan_stopped_report(d, p, states, plan_report_title(d.dir, p), stop);
  std::cerr << fmt::format("pnc: interrupted by {}: stopped waiting; the Slurm jobs keep running: "
                           "follow them with pnc status {}{}\n",
                           signal_name(sig), d.dir,
                           jobs.empty() ? "" : ", cancel them with scancel " + ids);
  return pnc::exit_code::stopped_by_signal(sig);
}

} // namespace pnc::app
