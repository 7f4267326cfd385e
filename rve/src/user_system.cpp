// "Characterize your own system": recipe section, input copy + hash, user equilibration stages
// and the measurement of the start state (units real). Decisions D120-D124.
#include "pnc/rve/user_system.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

namespace pnc::rve {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr std::int64_t kMaxSteps = 2000000000;
constexpr std::size_t kMaxLines = 2000, kMaxLineChars = 400;

/// Strict object reader: every key read is remembered, the rest are errors.
class Obj {
public:
  Obj(const json& j, std::string path, const std::string& source)
      : j_(j), path_(std::move(path)), src_(source) {
    if (!j_.is_object()) fail(src_, path_, show_json(j_), "must be an object (a table in TOML)");
  }
  std::string f(const std::string& k) const { return path_ + "." + k; }
  bool has(const std::string& k) const { return j_.contains(k); }
  const json* at(const std::string& k) {
    seen_.insert(k);
    return j_.contains(k) ? &j_.at(k) : nullptr;
  }
  void str(const std::string& k, std::string& out) {
    if (const json* v = at(k)) {
      if (!v->is_string()) fail(src_, f(k), show_json(*v), "must be a string");
      out = v->get<std::string>();
    }
  }
  void num(const std::string& k, double& out) {
    if (const json* v = at(k)) {
      if (!v->is_number() || !std::isfinite(v->get<double>()))
        fail(src_, f(k), show_json(*v), "must be a finite number");
      out = v->get<double>();
    }
  }
  void integer(const std::string& k, long& out, std::int64_t lo, std::int64_t hi) {
    if (const json* v = at(k)) out = get_integer_as<long>(*v, src_, f(k), lo, hi);
  }
  void done() const {
    for (auto it = j_.begin(); it != j_.end(); ++it)
      if (!seen_.count(it.key())) {
        std::string allowed;
        for (const auto& k : seen_)
          allowed += (allowed.empty() ? "" : ", ") + k;
        fail(src_, f(it.key()), show_json(it.value()), "unknown key; allowed: " + allowed);
      }
  }

private:
  const json& j_;
  std::string path_;
  const std::string& src_;
  std::set<std::string> seen_;
};

void check_positive(const std::string& src, const std::string& field, double v,
                    const std::string& unit) {
  if (!(v > 0)) fail(src, field, fmt::format("{}", v), "must be > 0 " + unit);
}

UserStage parse_stage(const json& j, const std::string& path, const std::string& src) {
  Obj o(j, path, src);
  UserStage s;
  o.str("kind", s.kind);
  if (s.kind != "minimize" && s.kind != "langevin" && s.kind != "npt")
    fail(src, o.f("kind"), s.kind.empty() ? "<missing>" : s.kind,
         "must be \"minimize\", \"langevin\" or \"npt\"");
  if (s.kind == "minimize") {
    o.num("ftol", s.ftol);
    o.integer("max_iterations", s.max_iterations, 1, 100000000);
    check_positive(src, o.f("ftol"), s.ftol, "kcal/mol/A");
  } else {
    o.num("temperature", s.temperature);
    o.num("temperature_end", s.temperature_end);
    o.integer("steps", s.steps, 100, kMaxSteps);
    o.num("timestep_fs", s.timestep_fs);
    o.num("damp_fs", s.damp_fs);
    if (!o.has("temperature")) fail(src, o.f("temperature"), "<missing>", "is required (K)");
    if (!o.has("steps")) fail(src, o.f("steps"), "<missing>", "is required (>= 100)");
    check_positive(src, o.f("temperature"), s.temperature, "K");
    if (o.has("temperature_end"))
      check_positive(src, o.f("temperature_end"), s.temperature_end, "K");
    if (!(s.timestep_fs > 0 && s.timestep_fs <= 20))
      fail(src, o.f("timestep_fs"), fmt::format("{}", s.timestep_fs), "must be in (0, 20] fs");
    check_positive(src, o.f("damp_fs"), s.damp_fs, "fs");
    if (s.kind == "npt") {
      o.num("pressure_atm", s.pressure_atm);
      o.num("pdamp_fs", s.pdamp_fs);
      if (std::fabs(s.pressure_atm) > 1e5)
        fail(src, o.f("pressure_atm"), fmt::format("{}", s.pressure_atm), "must be |p| <= 1e5 atm");
      check_positive(src, o.f("pdamp_fs"), s.pdamp_fs, "fs");
    }
  }
  o.done();
  return s;
}

} // namespace

const std::vector<std::string>& allowed_forcefield_commands() {
  // decision D122: commands that define interactions and neighbour lists, nothing else
  static const std::vector<std::string> a = {
      "pair_style",     "pair_coeff",    "pair_modify",    "bond_style",     "bond_coeff",
      "angle_style",    "angle_coeff",   "dihedral_style", "dihedral_coeff", "improper_style",
      "improper_coeff", "special_bonds", "mass",           "kspace_style",   "kspace_modify",
      "neighbor",       "neigh_modify",  "dielectric"};
  return a;
}

void check_forcefield_line(const std::string& source, const std::string& field,
                           const std::string& line) {
  if (line.empty() || line.size() > kMaxLineChars)
    fail(source, field, clip(line), fmt::format("must be 1..{} characters", kMaxLineChars));
  for (const char c : line) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u > 0x7e)
      fail(source, field, clip(line),
           fmt::format("must be printable ASCII (found byte 0x{:02x}; one command per line)", u));
    if (c == '$' || c == '&' || c == '"' || c == '\'')
      fail(source, field, clip(line),
           std::string("must not contain '") + c +
               "' (no variable substitution, line continuation or quoting in force-field lines)");
  }
  std::istringstream in(line);
  std::string first, w;
  in >> first;
  const auto& a = allowed_forcefield_commands();
  if (std::find(a.begin(), a.end(), first) == a.end()) {
    std::string list;
    for (const auto& c : a)
      list += (list.empty() ? "" : ", ") + c;
    fail(source, field, clip(line),
         "a force-field line must start with one of: " + list +
             " (no commands that run, write, include or print; docs/rve.md)");
  }
  while (in >> w)
    if (w == "python" || w.rfind("python/", 0) == 0)
      fail(source, field, clip(line), "Python styles are not allowed in force-field lines");
}

UserSystem parse_user_system(const json& sys, const json* eq, const std::string& source) {
  UserSystem u;
  u.enabled = true;
  Obj o(sys, "system", source);
  std::string data, restart, units, hash;
  o.str("data_file", data);
  o.str("restart_file", restart);
  o.str("atom_style", u.atom_style);
  o.str("units", units);
  o.str("fnv1a64", hash);
  if (data.empty() == restart.empty())
    fail(source, "system.data_file", data.empty() ? "<missing>" : data,
         "give exactly one of system.data_file (LAMMPS data file) and system.restart_file");
  if (!o.has("units"))
    fail(source, "system.units", "<missing>",
         "is required and must be \"real\" (the pipeline works in LAMMPS real units)");
  if (units != "real")
    fail(source, "system.units", units,
         "must be \"real\": the whole rve/ pipeline (timesteps in fs, pressures in atm, the "
         "conversion to Pa) is in LAMMPS real units; convert the data file and force field");
  static const std::vector<std::string> styles = {"atomic", "charge",    "bond",
                                                  "angle",  "molecular", "full"};
  if (std::find(styles.begin(), styles.end(), u.atom_style) == styles.end())
    fail(source, "system.atom_style", u.atom_style,
         "must be one of atomic, charge, bond, angle, molecular, full");
  u.is_restart = !restart.empty();
  u.given_path = u.is_restart ? restart : data;
  const char* key = u.is_restart ? "system.restart_file" : "system.data_file";
  fs::path p(u.given_path);
  if (p.is_relative()) p = fs::path(source).parent_path() / p;
  std::error_code ec;
  if (!fs::is_regular_file(p, ec))
    fail(source, key, u.given_path,
         fmt::format("no such file ({}; relative paths are relative to the recipe file's "
                     "directory)",
                     p.string()));
  u.input_file = fs::absolute(p).lexically_normal().string();
  u.fnv1a64 = file_fnv1a64(u.input_file);
  if (!hash.empty() && hash != u.fnv1a64)
    fail(source, "system.fnv1a64", hash,
         fmt::format("the file {} has FNV-1a 64 hash {}: it changed since the recipe was written",
                     u.input_file, u.fnv1a64));
  const json* ff = o.at("forcefield");
  if (!ff || !ff->is_array() || ff->empty() || ff->size() > kMaxLines)
    fail(source, "system.forcefield", ff ? show_json(*ff) : "<missing>",
         fmt::format("must be a non-empty array of at most {} LAMMPS commands (strings)",
                     kMaxLines));
  for (std::size_t i = 0; i < ff->size(); ++i) {
    const std::string field = fmt::format("system.forcefield[{}]", i);
    if (!(*ff)[i].is_string()) fail(source, field, show_json((*ff)[i]), "must be a string");
    const std::string line = (*ff)[i].get<std::string>();
    check_forcefield_line(source, field, line);
    u.forcefield.push_back(line);
  }
  o.done();
  if (eq) {
    Obj e(*eq, "equilibrate", source);
    if (const json* st = e.at("stages")) {
      if (!st->is_array() || st->size() > 100)
        fail(source, "equilibrate.stages", show_json(*st),
             "must be an array of at most 100 stages");
      for (std::size_t i = 0; i < st->size(); ++i)
        u.stages.push_back(parse_stage((*st)[i], fmt::format("equilibrate.stages[{}]", i), source));
    }
    e.done();
  }
  return u;
}

json user_system_json(const UserSystem& u) {
  json sys = {{u.is_restart ? "restart_file" : "data_file", u.input_file},
              {"atom_style", u.atom_style},
              {"units", "real"},
              {"forcefield", u.forcefield},
              {"fnv1a64", u.fnv1a64}};
  json st = json::array();
  for (const auto& s : u.stages) {
    json j = {{"kind", s.kind}};
    if (s.kind == "minimize") {
      j["ftol"] = s.ftol;
      j["max_iterations"] = s.max_iterations;
    } else {
      j["temperature"] = s.temperature;
      j["temperature_end"] = s.t_end();
      j["steps"] = s.steps;
      j["timestep_fs"] = s.timestep_fs;
      j["damp_fs"] = s.damp_fs;
      if (s.kind == "npt") {
        j["pressure_atm"] = s.pressure_atm;
        j["pdamp_fs"] = s.pdamp_fs;
      }
    }
    st.push_back(j);
  }
  return {{"system", sys}, {"equilibrate", {{"stages", st}}}};
}

namespace {
std::string record_path(const std::string& build_dir) {
  return (fs::path(build_dir) / "system.json").string();
}
void check_record(const UserSystem& u, const std::string& rec) {
  std::ifstream f(rec);
  const json j = json::parse(f, nullptr, false);
  const std::string old = j.is_object() ? j.value("fnv1a64", std::string()) : std::string();
  if (old != u.fnv1a64)
    fail(u.input_file, u.is_restart ? "system.restart_file" : "system.data_file", u.given_path,
         fmt::format("the input changed since this run was made (FNV-1a 64 hash {} recorded in "
                     "{}, {} now): --resume would mix two systems; use a new --out directory",
                     old.empty() ? "<unreadable>" : old, rec, u.fnv1a64));
}
} // namespace

void check_user_input_unchanged(const UserSystem& u, const std::string& dir) {
  const std::string rec = record_path((fs::path(dir) / "build").string());
  if (fs::exists(rec)) check_record(u, rec);
}

std::string prepare_user_input(const UserSystem& u, const std::string& build_dir, bool resume) {
  make_output_directory(build_dir);
  const std::string copy =
      (fs::path(build_dir) / (u.is_restart ? "system.restart" : "system.data")).string();
  const std::string rec = record_path(build_dir);
  if (resume && fs::exists(rec) && fs::exists(copy)) {
    check_record(u, rec);
    if (file_fnv1a64(copy) != u.fnv1a64)
      fail(copy, "", "",
           "the copy of the input in the run directory was modified; use a new --out");
    std::cerr << "pnc characterize [system] input unchanged (resumed)\n";
    return copy;
  }
  std::ifstream in(u.input_file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  if (!in.good() && !in.eof()) fail(u.input_file, "", "", "cannot read the input file");
  write_text_atomically(copy, bytes);
  if (file_fnv1a64(copy) != u.fnv1a64)
    fail(u.input_file, "", "", "the input file changed while it was copied");
  json r = user_system_json(u)["system"];
  r["copy"] = copy;
  r["given_path"] = u.given_path;
  r["hash_algorithm"] = "FNV-1a 64 of the file's bytes (16 hex digits)";
  write_text_atomically(rec, r.dump(2) + "\n");
  std::cerr << fmt::format("pnc characterize [system] {} ({} bytes, FNV-1a 64 {}) copied to {}\n",
                           u.input_file, bytes.size(), u.fnv1a64, copy);
  return copy;
}

std::string user_system_report(const UserSystem& u) {
  std::string s = fmt::format(
      "User system: {} `{}` (FNV-1a 64 `{}`, copied to build/), atom style {}, units real. "
      "Force field (re-issued by every stage and case):\n\n```\n",
      u.is_restart ? "restart file" : "data file", u.input_file, u.fnv1a64, u.atom_style);
  for (const auto& l : u.forcefield)
    s += l + "\n";
  s += "```\n\n";
  if (u.stages.empty())
    s += "No equilibration stages: the cases start from the input state (decision D123). The "
         "void fraction is not measured for a user system (no bead diameter).\n\n";
  else
    s += "The void fraction is not measured for a user system (no bead diameter).\n\n";
  return s;
}

} // namespace pnc::rve
