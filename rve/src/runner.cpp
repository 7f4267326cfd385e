// Child-process stage runner for LAMMPS (see runner.hpp for why).
#include "pnc/rve/runner.hpp"

#include "pnc/core/error.hpp"

#include <lammps/library.h>

#include <fmt/format.h>

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <map>
#include <sstream>

namespace pnc::rve {

void Lammps::cmd(const std::string& command) {
  lammps_command(h_, command.c_str());
}

void Lammps::cmds(const std::vector<std::string>& commands) {
  for (const auto& c : commands)
    cmd(c);
}

void Lammps::file(const std::string& path) {
  lammps_file(h_, path.c_str());
}

double Lammps::thermo(const char* keyword) {
  return lammps_get_thermo(h_, keyword);
}

long Lammps::natoms() {
  return static_cast<long>(lammps_get_natoms(h_));
}

double Lammps::fix_value(const std::string& id, int i, int j) {
  const int type = j < 0 ? LMP_TYPE_VECTOR : LMP_TYPE_ARRAY;
  auto* p = static_cast<double*>(
      lammps_extract_fix(h_, id.c_str(), LMP_STYLE_GLOBAL, type, i, j < 0 ? 0 : j));
  if (!p) fail("<lammps>", "fix " + id, fmt::format("({}, {})", i, j), "no such global value");
  const double v = *p;
  lammps_free(p);
  return v;
}

double Lammps::compute_value(const std::string& id, int i) {
  if (i < 0) {
    auto* p = static_cast<double*>(
        lammps_extract_compute(h_, id.c_str(), LMP_STYLE_GLOBAL, LMP_TYPE_SCALAR));
    if (!p) fail("<lammps>", "compute " + id, "", "no global scalar");
    return *p;
  }
  auto* p = static_cast<double*>(
      lammps_extract_compute(h_, id.c_str(), LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR));
  if (!p) fail("<lammps>", "compute " + id, std::to_string(i), "no global vector");
  return p[i];
}

std::vector<double> Lammps::gather(const std::string& name, int count) {
  std::vector<double> out(static_cast<std::size_t>(natoms()) * count);
  std::string n = name;
  lammps_gather_atoms(h_, n.data(), 1, count, out.data());
  return out;
}

void Lammps::box(double lo[3], double hi[3], double& xy, double& yz, double& xz) {
  int periodicity[3];
  int changed;
  lammps_extract_box(h_, lo, hi, &xy, &yz, &xz, periodicity, &changed);
}

std::string last_lammps_error(const std::string& log_path) {
  std::ifstream f(log_path);
  std::string line, err, last_cmd;
  bool after = false;
  while (std::getline(f, line)) {
    if (line.rfind("ERROR", 0) == 0) {
      err = line;
      last_cmd.clear();
      after = true;
    } else if (after && line.rfind("Last command:", 0) == 0) {
      last_cmd = line;
      after = false;
    }
  }
  if (err.empty()) return "";
  return last_cmd.empty() ? err : err + " | " + last_cmd;
}

namespace {

std::string error_file(const std::string& log) {
  return log + ".pnc-error";
}

[[noreturn]] void child_main(const StageSpec& spec, const StageBody& body) {
  std::vector<std::string> args = {"pnc", "-log", spec.log_path, "-screen", "none", "-nocite"};
  for (const auto& a : spec.extra_args)
    args.push_back(a);
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  int code = 0;
  void* h = lammps_open_no_mpi(static_cast<int>(argv.size()), argv.data(), nullptr);
  if (!h) {
    std::ofstream(error_file(spec.log_path)) << "could not create a LAMMPS instance\n";
    _exit(4);
  }
  try {
    Lammps lmp(h);
    body(lmp);
  } catch (const std::exception& e) {
    std::ofstream(error_file(spec.log_path)) << e.what() << "\n";
    code = 3;
  }
  lammps_close(h);
  lammps_mpi_finalize();
  std::fflush(nullptr);
  _exit(code);
}

pid_t start_child(const StageSpec& spec, const StageBody& body) {
  std::remove(error_file(spec.log_path).c_str());
  std::fflush(nullptr); // no duplicated stdio buffers in the child
  const pid_t pid = fork();
  if (pid < 0) fail("<runner>", spec.name, "", "fork() failed");
  if (pid == 0) {
    // a stage must not outlive pnc (kill -9 of the parent): its checkpoint stays consistent
    // and a later --resume does not race an orphan
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    child_main(spec, body);
  }
  return pid;
}

StageOutcome finish(const StageSpec& spec, int status, double seconds) {
  StageOutcome o;
  o.name = spec.name;
  o.log_path = spec.log_path;
  o.seconds = seconds;
  if (WIFEXITED(status)) {
    o.exit_code = WEXITSTATUS(status);
    o.ok = o.exit_code == 0;
  } else if (WIFSIGNALED(status)) {
    o.signal = WTERMSIG(status);
  }
  if (o.ok) return o;
  std::ifstream pe(error_file(spec.log_path));
  std::stringstream ss;
  ss << pe.rdbuf();
  std::string msg = ss.str();
  while (!msg.empty() && (msg.back() == '\n' || msg.back() == '\r'))
    msg.pop_back();
  if (msg.empty()) msg = last_lammps_error(spec.log_path);
  if (msg.empty())
    msg = o.signal ? fmt::format("killed by signal {}", o.signal)
                   : fmt::format("exited with status {} and no ERROR line in the log", o.exit_code);
  o.error = msg;
  return o;
}

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

} // namespace

StageOutcome run_stage(const StageSpec& spec, const StageBody& body) {
  const double t0 = now();
  const pid_t pid = start_child(spec, body);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
  }
  return finish(spec, status, now() - t0);
}

std::vector<StageOutcome> run_stages(const std::vector<std::pair<StageSpec, StageBody>>& stages,
                                     int jobs) {
  std::vector<StageOutcome> out(stages.size());
  std::map<pid_t, std::pair<std::size_t, double>> running;
  std::size_t next = 0;
  if (jobs < 1) jobs = 1;
  while (next < stages.size() || !running.empty()) {
    while (next < stages.size() && static_cast<int>(running.size()) < jobs) {
      running[start_child(stages[next].first, stages[next].second)] = {next, now()};
      ++next;
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) continue;
    auto it = running.find(pid);
    if (it == running.end()) continue;
    const auto [idx, t0] = it->second;
    out[idx] = finish(stages[idx].first, status, now() - t0);
    running.erase(it);
  }
  return out;
}

} // namespace pnc::rve
