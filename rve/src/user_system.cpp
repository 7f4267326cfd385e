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

const std::vector<Choice> kStageKinds = {
    {"minimize", "conjugate-gradient minimisation at the fixed box"},
    {"langevin", "NVE + Langevin"},
    {"npt", "Nose-Hoover, iso; then the box is set to the mean volume of the second half"}};

// One stage: "kind" first (it selects the keys), then the keys of that kind (declare_user_stage).
UserStage parse_stage(const json& j, const std::string& path, const std::string& src) {
  if (!j.is_object()) fail(src, path, show_json(j), "must be an object (a table in TOML)");
  UserStage s;
  {
    Parameters k("stage kind");
    k.string("kind", s.kind, kStageKinds, "what the stage does").require();
    if (!j.contains("kind"))
      fail(src, path + ".kind", "<missing>", "is required: " + k.at("kind").rule());
    k.at("kind").validate(j.at("kind"), src, path + ".kind");
  }
  Parameters p("stage");
  declare_user_stage(p, s, j.at("kind").get<std::string>());
  p.read(j, src, path);
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

void declare_user_stage(Parameters& p, UserStage& s, const std::string& kind) {
  p.string("kind", s.kind, kStageKinds, "what the stage does").require();
  if (kind == "minimize") {
    p.real("ftol", s.ftol, RealRange::above(0), "kcal/mol/A",
           "force tolerance (2-norm of the force vector)");
    p.integer("max_iterations", s.max_iterations, 1, 100000000, "", "iterations at most");
    return;
  }
  p.real("temperature", s.temperature, RealRange::above(0), "K", "thermostat temperature")
      .require();
  p.real("temperature_end", s.temperature_end, RealRange::above(0), "K",
         "temperature at the end of the stage, ramped from temperature")
      .no_default("= temperature");
  p.integer("steps", s.steps, 100, kMaxSteps, "", "MD steps").require();
  p.real("timestep_fs", s.timestep_fs, RealRange::open_closed(0, 20), "fs", "MD time step");
  p.real("damp_fs", s.damp_fs, RealRange::above(0), "fs", "thermostat damping time");
  if (kind != "npt") return;
  p.real("pressure_atm", s.pressure_atm, RealRange::closed(-1e5, 1e5), "atm", "pressure (iso)");
  p.real("pdamp_fs", s.pdamp_fs, RealRange::above(0), "fs", "barostat damping time");
}

void declare_user_system(Parameters& p, UserSystem& u, const std::string& applies,
                         bool stage_tables) {
  p.section("system",
            "your own LAMMPS data (or restart) file and force field instead of the builder "
            "(D121-D124)",
            applies);
  p.string("data_file", u.given.data_file, {},
           "LAMMPS data file, relative to the recipe file's directory (or absolute)")
      .no_default("give restart_file instead (exactly one of the two)");
  p.string("restart_file", u.given.restart_file, {}, "LAMMPS restart file, instead of data_file")
      .no_default("give data_file instead");
  p.string("atom_style", u.atom_style,
           {{"atomic", ""},
            {"charge", ""},
            {"bond", ""},
            {"angle", ""},
            {"molecular", ""},
            {"full", ""}},
           "LAMMPS atom style of the file");
  p.string("units", u.given.units,
           {{"real", "A, fs, kcal/mol, g/mol, atm, K: the whole rve/ pipeline, its timesteps, "
                     "pressures and the conversion to Pa, is in real units; convert the data "
                     "file and force field"}},
           "LAMMPS units of the file and the force field")
      .require();
  p.strings("forcefield", u.forcefield, 1, kMaxLines,
            "LAMMPS commands, re-issued after every read_data/read_restart of every stage and "
            "case")
      .require()
      .also(fmt::format("each at most {} characters and an allowed command (D122)", kMaxLineChars),
            [](const json& v, const std::string& source, const std::string& field) {
              for (std::size_t i = 0; i < v.size(); ++i)
                check_forcefield_line(source, fmt::format("{}[{}]", field, i),
                                      v[i].get<std::string>());
            });
  p.string("fnv1a64", u.given.fnv1a64, {},
           "FNV-1a 64 hash of the file's bytes (16 hex digits); the expanded recipe carries it")
      .no_default("not checked");
  p.section("equilibrate", "your own equilibration: stages run in order (D123)", applies);
  Parameter st;
  st.path = "stages";
  st.type = ParamType::table_list;
  st.default_value = json::array();
  st.max_size = 100;
  st.text = "the stages, each a table with \"kind\" and the keys of that kind";
  st.check = [&u](const json& v, const std::string& source, const std::string& field) {
    u.stages.clear();
    for (std::size_t i = 0; i < v.size(); ++i)
      u.stages.push_back(parse_stage(v[i], fmt::format("{}[{}]", field, i), source));
  };
  p.add(std::move(st));
  if (!stage_tables) return;
  static UserStage docs_stage; // only its defaults are read: the tables print them
  for (const auto& k : kStageKinds) {
    p.section("equilibrate.stages[]", k.meaning, "kind = \"" + k.value + "\"");
    declare_user_stage(p, docs_stage, k.value);
  }
}

void finish_user_system(UserSystem& u, const std::string& source) {
  u.enabled = true;
  const std::string& data = u.given.data_file;
  const std::string& restart = u.given.restart_file;
  if (data.empty() == restart.empty())
    fail(source, "system.data_file", data.empty() ? "<missing>" : data,
         "give exactly one of system.data_file (LAMMPS data file) and system.restart_file");
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
  const std::string& hash = u.given.fnv1a64;
  if (!hash.empty() && hash != u.fnv1a64)
    fail(source, "system.fnv1a64", hash,
         fmt::format("the file {} has FNV-1a 64 hash {}: it changed since the recipe was written",
                     u.input_file, u.fnv1a64));
}

UserSystem parse_user_system(const json& sys, const json* eq, const std::string& source) {
  UserSystem u;
  Parameters p("system");
  declare_user_system(p, u);
  json in = {{"system", sys}};
  if (eq) in["equilibrate"] = *eq;
  p.read(in, source);
  finish_user_system(u, source);
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
