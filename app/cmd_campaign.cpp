// pnc characterize (the driver: plan, local or Slurm executor), pnc run-unit DIR UNIT, pnc status
// DIR, and the driver pieces every planned command shares (app/characterize.hpp,
// app/campaign_driver.hpp; docs/rve.md, docs/cluster.md, decisions D240-D246, D285-D289).
#include "campaign_driver.hpp"
#include "characterize.hpp"
#include "registrars.hpp"
#include "run_control.hpp"
#include "stopped_report.hpp"

#include "pnc/campaign/campaign.hpp"
#include "pnc/campaign/executor.hpp"
#include "pnc/campaign/slurm.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/error_record.hpp"
#include "pnc/core/progress.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/run_log.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/md/lammps_server.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

namespace pnc::app {

namespace fs = std::filesystem;

std::string preset_list() {
  std::string s;
  for (const auto& n : rve::preset_names())
    s += (s.empty() ? "" : ", ") + n;
  return s;
}

rve::Recipe load_recipe(const std::string& arg) {
  for (const auto& n : rve::preset_names())
    if (arg == n) return rve::parse_recipe(rve::preset_json(n), "preset " + n);
  if (!fs::is_regular_file(arg))
    fail(arg, "RECIPE", arg,
         "is neither a recipe file (.json, .toml) nor a preset name (" + preset_list() + ")");
  return rve::read_recipe(arg);
}

namespace {

/// The planned commands other than characterize (register_plan_command).
std::map<std::string, PlanUnitRunner>& plan_commands() {
  static std::map<std::string, PlanUnitRunner> m;
  return m;
}

/// Runs unit `u` of a characterization in this process and records its state; returns the
/// exit code (0; the fit's 3 or 4; else as guarded_unit).
int unit_main(const std::string& dir, const campaign::Plan& p, const rve::Recipe& r,
              const campaign::Unit& u, bool print_errors) {
  return guarded_unit(u, print_errors, [&] {
    if (u.kind == "fit") {
      int code = 0;
      campaign::run_unit_recorded(dir, u, [&] {
        const rve::MdOutcome md = rve::collect_md(r, dir, p);
        FitUnitArgs fa{p.parameters.value("recipe", std::string(dir)), dir,
                       p.parameters.value("no_plots", false), p.parameters.value("replicas", 0)};
        code = run_fit_unit(r, md, fa);
        return nlohmann::json{{"exit_code", code}, {"summary", summary_path(dir)}};
      });
      return code;
    }
    campaign::run_unit_recorded(dir, u, [&] { return rve::run_md_unit(r, dir, u); });
    return 0;
  });
}

/// After the executor: the fit's result (its summary and exit code), or the failures.
int conclude(const CharacterizeArgs& a, const campaign::Plan& p,
             const std::vector<std::string>& failed, const std::vector<std::string>& not_run) {
  throw_unless_final_done({"characterize", a.out, "fit", a.json}, p, failed, not_run);
  const campaign::UnitStatus fit = campaign::read_status(a.out, "fit");
  if (a.json) {
    std::ifstream f(summary_path(a.out));
    std::stringstream ss;
    ss << f.rdbuf();
    std::cout << ss.str() << std::flush;
  }
  return fit.detail.value("exit_code", 0);
}

/// Polls the unit states until the final unit ended, printing every change; a stop request
/// ends the wait (the jobs keep running).
void wait_for_slurm(const PlanDriver& d, const campaign::Plan& p, std::vector<std::string>& failed,
                    int poll_s) {
  std::map<std::string, std::string> shown;
  for (;;) {
    std::map<std::string, std::string> q;
    bool have_queue = true;
    try {
      q = campaign::slurm_queue();
    } catch (const pnc::InputError& e) {
      have_queue = false;
      std::cerr << "pnc: warning: " << e.what() << "\n";
    }
    failed.clear();
    campaign::UnitStatus last;
    for (const auto& u : p.units) {
      const campaign::UnitStatus s =
          campaign::effective_status(d.dir, u.id, have_queue ? &q : nullptr);
      std::string line = campaign::state_name(s.state);
      if (!s.job_id.empty()) line += " (job " + s.job_id + ")";
      if (s.state == campaign::UnitState::failed) {
        line += ": " + with_log(s.message, s.log_path);
        failed.push_back(u.id + ": " + s.message + " (job " + s.job_id + ")");
      }
      if (shown[u.id] != line) {
        std::cerr << "pnc: unit " << u.id << ": " << line << "\n";
        shown[u.id] = line;
      }
      if (u.id == d.final_unit) last = s;
    }
    if (last.state == campaign::UnitState::done || last.state == campaign::UnitState::failed)
      return;
    if (last.state == campaign::UnitState::pending)
      fail(d.dir, d.final_unit, "",
           "the " + d.final_unit + " unit has no job: rerun with --resume to submit it");
    for (int k = 0; k < poll_s * 10; ++k) {
      pnc::throw_if_stopped(
          fmt::format("stopped waiting; the Slurm jobs keep running (pnc status {})", d.dir));
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
}

int run_slurm(const CharacterizeArgs& a, const rve::Recipe& r, const campaign::Plan& p) {
  return run_plan_slurm(
      {"characterize", a.out, "fit", a.json}, p, r.slurm, a.slurm, job_prefix_of(r.name),
      [&](const std::vector<std::string>& failed) { return conclude(a, p, failed, {}); });
}

int run_unit_cli(const std::string& dir, const std::vector<std::string>& ids) {
  const campaign::Plan p = campaign::read_plan(dir);
  std::string id = ids.size() == 1 ? ids[0] : "";
  if (ids.size() > 1) { // a job array: task i runs the i-th unit
    const char* t = std::getenv("SLURM_ARRAY_TASK_ID");
    const long k = t && *t ? std::strtol(t, nullptr, 10) : -1;
    if (k < 0 || k >= static_cast<long>(ids.size()))
      fail("<command line>", "UNIT", fmt::format("{} units", ids.size()),
           "several units need $SLURM_ARRAY_TASK_ID = 0..n-1 to pick one (a Slurm job array)");
    id = ids[static_cast<std::size_t>(k)];
  }
  campaign::check_unit_id(id, "<command line>");
  const campaign::Unit& u = p.unit(id);
  if (campaign::read_status(dir, id).state == campaign::UnitState::done) { // e.g. a resubmitted job
    std::cerr << fmt::format("pnc run-unit {} {}: already done, nothing to do\n", dir, id);
    return 0;
  }
  const auto other = plan_commands().find(p.command);
  if (p.command != "characterize" && other == plan_commands().end())
    fail(campaign::plan_path(dir), "command", p.command,
         "is not a command whose units this pnc runs (characterize, thermo ti)");
  const StopSignals signals; // scancel's SIGTERM: stop at the next checkpoint, pending again
  start_run_log(dir, command_line()); // the unit's lines join the run folder's pnc.log
  std::cerr << fmt::format("pnc run-unit {} {} on {} (pid {})\n", dir, id, campaign::host_name(),
                           ::getpid());
  if (p.command != "characterize") return other->second(dir, p, u, true);
  const rve::Recipe r = rve::read_run_recipe(dir);
  return unit_main(dir, p, r, u, true);
}

/// A unit's detail for `pnc status --json`, its times under SI keys (D238, D283): the state
/// files keep `seconds`, `seconds_build`, `seconds_equilibrate`; the JSON says `wall_s`,
/// `build_wall_s`, `equilibrate_wall_s`.
nlohmann::json status_detail_json(const nlohmann::json& detail) {
  if (!detail.is_object()) return nlohmann::json::object();
  static const std::map<std::string, std::string> renamed = {
      {"seconds", "wall_s"},
      {"seconds_build", "build_wall_s"},
      {"seconds_equilibrate", "equilibrate_wall_s"}};
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [k, v] : detail.items()) {
    const auto it = renamed.find(k);
    out[it == renamed.end() ? k : it->second] = v;
  }
  return out;
}

int run_status(const std::string& dir, bool json) {
  const campaign::Plan p = campaign::read_plan(dir);
  bool slurm = false;
  for (const auto& u : p.units)
    slurm = slurm || !campaign::read_status(dir, u.id).job_id.empty();
  std::map<std::string, std::string> q;
  bool have_queue = false;
  if (slurm) try {
      q = campaign::slurm_queue();
      have_queue = true;
    } catch (const pnc::InputError& e) {
      std::cerr << "pnc: warning: " << e.what() << "; states as recorded\n";
    }
  nlohmann::json units = nlohmann::json::array();
  std::map<std::string, int> count;
  std::string table = fmt::format("{:<28} {:<8} {:<10} {:>9}  {}\n", "unit", "state", "job",
                                  "seconds", "queue / message / log");
  const std::string me = campaign::host_name();
  UnitStates states;
  std::vector<std::pair<double, campaign::UnitSeconds>> done_at; // for the ETA (D429): ended
  std::vector<campaign::UnitSeconds> left;
  const double now = campaign::epoch_seconds();
  int running = 0;
  for (const auto& u : p.units) {
    campaign::UnitStatus s = campaign::effective_status(dir, u.id, have_queue ? &q : nullptr);
    states[u.id] = s;
    // a local unit that is "running" in a process that is gone ended without a report
    if (s.state == campaign::UnitState::running && s.job_id.empty() && s.host == me && s.pid > 0 &&
        ::kill(static_cast<pid_t>(s.pid), 0) != 0 && errno == ESRCH) {
      s.state = campaign::UnitState::failed;
      s.message = fmt::format("process {} ended without a report", s.pid);
    }
    ++count[campaign::state_name(s.state)];
    if (s.state == campaign::UnitState::done && s.started_s > 0 && s.ended_s >= s.started_s)
      done_at.push_back({s.ended_s, {u.kind, s.ended_s - s.started_s}});
    else if (s.state == campaign::UnitState::running) {
      ++running;
      left.push_back({u.kind, s.started_s > 0 ? std::max(now - s.started_s, 0.0) : 0.0});
    } else if (s.state != campaign::UnitState::done && s.state != campaign::UnitState::failed)
      left.push_back({u.kind, 0.0});
    const double secs = s.detail.value("seconds", 0.0);
    std::string note = s.message;
    if (have_queue && q.count(s.job_id)) note = q[s.job_id] + (note.empty() ? "" : "; " + note);
    if (!s.log_path.empty() && s.state != campaign::UnitState::done)
      note = note.empty() ? "log " + s.log_path : with_log(note, s.log_path);
    table += fmt::format("{:<28} {:<8} {:<10} {:>9}  {}\n", u.id, campaign::state_name(s.state),
                         s.job_id.empty() ? "-" : s.job_id,
                         secs > 0 ? fmt::format("{:.1f}", secs) : "-", note);
    nlohmann::json j = campaign::status_json(s);
    j["detail"] = status_detail_json(s.detail);
    j["unit"] = u.id;
    j["kind"] = u.kind;
    j["needs"] = u.needs;
    if (have_queue && q.count(s.job_id)) j["queue"] = q[s.job_id];
    units.push_back(j);
  }
  std::string sum;
  for (const char* k : {"done", "running", "queued", "pending", "failed"})
    if (count[k]) sum += fmt::format("{}{} {}", sum.empty() ? "" : ", ", count[k], k);
  // the time left if the units that run now keep running this many at a time (D429), from the
  // finished units in the order they ended
  std::stable_sort(done_at.begin(), done_at.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<campaign::UnitSeconds> finished;
  for (const auto& d : done_at)
    finished.push_back(d.second);
  const double eta = running > 0 ? campaign::remaining_seconds(finished, left, running)
                                 : std::numeric_limits<double>::quiet_NaN();
  if (running > 0 && std::isfinite(eta))
    sum += fmt::format("; about {} left at {} at a time (each unit left at the mean time of "
                       "the finished units of its kind)",
                       pnc::format_duration(eta), running);
  std::cerr << table << fmt::format("pnc status {}: {} unit(s): {}\n", dir, p.units.size(), sum);
  // a Slurm plan whose jobs all ended without its final unit: the run's page says so (D300)
  if (slurm && !p.units.empty()) ended_slurm_plan_report(dir, p, states, p.units.back().id);
  if (json)
    std::cout << nlohmann::json{{"command", "status"},
                                {"dir", dir},
                                {"units", units},
                                {"eta_s",
                                 std::isfinite(eta) ? nlohmann::json(eta) : nlohmann::json()}}
                     .dump()
              << std::endl;
  return count["failed"] > 0 ? 1 : 0;
}

} // namespace

void register_plan_command(const std::string& command, PlanUnitRunner runner) {
  plan_commands()[command] = std::move(runner);
}

int guarded_unit(const campaign::Unit& u, bool print_errors, const std::function<int()>& body) {
  try {
    return body();
  } catch (const pnc::Interrupted& e) {
    if (print_errors)
      std::cerr << "pnc: unit " << u.id << " stopped by " << signal_name(e.signal()) << ": "
                << e.detail() << "; it is pending again\n";
    return 128 + (e.signal() > 0 ? e.signal() : 2);
  } catch (const pnc::InputError& e) {
    if (print_errors) std::cerr << "pnc: error: unit " << u.id << ": " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    if (print_errors) std::cerr << "pnc: internal error: unit " << u.id << ": " << e.what() << "\n";
    return 2;
  }
}

bool plan_parallelism(int cli_ranks, int cli_jobs, int default_jobs, int& ranks, int& jobs) {
  const md::LauncherInfo li = md::launcher_from_environment();
  if (li.rank > 0) return false;
  ranks = cli_ranks > 0 ? cli_ranks : li.size;
  jobs = cli_jobs > 0 ? cli_jobs : (li.size > 1 ? 1 : default_jobs);
  if (li.size > 1)
    std::cerr << fmt::format("pnc: started by mpirun with {} ranks: each LAMMPS stage runs on {} "
                             "rank(s), {} unit(s) at a time\n",
                             li.size, ranks, jobs);
  const unsigned cores = std::thread::hardware_concurrency();
  if (cores > 0 && static_cast<unsigned>(ranks * jobs) > cores)
    std::cerr << fmt::format("pnc: warning: {} ranks x {} jobs = {} processes on {} cores\n", ranks,
                             jobs, ranks * jobs, cores);
  return true;
}

void add_slurm_options(CLI::App* cmd, SlurmOptions& o, const std::string& file) {
  const std::string from = file + "'s slurm.";
  const auto dflt = [&](const std::string& key, const std::string& otherwise) {
    return " (default: " + (!file.empty() ? from + key + ", else " : std::string()) + otherwise +
           ")";
  };
  cmd->add_flag("--wait", o.wait,
                "slurm: wait until the last unit ends, printing every unit's change, then report "
                "as the local executor does (default: submit and return)");
  cmd->add_option("--partition", o.partition,
                  "slurm: partition" + dflt("partition", "the cluster's"));
  cmd->add_option("--account", o.account, "slurm: account" + dflt("account", "the user's"));
  cmd->add_option("--time", o.time,
                  "slurm: time limit per unit job, e.g. 2:00:00" + dflt("time", "the cluster's"));
  cmd->add_option("--sbatch-template", o.sbatch_template,
                  "slurm: job-script template with {{placeholders}}" +
                      dflt("template", "the built-in one; docs/cluster.md"));
  cmd->add_option("--mpi", o.mpi,
                  "slurm: srun's MPI plugin for units on more than one rank, e.g. pmi2" +
                      dflt("mpi", "pmix"));
  cmd->add_option("--job-name", o.job_name, "slurm: prefix of the job names (default pnc-<name>)");
}

std::string job_prefix_of(const std::string& name) {
  std::string s = "pnc-";
  for (char c : name)
    s += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' ? c : '_';
  return s.substr(0, 40);
}

void throw_unless_final_done(const PlanDriver& d, const campaign::Plan& p,
                             const std::vector<std::string>& failed,
                             const std::vector<std::string>& not_run) {
  if (campaign::read_status(d.dir, d.final_unit).state == campaign::UnitState::done) return;
  // a unit stopped by LAMMPS (or by a simulation failure): the driver ends with that error
  // and its exit code (7 or 6, docs/errors.md), the other failures counted on the line before
  for (const auto& u : p.units) {
    const campaign::UnitStatus s = campaign::read_status(d.dir, u.id);
    const auto e = s.detail.find("error");
    if (s.state != campaign::UnitState::failed || e == s.detail.end() || !e->is_object()) continue;
    const int code = e->value("exit_code", 0);
    if (code != pnc::exit_code::tool_failed && code != pnc::exit_code::simulation_failed) continue;
    std::cerr << fmt::format("pnc {}: {} unit(s) failed{}; finished units are kept: "
                             "rerun with --resume (pnc status {} shows every unit)\n",
                             d.command, failed.size(),
                             not_run.empty() ? "" : fmt::format(", {} not run", not_run.size()),
                             d.dir);
    pnc::rethrow_error_record(*e);
  }
  std::string first =
      failed.empty() ? fmt::format("the {} did not run", d.final_unit) : failed.front();
  for (const auto& f : failed)
    if (f.rfind(d.final_unit + ":", 0) != 0) {
      first = f;
      break;
    }
  fail(d.dir, "units", std::to_string(failed.size() + not_run.size()),
       fmt::format("{} unit(s) failed{}: {}; finished units are kept: rerun with --resume "
                   "(pnc status {} shows every unit)",
                   failed.size(),
                   not_run.empty() ? "" : fmt::format(", {} not run", not_run.size()), first,
                   d.dir));
}

int run_local_reported(const PlanDriver& d, const campaign::Plan& p, const std::string& title,
                       const std::function<int()>& body) {
  try {
    return body();
  } catch (const pnc::Interrupted& e) {
    write_plan_stopped_report(d, p, title, signal_reason(e.signal()), false);
    throw;
  } catch (const pnc::Error& e) {
    write_plan_stopped_report(d, p, title, e.what(), true);
    throw;
  }
}

int run_plan_slurm(const PlanDriver& d, const campaign::Plan& p, campaign::SlurmSpec spec,
                   const SlurmOptions& o, const std::string& default_prefix,
                   const std::function<int(const std::vector<std::string>&)>& conclude) {
  if (!o.partition.empty()) spec.partition = o.partition;
  if (!o.account.empty()) spec.account = o.account;
  if (!o.time.empty()) spec.time = o.time;
  if (!o.sbatch_template.empty()) spec.template_path = o.sbatch_template;
  if (!o.mpi.empty()) spec.mpi = o.mpi;
  spec.validate("<command line>");
  const std::string exe = fs::canonical("/proc/self/exe").string();
  const std::string prefix = o.job_name.empty() ? default_prefix : o.job_name;
  const campaign::SlurmSubmission sub = campaign::submit_slurm(d.dir, p, spec, exe, prefix);
  std::map<std::string, std::vector<std::string>> by_job;
  for (const auto& [unit, job] : sub.job_of_unit)
    by_job[job.substr(0, job.find('_'))].push_back(unit);
  for (const auto& j : sub.jobs)
    std::cerr << fmt::format("pnc {}: job {}: {}\n", d.command, j, fmt::join(by_job[j], ", "));
  if (!sub.kept.empty())
    std::cerr << fmt::format("pnc {}: still queued or running: {}\n", d.command,
                             fmt::join(sub.kept, ", "));
  if (sub.jobs.empty() && sub.kept.empty())
    std::cerr << fmt::format("pnc {}: every unit is done\n", d.command);
  if (!o.wait && !(sub.jobs.empty() && sub.kept.empty())) {
    std::cerr << fmt::format("pnc {}: submitted {} job(s); follow with: pnc status {}\n", d.command,
                             sub.jobs.size(), d.dir);
    if (d.json)
      std::cout << nlohmann::json{{"command", d.command},
                                  {"executor", "slurm"},
                                  {"out", d.dir},
                                  {"jobs", sub.jobs},
                                  {"units", sub.job_of_unit}}
                       .dump()
                << std::endl;
    return 0;
  }
  std::vector<std::string> failed;
  const char* poll = std::getenv("PNC_SLURM_POLL_SECONDS");
  try {
    wait_for_slurm(d, p, failed, poll && std::atoi(poll) > 0 ? std::atoi(poll) : 10);
  } catch (const pnc::Interrupted& e) { // only the waiting stops: the jobs keep running (D306)
    return slurm_wait_interrupted(d, p, e.signal() > 0 ? e.signal() : SIGINT);
  }
  try {
    return conclude(failed);
  } catch (const pnc::Error& e) { // the final unit did not run: its page was not written
    if (campaign::read_status(d.dir, d.final_unit).state != campaign::UnitState::done) {
      bool have_queue = false;
      RunStop stop;
      stop.reason = e.what();
      stop.resume = resume_command(); // finished units are kept and not submitted again
      stop.failure = true;
      write_plan_stopped_report(d, p, slurm_states(d.dir, p, have_queue),
                                plan_report_title(d.dir, p), stop);
    }
    throw;
  }
}

int run_characterize(const CharacterizeArgs& a) {
  rve::Recipe r = load_recipe(a.recipe);
  if (a.replicas > 0) r.replicas = a.replicas; // D418: a run of more replicas, or more added
  if (a.executor != "local" && a.executor != "slurm")
    fail("<command line>", "--executor", a.executor, "must be local or slurm");
  int ranks = 1, jobs = 1;
  if (!plan_parallelism(a.ranks, a.jobs, r.jobs, ranks, jobs)) return 0;
  const int nrep = std::max(1, r.replicas);
  int eq_ranks = a.equilibrate_ranks;
  if (a.executor == "slurm") { // ranks per unit: CLI, else the recipe's slurm section, else 1
    if (a.ranks == 0 && r.slurm.ranks > 0) ranks = r.slurm.ranks;
    if (eq_ranks == 0) eq_ranks = r.slurm.equilibrate_ranks > 0 ? r.slurm.equilibrate_ranks : ranks;
  } else if (eq_ranks == 0) {
    // decision D241: min(jobs, replicas) equilibrations run at once and share the cores the
    // cases will share (ranks x jobs, at most the machine's); one replica gets them all
    const int cores = static_cast<int>(std::thread::hardware_concurrency());
    const int budget = cores > 0 ? std::min(ranks * jobs, cores) : ranks;
    eq_ranks = std::max(ranks, budget / std::max(1, std::min(jobs, nrep)));
  }
  // one driver per run folder (core/run_dir.hpp); SIGINT/SIGTERM stop the units at their next
  // checkpoint and leave them pending for --resume (run_control.hpp)
  const RunDirLock lock(a.out, command_line());
  start_run_log(a.out, command_line()); // pnc.log: what this run printed
  const StopSignals signals;
  // --refit (D400): a finished run whose recipe differs only under "fit" continues as --resume
  if (a.refit) rve::check_refit(r, a.out);
  const bool resume = a.resume || a.refit;
  rve::prepare_run_folder(r, a.out, resume, a.refit);
  // the fit runs again on every --resume: it takes seconds, reads only what the MD units left
  // on disk, and follows this command's options (--no-plots) rather than the first run's
  if (resume) campaign::clear_status(a.out, "fit");
  const nlohmann::json params = {
      {"recipe", a.recipe},
      {"replicas", a.replicas}, // --replicas as given (0: the recipe's; D418)
      {"no_plots", a.no_plots},
      {"executor", a.executor},
      {"jobs", jobs},
      {"command_line", command_line()}}; // pnc status offers it with --resume (D300)
  const campaign::Plan p = rve::characterize_plan(r, ranks, eq_ranks, params);
  campaign::write_plan(a.out, p);
  if (a.executor == "slurm") return run_slurm(a, r, p);
  std::cerr << fmt::format("pnc characterize: {} unit(s), {} at a time; cases on {} MPI rank(s), "
                           "equilibrations on {}; states in {}/state, pnc status {} shows them\n",
                           p.units.size(), jobs, ranks, eq_ranks, a.out, a.out);
  return run_local_reported({"characterize", a.out, "fit", a.json}, p,
                            "pnc characterize: " + r.name, [&] {
                              const campaign::LocalRun lr =
                                  campaign::run_local(a.out, p, jobs, [&](const campaign::Unit& u) {
                                    return unit_main(a.out, p, r, u, false);
                                  });
                              return conclude(a, p, lr.failed, lr.not_run);
                            });
}

void register_campaign(CLI::App& app, Action& action) {
  struct UnitArgs {
    std::string dir;
    std::vector<std::string> units;
  };
  auto ua = std::make_shared<UnitArgs>();
  auto* ru = app.add_subcommand(
      "run-unit", "Run one unit of a run folder's plan (what a Slurm job of pnc executes; "
                  "docs/cluster.md)");
  ru->add_option("dir", ua->dir, "Run folder (the --out of pnc characterize or pnc thermo ti)")
      ->required();
  ru->add_option("unit", ua->units,
                 "Unit id, e.g. replica_2/case_4 (several: a job array, task "
                 "$SLURM_ARRAY_TASK_ID picks one)")
      ->required();
  ru->callback([ua, &action] { action = [ua] { return run_unit_cli(ua->dir, ua->units); }; });

  struct StatusArgs {
    std::string dir;
    bool json = false;
  };
  auto sa = std::make_shared<StatusArgs>();
  auto* st = app.add_subcommand(
      "status", "Each unit of a run folder: pending, queued, running, done or failed (with its "
                "message, log and Slurm job id); exit code 1 when a unit failed");
  st->add_option("dir", sa->dir, "Run folder (the --out of pnc characterize or pnc thermo ti)")
      ->required();
  st->add_flag("--json", sa->json, "Print one JSON object on stdout");
  st->callback([sa, &action] { action = [sa] { return run_status(sa->dir, sa->json); }; });
}

} // namespace pnc::app
