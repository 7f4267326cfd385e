// The Slurm executor: job arrays per group, afterok/afterany dependencies, held submission,
// queue checks (slurm.hpp, decisions D243-D245).
#include "pnc/campaign/slurm.hpp"
#include "pnc/campaign/slurm_parameters.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/subprocess.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace pnc::campaign {

namespace fs = std::filesystem;

namespace {

bool is_name(const std::string& s) {
  return !s.empty() && s.size() <= 64 && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-';
  }) && s.front() != '-';
}

void check_name(const std::string& source, const std::string& field, const std::string& v) {
  if (!v.empty() && !is_name(v))
    fail(source, field, v,
         "must be 1 to 64 characters of letters, digits, '_', '.' and '-', not starting with '-'");
}

std::string last_line(const std::string& text) {
  std::istringstream in(text);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  while (!s.empty() && s.back() == ' ')
    s.pop_back();
  return s;
}

} // namespace

void SlurmSpec::validate(const std::string& source) const {
  check_name(source, "slurm.partition", partition);
  check_name(source, "slurm.account", account);
  static const std::regex time_re(R"(^(\d{1,4}-)?\d{1,6}(:\d{1,2}){0,2}$)");
  if (!time.empty() && !std::regex_match(time, time_re))
    fail(source, "slurm.time", time,
         "must be a Slurm time limit: minutes, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS");
  if (ranks < 0 || ranks > 4096)
    fail(source, "slurm.ranks", std::to_string(ranks), "must be 1 to 4096 (0: the default)");
  if (equilibrate_ranks < 0 || equilibrate_ranks > 4096)
    fail(source, "slurm.equilibrate_ranks", std::to_string(equilibrate_ranks),
         "must be 1 to 4096 (0: the default)");
  check_name(source, "slurm.mpi", mpi);
  if (mpi.empty()) fail(source, "slurm.mpi", mpi, "must name srun's MPI plugin (pmix, pmi2)");
}

SlurmSpec parse_slurm_spec(const nlohmann::json& j, const std::string& source) {
  SlurmSpec s;
  s.given = true;
  if (!j.is_object()) fail(source, "slurm", j.dump(), "must be an object");
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string k = it.key();
    const auto& v = it.value();
    const std::string field = "slurm." + k;
    if (k == "partition" || k == "account" || k == "time" || k == "template" || k == "mpi") {
      if (!v.is_string()) fail(source, field, v.dump(), "must be a string");
      const std::string x = v.get<std::string>();
      (k == "partition" ? s.partition
       : k == "account" ? s.account
       : k == "time"    ? s.time
       : k == "mpi"     ? s.mpi
                        : s.template_path) = x;
    } else if (k == "ranks" || k == "equilibrate_ranks") {
      if (!v.is_number_integer()) fail(source, field, v.dump(), "must be an integer 1 to 4096");
      const auto n = v.get<long long>();
      if (n < 1 || n > 4096) fail(source, field, v.dump(), "must be an integer 1 to 4096");
      (k == "ranks" ? s.ranks : s.equilibrate_ranks) = static_cast<int>(n);
    } else {
      fail(source, field, v.dump(),
           "unknown key; allowed: partition, account, time, ranks, equilibrate_ranks, "
           "template, mpi");
    }
  }
  s.validate(source);
  return s;
}

namespace {
// A string key of the slurm section checked by SlurmSpec::validate (its wording and field).
ParamCheck slurm_check(std::string SlurmSpec::*member) {
  return [member](const nlohmann::json& v, const std::string& source, const std::string&) {
    SlurmSpec s;
    s.*member = v.get<std::string>();
    s.validate(source);
  };
}
} // namespace

void declare_slurm_section(Parameters& p, SlurmSpec& s, const std::string& text, bool ranks) {
  p.optional_section("slurm", s.given, text);
  const std::string name = "a name: 1 to 64 letters, digits, '_', '.', '-', not starting with '-'";
  p.string("partition", s.partition, {}, "sbatch --partition of the unit jobs")
      .also(name, slurm_check(&SlurmSpec::partition))
      .no_default("the cluster's default partition");
  p.string("account", s.account, {}, "sbatch --account of the unit jobs")
      .also(name, slurm_check(&SlurmSpec::account))
      .no_default("the user's default account");
  p.string("time", s.time, {}, "time limit per unit job")
      .also("a Slurm time limit: minutes, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS",
            slurm_check(&SlurmSpec::time))
      .no_default("the partition's default");
  if (ranks) {
    p.integer("ranks", s.ranks, 1, 4096, "", "MPI ranks per case unit under Slurm")
        .no_default("pnc characterize --ranks, else 1");
    p.integer("equilibrate_ranks", s.equilibrate_ranks, 1, 4096, "",
              "MPI ranks per equilibration and phase-check unit under Slurm")
        .no_default("slurm.ranks");
  }
  p.string("template", s.template_path, {}, "the job-script template file (docs/cluster.md)")
      .no_default("the built-in template");
  // D332: every planned command's units may run on K > 1 ranks (characterize's cases, thermo
  // ti's points), so `mpi` is declared for both, the rank keys for characterize only
  p.string("mpi", s.mpi, {}, "srun's MPI plugin (--mpi) for units on more than one rank")
      .also(name, slurm_check(&SlurmSpec::mpi))
      .omit_when_default();
}

nlohmann::json slurm_spec_json(const SlurmSpec& s) {
  nlohmann::json j = nlohmann::json::object();
  if (!s.partition.empty()) j["partition"] = s.partition;
  if (!s.account.empty()) j["account"] = s.account;
  if (!s.time.empty()) j["time"] = s.time;
  if (s.ranks > 0) j["ranks"] = s.ranks;
  if (s.equilibrate_ranks > 0) j["equilibrate_ranks"] = s.equilibrate_ranks;
  if (!s.template_path.empty()) j["template"] = s.template_path;
  if (s.mpi != "pmix") j["mpi"] = s.mpi;
  return j;
}

const std::string& default_sbatch_template() {
  static const std::string t =
      "#!/bin/bash\n"
      "# pnc unit job {{job_name}}: {{kind}} unit(s), {{ranks}} MPI rank(s) each.\n"
      "# Written by pnc from its built-in template (docs/cluster.md). pnc passes the sbatch\n"
      "# options (array, dependencies, ntasks, partition, account, time, output) on sbatch's\n"
      "# command line, and the command the job runs as this script's arguments.\n"
      "# Site set-up goes here, e.g.:\n"
      "#   module load openmpi lammps\n"
      "set -eu\n"
      "exec \"$@\"\n";
  return t;
}

std::string render_template(const std::string& text,
                            const std::map<std::string, std::string>& values,
                            const std::string& source) {
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    const auto open = text.find("{{", i);
    if (open == std::string::npos) {
      out += text.substr(i);
      break;
    }
    out += text.substr(i, open - i);
    const auto close = text.find("}}", open + 2);
    if (close == std::string::npos)
      fail(source, "template", text.substr(open, 20), "a '{{' without its '}}'");
    const std::string name = text.substr(open + 2, close - open - 2);
    const auto it = values.find(name);
    if (it == values.end()) {
      std::string known;
      for (const auto& [k, v] : values)
        known += (known.empty() ? "" : ", ") + ("{{" + k + "}}");
      fail(source, "template", "{{" + name + "}}", "unknown placeholder; known: " + known);
    }
    out += it->second;
    i = close + 2;
  }
  return out;
}

std::map<std::string, std::string> slurm_queue() {
  const auto r = run_subprocess({"squeue", "--me", "-h", "-r", "-o", "%i|%T|%r"});
  if (!r.ok())
    fail("squeue", "", "",
         r.started ? "squeue failed: " + one_line(r.output)
                   : "cannot run squeue (" + r.error + "): is Slurm installed and on PATH?");
  std::map<std::string, std::string> q;
  std::istringstream in(r.output);
  std::string line;
  while (std::getline(in, line)) {
    const auto a = line.find('|');
    if (a == std::string::npos) continue;
    const auto b = line.find('|', a + 1);
    const std::string id = line.substr(0, a);
    const std::string state = line.substr(a + 1, b == std::string::npos ? b : b - a - 1);
    const std::string reason = b == std::string::npos ? "" : line.substr(b + 1);
    q[id] = reason.empty() || reason == "None" ? state : state + " (" + reason + ")";
  }
  return q;
}

UnitStatus effective_status(const std::string& dir, const std::string& id,
                            const std::map<std::string, std::string>* queue) {
  UnitStatus s = read_status(dir, id);
  if (!queue || s.job_id.empty()) return s;
  if (s.state != UnitState::queued && s.state != UnitState::running) return s;
  if (queue->count(s.job_id)) return s;
  s.state = UnitState::failed;
  s.message = fmt::format("job {} ended without a report (cancelled, timed out, killed, or its "
                          "dependency failed){}",
                          s.job_id, s.message.empty() ? "" : "; last message: " + s.message);
  return s;
}

namespace {

struct Group {
  std::string name, kind;
  int ranks = 1;
  bool join = false;
  std::vector<const Unit*> units;
};

std::string submit_one(const std::vector<std::string>& argv, const std::string& group) {
  const auto r = run_subprocess(argv);
  if (!r.ok())
    fail("sbatch", group, "",
         r.started ? "sbatch refused the job: " + one_line(r.output)
                   : "cannot run sbatch (" + r.error + "): is Slurm installed and on PATH?");
  static const std::regex id_re(R"(^(\d+)(;.*)?$)");
  std::smatch m;
  const std::string line = last_line(r.output);
  if (!std::regex_match(line, m, id_re))
    fail("sbatch", group, line, "sbatch --parsable printed no job id");
  return m[1].str();
}

} // namespace

SlurmSubmission submit_slurm(const std::string& dir, const Plan& p, const SlurmSpec& spec,
                             const std::string& pnc_exe, const std::string& job_prefix) {
  spec.validate("slurm options");
  check_name("slurm options", "job name", job_prefix);
  const std::string adir = fs::absolute(dir).lexically_normal().string();
  if (adir.find('%') != std::string::npos)
    fail(dir, "--out", dir, "must not contain '%' (sbatch expands it in output file names)");
  const std::map<std::string, std::string> queue = slurm_queue();
  SlurmSubmission out;
  std::set<std::string> done;
  std::vector<Group> groups;
  for (const auto& u : p.units) {
    const UnitStatus s = read_status(dir, u.id);
    if (s.state == UnitState::done) {
      done.insert(u.id);
      continue;
    }
    if ((s.state == UnitState::queued || s.state == UnitState::running) && !s.job_id.empty() &&
        queue.count(s.job_id)) { // alive: keep it, and wait for it
      out.job_of_unit[u.id] = s.job_id;
      out.kept.push_back(u.id);
      continue;
    }
    auto g = std::find_if(groups.begin(), groups.end(),
                          [&](const Group& x) { return x.name == u.group; });
    if (g == groups.end()) {
      groups.push_back({u.group, u.kind, u.ranks, u.join, {}});
      g = groups.end() - 1;
    }
    g->ranks = std::max(g->ranks, u.ranks);
    g->join = g->join || u.join;
    g->units.push_back(&u);
  }
  const std::string tpl_source =
      spec.template_path.empty() ? std::string("<built-in sbatch template>") : spec.template_path;
  std::string tpl = default_sbatch_template();
  if (!spec.template_path.empty()) {
    std::ifstream f(spec.template_path);
    if (!f) fail(spec.template_path, "slurm.template", "", "cannot read the job-script template");
    std::stringstream ss;
    ss << f.rdbuf();
    tpl = ss.str();
  }
  const std::string sdir = (fs::path(adir) / "slurm").string();
  make_output_directory(sdir);
  try {
    for (const auto& g : groups) {
      std::set<std::string> deps;
      for (const Unit* u : g.units)
        for (const auto& n : u->needs)
          if (!done.count(n)) {
            const auto it = out.job_of_unit.find(n);
            if (it == out.job_of_unit.end())
              fail(plan_path(dir), u->id, n, "a need has no job (plan order broken)");
            deps.insert(it->second);
          }
      const std::string name = job_prefix + "-" + g.name;
      const std::map<std::string, std::string> values = {{"job_name", name},
                                                         {"kind", g.kind},
                                                         {"ranks", std::to_string(g.ranks)},
                                                         {"group", g.name},
                                                         {"partition", spec.partition},
                                                         {"account", spec.account},
                                                         {"time", spec.time}};
      const std::string script = (fs::path(sdir) / (g.name + ".sbatch")).string();
      write_text_atomically(script, render_template(tpl, values, tpl_source));
      const bool array = g.units.size() > 1;
      std::vector<std::string> argv = {
          "sbatch",
          "--parsable",
          "--hold",
          "--job-name=" + name,
          "--chdir=" + adir,
          "--ntasks=" + std::to_string(g.ranks),
          "--kill-on-invalid-dep=yes",
          "--export=ALL,PNC_STAGE_LAUNCHER=srun,PNC_SRUN_MPI=" + spec.mpi,
          "--output=" + sdir + "/" + g.name + (array ? "-%A_%a.out" : "-%j.out")};
      if (array) argv.push_back(fmt::format("--array=0-{}", g.units.size() - 1));
      if (!deps.empty()) {
        std::string d = g.join ? "afterany" : "afterok";
        for (const auto& j : deps)
          d += ":" + j;
        argv.push_back("--dependency=" + d);
      }
      if (!spec.partition.empty()) argv.push_back("--partition=" + spec.partition);
      if (!spec.account.empty()) argv.push_back("--account=" + spec.account);
      if (!spec.time.empty()) argv.push_back("--time=" + spec.time);
      argv.insert(argv.end(), {script, pnc_exe, "run-unit", adir});
      for (const Unit* u : g.units)
        argv.push_back(u->id);
      const std::string job = submit_one(argv, g.name);
      out.jobs.push_back(job);
      for (std::size_t i = 0; i < g.units.size(); ++i) {
        const std::string jid = array ? fmt::format("{}_{}", job, i) : job;
        out.job_of_unit[g.units[i]->id] = jid;
        UnitStatus s;
        s.state = UnitState::queued;
        s.job_id = jid;
        s.log_path = sdir + "/" + g.name +
                     (array ? fmt::format("-{}_{}.out", job, i) : fmt::format("-{}.out", job));
        s.queued_s = epoch_seconds();
        write_status(dir, g.units[i]->id, s);
      }
    }
  } catch (...) {
    for (const auto& j : out.jobs)
      run_subprocess({"scancel", j});
    throw;
  }
  if (!out.jobs.empty()) {
    std::vector<std::string> argv = {"scontrol", "release"};
    std::string ids;
    for (const auto& j : out.jobs)
      ids += (ids.empty() ? "" : ",") + j;
    argv.push_back(ids);
    const auto r = run_subprocess(argv);
    if (!r.ok())
      fail("scontrol", "release", ids,
           "could not release the held jobs: " + one_line(r.output) +
               "; release them with scontrol release, or cancel them with scancel");
  }
  return out;
}

} // namespace pnc::campaign
