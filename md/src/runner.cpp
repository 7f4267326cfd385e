// Child-process stage runner for LAMMPS (see runner.hpp for why; each stage's in.<stage>: D247).
#include "pnc/md/runner.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/fd_io.hpp"
#include "pnc/core/locate.hpp"
#include "pnc/core/params.hpp"
#include "pnc/core/version.hpp"

#include <lammps/library.h>

#include <fmt/format.h>

#include "lammps_wire.hpp"
#include "pnc/md/private_channel.hpp"

#include <fcntl.h>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>

namespace pnc::md {

std::vector<double> Lammps::call(char op, const std::string& text, int i, int j, bool* found) {
  wire::Request r;
  r.op = op;
  r.i = i;
  r.j = j;
  r.text = text;
  std::vector<char> ans;
  if (!wire::write_frame(fd_, wire::encode(r)) || !wire::read_frame(fd_, ans) || ans.empty()) {
    const std::string err = last_lammps_error(log_);
    fail_tool("LAMMPS", "running '" + clip(text) + "' on the LAMMPS server",
              err.empty() ? "the LAMMPS server ended without an ERROR line in its log (see " +
                                log_ + ".mpirun)"
                          : err,
              log_);
  }
  if (found) *found = ans[0] == 0;
  std::vector<double> v((ans.size() - 1) / sizeof(double));
  if (!v.empty()) std::memcpy(v.data(), ans.data() + 1, v.size() * sizeof(double));
  return v;
}

Lammps::~Lammps() {
  if (input_fd_ >= 0) ::close(input_fd_);
  if (owned_ && h_) lammps_close(h_); // open_in_process (lammps_local.cpp)
}

bool Lammps::record_input(const std::string& path, const std::string& header) {
  if (input_fd_ >= 0) ::close(input_fd_);
  input_fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (input_fd_ < 0) return false;
  record(header);
  return true;
}

// Written before LAMMPS runs the command, unbuffered: a LAMMPS error ends the process at once.
void Lammps::record(const std::string& text) {
  if (input_fd_ < 0) return;
  // best effort: the recorded input is a copy; LAMMPS runs the command either way
  (void)write_fully(input_fd_, text.empty() || text.back() != '\n' ? text + "\n" : text);
}

void Lammps::cmd(const std::string& command) {
  record(command);
  if (fd_ >= 0)
    call(wire::kCommand, command);
  else
    lammps_command(h_, command.c_str());
}

void Lammps::cmds(const std::vector<std::string>& commands) {
  for (const auto& c : commands)
    cmd(c);
}

void Lammps::file(const std::string& path) {
  record("include " + path);
  if (fd_ >= 0)
    call(wire::kFile, path);
  else
    lammps_file(h_, path.c_str());
}

double Lammps::thermo(const char* keyword) {
  if (fd_ >= 0) return call(wire::kThermo, keyword).at(0);
  return lammps_get_thermo(h_, keyword);
}

long Lammps::natoms() {
  if (fd_ >= 0) return static_cast<long>(call(wire::kNatoms, "").at(0));
  return static_cast<long>(lammps_get_natoms(h_));
}

double Lammps::fix_value(const std::string& id, int i, int j) {
  if (fd_ >= 0) {
    bool found = false;
    const auto v = call(wire::kFix, id, i, j, &found);
    if (!found || v.empty())
      fail("<lammps>", "fix " + id, fmt::format("({}, {})", i, j), "no such global value");
    return v[0];
  }
  const int type = j < 0 ? LMP_TYPE_VECTOR : LMP_TYPE_ARRAY;
  auto* p = static_cast<double*>(
      lammps_extract_fix(h_, id.c_str(), LMP_STYLE_GLOBAL, type, i, j < 0 ? 0 : j));
  if (!p) fail("<lammps>", "fix " + id, fmt::format("({}, {})", i, j), "no such global value");
  const double v = *p;
  lammps_free(p);
  return v;
}

double Lammps::compute_value(const std::string& id, int i) {
  if (fd_ >= 0) {
    bool found = false;
    const auto v = call(wire::kCompute, id, i, 0, &found);
    if (!found || v.empty())
      fail("<lammps>", "compute " + id, i < 0 ? "" : std::to_string(i),
           i < 0 ? "no global scalar" : "no global vector");
    return v[0];
  }
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
  if (fd_ >= 0) return call(wire::kGather, name, count);
  std::vector<double> out(static_cast<std::size_t>(natoms()) * count);
  std::string n = name;
  lammps_gather_atoms(h_, n.data(), 1, count, out.data());
  return out;
}

std::vector<double> Lammps::compute_local_vector(const std::string& id) {
  bool ok = false;
  std::vector<double> v;
  if (fd_ >= 0) {
    bool found = false;
    v = call(wire::kLocal, id, 0, 0, &found);
    ok = found;
  } else {
    v = wire::local_compute_rows(h_, id, ok);
  }
  if (!ok)
    fail("<lammps>", "compute " + id, "",
         fmt::format("no local vector (or more than {} rows)", wire::kMaxLocalRows));
  return v;
}

int Lammps::version() {
  if (fd_ >= 0) return static_cast<int>(call(wire::kVersion, "").at(0));
  return lammps_version(h_);
}

double Lammps::extract_global_double(const std::string& name) {
  bool ok = false;
  double v = 0;
  if (fd_ >= 0) {
    const auto r = call(wire::kGlobal, name, 0, 0, &ok);
    ok = ok && !r.empty();
    if (ok) v = r[0];
  } else {
    v = wire::global_double(h_, name, ok);
  }
  if (!ok) fail("<lammps>", "global", name, "LAMMPS has no global double of that name");
  return v;
}

LmpBox Lammps::box() {
  LmpBox b;
  if (fd_ >= 0) { // the server sends lo, hi, xy, yz, xz (LAMMPS order)
    const auto v = call(wire::kBox, "");
    for (std::size_t k = 0; k < 3; ++k) {
      b.lo[k] = v.at(k);
      b.hi[k] = v.at(3 + k);
    }
    b.xy = v.at(6);
    b.yz = v.at(7);
    b.xz = v.at(8);
    return b;
  }
  int periodicity[3];
  int changed;
  lammps_extract_box(h_, b.lo.data(), b.hi.data(), &b.xy, &b.yz, &b.xz, periodicity, &changed);
  return b;
}

void Lammps::quit() {
  if (fd_ >= 0) call(wire::kQuit, "");
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

// `<log>.pnc-error`: the error the stage body threw in the child, so that the parent rebuilds
// it with its kind. Line 1 "pnc-error K" (K: the error's exit code, core/error.hpp), then its
// parts one per line (line breaks inside a part become blanks):
//   1 (InputError): source, field, value, rule
//   6 (SimulationError): entity, step, time, time unit, message
//   7 (ToolError): tool, doing, message, log path
//   2 (anything else): what()
constexpr const char* kErrorTag = "pnc-error ";

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

void write_error_file(const std::string& log, const std::exception& e) {
  std::vector<std::string> parts;
  int kind = exit_code::internal_error;
  if (const auto* ie = dynamic_cast<const InputError*>(&e)) {
    const auto& c = ie->context();
    kind = exit_code::bad_input;
    parts = {c.source, c.field, c.value, c.rule};
  } else if (const auto* se = dynamic_cast<const SimulationError*>(&e)) {
    const auto& c = se->context();
    kind = exit_code::simulation_failed;
    parts = {c.entity, std::to_string(c.step), fmt::format("{:.17g}", c.time), c.time_unit,
             c.message};
  } else if (const auto* te = dynamic_cast<const ToolError*>(&e)) {
    const auto& c = te->context();
    kind = exit_code::tool_failed;
    parts = {c.tool, c.doing, c.message, c.log_path};
  } else {
    parts = {e.what()};
  }
  std::ofstream f(error_file(log));
  f << kErrorTag << kind << "\n";
  for (const auto& p : parts)
    f << one_line(p) << "\n";
}

/// Rebuilds the child's error from `<log>.pnc-error`; null when there is none. `text` gets its
/// one-line message (what()).
std::exception_ptr read_error_file(const std::string& log, std::string& text) {
  std::ifstream f(error_file(log));
  std::string head;
  if (!f || !std::getline(f, head) || head.rfind(kErrorTag, 0) != 0) return nullptr;
  std::vector<std::string> p;
  for (std::string line; std::getline(f, line);)
    p.push_back(line);
  const int kind = std::atoi(head.c_str() + std::strlen(kErrorTag));
  const auto part = [&p](std::size_t i) { return i < p.size() ? p[i] : std::string(); };
  std::exception_ptr e;
  try {
    switch (kind) {
    case exit_code::bad_input:
      throw InputError(ErrorContext{part(0), part(1), part(2), part(3)});
    case exit_code::simulation_failed:
      throw SimulationError(SimulationContext{part(0), std::atoll(part(1).c_str()),
                                              std::strtod(part(2).c_str(), nullptr), part(3),
                                              part(4)});
    case exit_code::tool_failed:
      throw ToolError(ToolContext{part(0), part(1), part(2), part(3)});
    default:
      throw std::runtime_error(part(0));
    }
  } catch (const std::exception& x) {
    text = x.what();
    e = std::current_exception();
  }
  return e;
}

std::string server_executable() {
  if (const char* e = std::getenv("PNC_LAMMPS_SERVER"); e && *e) return e;
  // libexec/pnc relative to the running executable (install and build tree alike, D151)
  const Located r = locate_shipped(ShippedDir::libexec, "pnc_lammps_server", nullptr);
  if (r.path.empty())
    fail("<pnc installation>", "", "pnc_lammps_server",
         "the MPI stage server was not found (" + r.looked_in() +
             "); set PNC_LAMMPS_SERVER to its path (install layout: docs/install.md)");
  return r.path;
}

/// The launcher of a K-rank stage: `mpirun -np K --bind-to none`, or inside a Slurm job of
/// the Slurm executor (PNC_STAGE_LAUNCHER=srun, decision D244) `srun --ntasks=K --mpi=<plugin>`
/// (PNC_SRUN_MPI, default pmix), a job step on the job's own allocation.
std::vector<std::string> stage_launcher(int ranks) {
  const char* l = std::getenv("PNC_STAGE_LAUNCHER");
  if (l && std::string(l) == "srun") {
    const char* m = std::getenv("PNC_SRUN_MPI");
    return {"srun", "--ntasks=" + std::to_string(ranks),
            std::string("--mpi=") + (m && *m ? m : "pmix"), "--overlap"};
  }
  return {"mpirun", "-np", std::to_string(ranks), "--bind-to", "none"};
}

/// Starts `mpirun -np K pnc_lammps_server SOCKET <lammps args>` with a clean MPI environment
/// (so that it also works when pnc itself was started by mpirun) and the channel's token in
/// the environment (private_channel.hpp), and waits until rank 0 connects and passes the
/// checks. Returns the connected socket; throws (pnc error) if mpirun ends first or the
/// server does not connect within PNC_LAMMPS_CONNECT_TIMEOUT seconds (default 300). The
/// private directory and its socket are gone when this returns or throws.
int start_server(const StageSpec& spec, const std::vector<std::string>& lammps_args,
                 pid_t& mpirun_pid) {
  PrivateListener channel; // throws naming the directory when it cannot be made
  const std::string exe = server_executable();
  const std::string out = spec.log_path + ".mpirun";
  std::vector<std::string> args = stage_launcher(spec.ranks); // mpirun, or srun in a Slurm job
  args.insert(args.end(), {exe, channel.socket_path()});
  args.insert(args.end(), lammps_args.begin(), lammps_args.end());
  std::fflush(nullptr);
  mpirun_pid = fork();
  if (mpirun_pid < 0) fail("<runner>", spec.name, "", "fork() failed");
  if (mpirun_pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGTERM); // mpirun forwards SIGTERM to its ranks
    // a clean launcher environment: drop what an outer mpirun set for this process
    std::vector<std::string> drop;
    for (char** e = environ; *e; ++e) {
      const std::string kv = *e;
      for (const char* pre : {"OMPI_", "PMIX_", "OPAL_", "ORTE_", "PMI_", "HYDRA_"})
        if (kv.rfind(pre, 0) == 0) drop.push_back(kv.substr(0, kv.find('=')));
    }
    for (const auto& d : drop)
      unsetenv(d.c_str());
    if (getuid() == 0) { // Open MPI refuses root without these; CI containers run as root
      setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
      setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    }
    // the token goes through the environment (owner-readable), never argv (world-readable)
    setenv(kLammpsTokenEnv, channel.token().c_str(), 1);
    cpu_set_t all; // an outer mpirun may have bound this process to one core
    CPU_ZERO(&all);
    for (int c = 0; c < CPU_SETSIZE; ++c)
      CPU_SET(c, &all);
    sched_setaffinity(0, sizeof(all), &all);
    const int fd = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
    }
    std::vector<char*> argv;
    for (auto& s : args)
      argv.push_back(s.data());
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    std::fprintf(stderr, "pnc: cannot run %s: %s\n", argv[0], std::strerror(errno));
    _exit(127);
  }
  const char* t = std::getenv("PNC_LAMMPS_CONNECT_TIMEOUT");
  const double timeout = t && std::atof(t) > 0 ? std::atof(t) : 300.0;
  const double t0 =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  for (;;) { // accept, refusing impostors, until the real rank 0 connects or mpirun ends
    const int fd = channel.accept_one(args[0] == "srun" ? -1 : mpirun_pid, 200);
    if (fd >= 0) return fd; // `channel` removes the socket and its directory on return
    int status = 0;
    if (waitpid(mpirun_pid, &status, WNOHANG) == mpirun_pid) {
      std::ifstream f(out);
      std::string line, last;
      while (std::getline(f, line))
        if (!line.empty()) last = line;
      fail_tool("mpirun", fmt::format("starting the LAMMPS server (mpirun -np {})", spec.ranks),
                fmt::format("mpirun ended (status {}) before the LAMMPS server connected: {}{}",
                            WIFEXITED(status) ? WEXITSTATUS(status) : -1, last,
                            channel.refused() ? " (refused peer: " + channel.last_refusal() + ")"
                                              : std::string()),
                out);
    }
    const double el =
        std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count() -
        t0;
    if (el > timeout) {
      kill(mpirun_pid, SIGTERM);
      while (waitpid(mpirun_pid, &status, 0) < 0 && errno == EINTR) {
      }
      fail_tool("mpirun", fmt::format("starting the LAMMPS server (mpirun -np {})", spec.ranks),
                fmt::format("the LAMMPS server did not connect within {} s{}", timeout,
                            channel.refused() ? " (refused peer: " + channel.last_refusal() + ")"
                                              : std::string()),
                out);
    }
  }
}

/// The comment lines that open a stage's `in.<name>` (stage_input_path).
std::string input_header(const StageSpec& spec, const std::vector<std::string>& lammps_args) {
  std::error_code ec;
  std::string extra;
  for (const auto& a : lammps_args)
    extra += " " + a;
  std::string h = fmt::format(
      "# LAMMPS input of the pnc stage '{}' ({}), recorded as it ran: every command pnc sent\n"
      "# to LAMMPS, in order. Values pnc read back between commands (thermo, fix and compute\n"
      "# values) only chose the commands that follow, which are recorded as sent.\n"
      "# Rerun from {} with:\n#   {}lmp{} -in {}\n",
      spec.name, version_string(), std::filesystem::current_path(ec).string(),
      spec.ranks > 1 ? fmt::format("mpirun -np {} ", spec.ranks) : std::string(), extra,
      stage_input_path(spec));
  return h;
}

[[noreturn]] void child_main(const StageSpec& spec, const StageBody& body) {
  std::vector<std::string> args = {"pnc", "-log", spec.log_path, "-screen", "none", "-nocite"};
  for (const auto& a : spec.extra_args)
    args.push_back(a);
  if (spec.ranks > 1) {
    int code = 0;
    try {
      pid_t mp = -1;
      const int fd = start_server(spec, {args.begin() + 1, args.end()}, mp);
      {
        Lammps lmp(fd, spec.log_path);
        lmp.record_input(stage_input_path(spec), input_header(spec, spec.extra_args));
        body(lmp);
        lmp.quit();
      }
      close(fd);
      int status = 0;
      while (waitpid(mp, &status, 0) < 0) {
      }
    } catch (const std::exception& e) {
      write_error_file(spec.log_path, e);
      code = 3;
    }
    std::fflush(nullptr);
    _exit(code);
  }
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  int code = 0;
  void* h = lammps_open_no_mpi(static_cast<int>(argv.size()), argv.data(), nullptr);
  if (!h) {
    write_error_file(spec.log_path,
                     ToolError(ToolContext{"LAMMPS", "starting stage " + spec.name,
                                           "could not create a LAMMPS instance", spec.log_path}));
    _exit(4);
  }
  try {
    Lammps lmp(h);
    lmp.record_input(stage_input_path(spec), input_header(spec, spec.extra_args));
    body(lmp);
  } catch (const std::exception& e) {
    write_error_file(spec.log_path, e);
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
  std::error_code ec;
  if (std::filesystem::exists(stage_input_path(spec), ec)) o.input_path = stage_input_path(spec);
  if (o.ok) return o;
  std::string msg;
  o.child_error = read_error_file(spec.log_path, msg);
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

void throw_stage_failure(const StageOutcome& o, const std::string& stage, const std::string& note) {
  if (o.child_error) {
    try {
      std::rethrow_exception(o.child_error);
    } catch (const InputError& e) { // as before: the stage and its log name the source
      fail(o.log_path, stage, "", e.what() + note);
    } catch (const SimulationError& e) {
      SimulationContext c = e.context();
      c.entity = c.entity.empty() ? stage : stage + ": " + c.entity;
      c.message += note + " (log " + o.log_path + ")";
      throw SimulationError(c);
    } catch (const ToolError& e) { // e.g. the MPI server: named with the stage it served
      ToolContext c = e.context();
      c.doing += (c.doing.empty() ? "" : " ") + ("(" + stage + ")");
      c.message += note;
      throw ToolError(c);
    } catch (const std::exception& e) {
      throw std::runtime_error(stage + ": " + e.what() + note + " (log " + o.log_path + ")");
    }
  }
  // the commands as LAMMPS received them, up to the one that failed (D247): rerunnable alone
  const std::string input =
      o.input_path.empty() ? "" : "; the commands sent, rerunnable with lmp -in: " + o.input_path;
  fail_tool("LAMMPS", "running " + stage, o.error + note + input, o.log_path);
}

std::string stage_input_path(const StageSpec& spec) {
  std::string n = spec.name.empty() ? "stage" : spec.name;
  for (char& c : n)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return (std::filesystem::path(spec.log_path).parent_path() / ("in." + n)).string();
}

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

} // namespace pnc::md
