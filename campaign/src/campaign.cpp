// Plan of units and per-unit state files (campaign.hpp, decisions D240-D242).
#include "pnc/campaign/campaign.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/error_record.hpp"
#include "pnc/core/stop.hpp"

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace pnc::campaign {

namespace fs = std::filesystem;

const Unit& Plan::unit(const std::string& id) const {
  for (const auto& u : units)
    if (u.id == id) return u;
  fail("plan.json", "unit", id, "no such unit in this run's plan (pnc status DIR lists them)");
}

bool Plan::has(const std::string& id) const {
  for (const auto& u : units)
    if (u.id == id) return true;
  return false;
}

void check_unit_id(const std::string& id, const std::string& source) {
  bool ok = !id.empty() && id.size() <= 200 && id.front() != '/' && id.back() != '/';
  for (std::size_t i = 0; ok && i < id.size(); ++i) {
    const char c = id[i];
    ok = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
         (c == '/' && id[i - 1] != '/');
  }
  if (!ok)
    fail(source, "unit", id,
         "a unit id is lower-case letters, digits and '_' in parts separated by single '/'");
}

void check_plan(const Plan& p, const std::string& source) {
  std::set<std::string> seen;
  std::map<std::string, std::string> group_kind;
  for (const auto& u : p.units) {
    check_unit_id(u.id, source);
    if (!seen.insert(u.id).second) fail(source, "unit", u.id, "appears twice in the plan");
    for (const auto& n : u.needs)
      if (!seen.count(n))
        fail(source, u.id + ".needs", n, "must name a unit listed before it in the plan");
    if (u.ranks < 1 || u.ranks > 4096)
      fail(source, u.id + ".ranks", std::to_string(u.ranks), "must be 1 to 4096");
    check_unit_id(u.group, source + " (group)");
    auto [it, fresh] = group_kind.emplace(u.group, u.kind);
    if (!fresh && it->second != u.kind)
      fail(source, u.id + ".group", u.group, "a group holds units of one kind only");
  }
}

nlohmann::json plan_json(const Plan& p) {
  nlohmann::json units = nlohmann::json::array();
  for (const auto& u : p.units)
    units.push_back({{"id", u.id},
                     {"kind", u.kind},
                     {"group", u.group},
                     {"needs", u.needs},
                     {"join", u.join},
                     {"ranks", u.ranks},
                     {"inputs", u.inputs},
                     {"outputs", u.outputs}});
  return {{"format", "pnc plan v1 (docs/cluster.md)"},
          {"command", p.command},
          {"parameters", p.parameters},
          {"units", units}};
}

Plan plan_from_json(const nlohmann::json& j, const std::string& source) {
  Plan p;
  try {
    p.command = j.at("command").get<std::string>();
    p.parameters = j.at("parameters");
    for (const auto& u : j.at("units")) {
      Unit x;
      x.id = u.at("id").get<std::string>();
      x.kind = u.at("kind").get<std::string>();
      x.group = u.at("group").get<std::string>();
      x.needs = u.at("needs").get<std::vector<std::string>>();
      x.join = u.at("join").get<bool>();
      x.ranks = u.at("ranks").get<int>();
      x.inputs = u.value("inputs", std::vector<std::string>{});
      x.outputs = u.value("outputs", std::vector<std::string>{});
      p.units.push_back(std::move(x));
    }
  } catch (const nlohmann::json::exception& e) {
    fail(source, "", "", std::string("is not a pnc plan: ") + e.what());
  }
  check_plan(p, source);
  return p;
}

std::string plan_path(const std::string& dir) {
  return (fs::path(dir) / "plan.json").string();
}

void write_plan(const std::string& dir, const Plan& p) {
  check_plan(p, plan_path(dir));
  write_text_atomically(plan_path(dir), plan_json(p).dump(2) + "\n");
}

Plan read_plan(const std::string& dir) {
  const std::string path = plan_path(dir);
  std::ifstream f(path);
  if (!f) fail(path, "", "", "no plan in this folder: is it the --out folder of pnc characterize?");
  const auto j = nlohmann::json::parse(f, nullptr, false);
  if (j.is_discarded()) fail(path, "", "", "is not valid JSON");
  return plan_from_json(j, path);
}

const char* state_name(UnitState s) {
  switch (s) {
  case UnitState::pending:
    return "pending";
  case UnitState::queued:
    return "queued";
  case UnitState::running:
    return "running";
  case UnitState::done:
    return "done";
  case UnitState::failed:
    return "failed";
  }
  return "pending";
}

nlohmann::json status_json(const UnitStatus& s) {
  return {{"state", state_name(s.state)},
          {"job_id", s.job_id},
          {"host", s.host},
          {"pid", s.pid},
          {"message", s.message},
          {"log", s.log_path},
          {"queued_s", s.queued_s},
          {"started_s", s.started_s},
          {"ended_s", s.ended_s},
          {"detail", s.detail}};
}

std::string state_path(const std::string& dir, const std::string& id) {
  check_unit_id(id, plan_path(dir));
  return (fs::path(dir) / "state" / (id + ".json")).string();
}

UnitStatus read_status(const std::string& dir, const std::string& id) {
  UnitStatus s;
  const std::string path = state_path(dir, id);
  std::ifstream f(path);
  if (!f) return s;
  const auto j = nlohmann::json::parse(f, nullptr, false);
  if (j.is_discarded() || !j.is_object()) fail(path, "", "", "is not a unit state (JSON object)");
  const std::string st = j.value("state", "");
  bool known = false;
  for (auto k : {UnitState::pending, UnitState::queued, UnitState::running, UnitState::done,
                 UnitState::failed})
    if (st == state_name(k)) {
      s.state = k;
      known = true;
    }
  if (!known) fail(path, "state", st, "must be pending, queued, running, done or failed");
  s.job_id = j.value("job_id", "");
  s.host = j.value("host", "");
  s.pid = j.value("pid", 0L);
  s.message = j.value("message", "");
  s.log_path = j.value("log", "");
  s.queued_s = j.value("queued_s", 0.0);
  s.started_s = j.value("started_s", 0.0);
  s.ended_s = j.value("ended_s", 0.0);
  if (j.contains("detail") && j["detail"].is_object()) s.detail = j["detail"];
  return s;
}

void write_status(const std::string& dir, const std::string& id, const UnitStatus& s) {
  const std::string path = state_path(dir, id);
  make_output_directory(fs::path(path).parent_path().string());
  write_text_atomically(path, status_json(s).dump(2) + "\n");
}

void clear_status(const std::string& dir, const std::string& id) {
  std::error_code ec;
  fs::remove(state_path(dir, id), ec);
}

double epoch_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string host_name() {
  char h[256] = {};
  if (::gethostname(h, sizeof h - 1) != 0) return "?";
  return h;
}

namespace {
/// An exclusive lock on DIR/state/<id>.lock for as long as the unit runs: one process per unit.
class UnitLock {
public:
  UnitLock(const std::string& dir, const std::string& id) {
    const std::string path = state_path(dir, id) + ".lock";
    make_output_directory(fs::path(path).parent_path().string());
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd_ < 0) fail(path, "unit", id, "cannot open the unit's lock file");
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      fail(path, "unit", id, "is being run by another process (its state file says where)");
    }
  }
  ~UnitLock() { ::close(fd_); }
  UnitLock(const UnitLock&) = delete;
  UnitLock& operator=(const UnitLock&) = delete;

private:
  int fd_ = -1;
};
} // namespace

void run_unit_recorded(const std::string& dir, const Unit& u,
                       const std::function<nlohmann::json()>& body,
                       const std::string& fallback_log) {
  const UnitLock lock(dir, u.id);
  UnitStatus s = read_status(dir, u.id);
  s.state = UnitState::running;
  if (const char* j = std::getenv("SLURM_JOB_ID"); j && *j) {
    const char* a = std::getenv("SLURM_ARRAY_JOB_ID");
    const char* t = std::getenv("SLURM_ARRAY_TASK_ID");
    s.job_id = a && *a && t && *t ? fmt::format("{}_{}", a, t) : std::string(j);
  }
  s.host = host_name();
  s.pid = static_cast<long>(::getpid());
  s.message.clear();
  s.started_s = epoch_seconds();
  s.ended_s = 0;
  s.detail = nlohmann::json::object();
  if (s.log_path.empty() || s.job_id.empty()) s.log_path = fallback_log;
  write_status(dir, u.id, s);
  try {
    s.detail = body();
    s.state = UnitState::done;
    s.ended_s = epoch_seconds();
    s.detail["seconds"] = s.ended_s - s.started_s;
    s.pid = 0;
    write_status(dir, u.id, s);
  } catch (const pnc::Interrupted& e) {
    s.state = UnitState::pending;
    s.message = "stopped by signal " + std::to_string(e.signal()) + ": " + e.detail();
    s.pid = 0;
    s.ended_s = epoch_seconds();
    write_status(dir, u.id, s);
    throw;
  } catch (const UnitFailure& e) {
    s.state = UnitState::failed;
    s.message = e.what();
    if (!e.log_path.empty()) s.log_path = e.log_path;
    s.pid = 0;
    s.ended_s = epoch_seconds();
    write_status(dir, u.id, s);
    throw;
  } catch (const pnc::InputError& e) {
    s.state = UnitState::failed;
    s.message = e.what();
    s.detail["error"] = error_record(e);
    // a stage failure names its LAMMPS log as the error's source (runner.hpp)
    const std::string src = e.context().source;
    if (src.size() > 4 && (src.find(".log") != std::string::npos) && fs::exists(src))
      s.log_path = src;
    s.pid = 0;
    s.ended_s = epoch_seconds();
    write_status(dir, u.id, s);
    throw;
  } catch (const std::exception& e) {
    s.state = UnitState::failed;
    s.message = e.what();
    // the driver throws the same kind again (exit code 6 or 7 with the tool's log)
    s.detail["error"] = error_record(e);
    if (const auto* te = dynamic_cast<const ToolError*>(&e); te && !te->context().log_path.empty())
      s.log_path = te->context().log_path;
    s.pid = 0;
    s.ended_s = epoch_seconds();
    write_status(dir, u.id, s);
    throw;
  }
}

} // namespace pnc::campaign
