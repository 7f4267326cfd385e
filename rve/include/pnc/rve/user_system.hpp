#pragma once
// pnc/rve/user_system.hpp: "characterize your own system": a recipe that starts from the user's
// LAMMPS data (or restart) file and force-field commands instead of pnc's builder.
//
// Units: LAMMPS `real` only (A, fs, kcal/mol, g/mol, atm, K; densities g/cm^3); a recipe with
// other units is refused (the whole rve/ pipeline, its stresses and its Pa conversion assume
// real units).
//
// Recipe sections (JSON; TOML tables with the same keys), docs/rve.md "Characterize your own
// system":
//   "system": { "data_file": "fcc.data"        (path relative to the recipe file's directory)
//               | "restart_file": "x.restart", (exactly one of the two)
//               "atom_style": "atomic",        (atomic|charge|bond|angle|molecular|full)
//               "units": "real",               (required, must be "real")
//               "forcefield": ["pair_style lj/cut 8.5", "pair_coeff * * 0.2381 3.405", ...],
//               "fnv1a64": "<16 hex digits>" } (optional: the input file's hash must match)
//   "equilibrate": { "stages": [ {"kind": "minimize", "ftol": 1e-8, "max_iterations": 10000},
//                                {"kind": "langevin", "temperature": K, "temperature_end": K,
//                                 "steps": N, "timestep_fs": 1, "damp_fs": 100},
//                                {"kind": "npt", "temperature": K, "temperature_end": K,
//                                 "pressure_atm": 0, "steps": N, "timestep_fs": 1,
//                                 "damp_fs": 100, "pdamp_fs": 1000} ] }  ([] or absent: none)
// Force-field commands are an allow-list (kAllowedForceFieldCommands; decision D122): nothing
// that runs dynamics, writes or includes files, calls the shell or Python, or substitutes
// variables.
#include "pnc/core/parameters.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace pnc::rve {

struct UserStage {
  std::string kind;            ///< "minimize", "langevin" or "npt"
  double temperature = 0;      ///< K (langevin, npt: > 0)
  double temperature_end = -1; ///< K, ramp target over the stage; < 0: = temperature
  double pressure_atm = 0;     ///< npt (iso)
  long steps = 0;              ///< langevin, npt: >= 100
  double timestep_fs = 1.0;
  double damp_fs = 100;   ///< thermostat damping time, fs
  double pdamp_fs = 1000; ///< barostat damping time, fs
  double ftol = 1e-8;     ///< minimize: force tolerance, kcal/mol/A (2-norm of the force vector)
  long max_iterations = 10000; ///< minimize
  double t_end() const { return temperature_end < 0 ? temperature : temperature_end; }
};

struct UserSystem {
  /// The keys of "system" as written in the recipe (declare_user_system binds them); the fields
  /// below are what finish_user_system makes of them.
  struct Given {
    std::string data_file, restart_file, units, fnv1a64;
  } given;
  bool enabled = false;    ///< the recipe has a "system" section
  std::string input_file;  ///< absolute path of the data or restart file
  bool is_restart = false; ///< input_file is a LAMMPS restart file (else a data file)
  std::string given_path;  ///< the path as written in the recipe
  std::string atom_style = "atomic";
  std::vector<std::string> forcefield; ///< re-issued after every read_data / read_restart
  std::vector<UserStage> stages;
  std::string fnv1a64; ///< hash of input_file's bytes when the recipe was read (16 hex digits)
};

/// The first words a force-field line may start with.
const std::vector<std::string>& allowed_forcefield_commands();

/// Declares the keys of "system" and of the user's "equilibrate" (its "stages", each read with
/// declare_user_stage) in `p`, bound to `u` (decisions D121, D231). `applies` labels the two
/// sections in printed tables; with `stage_tables` the keys of each stage kind are declared too,
/// as sections "equilibrate.stages[]" (for the documentation only).
void declare_user_system(Parameters& p, UserSystem& u, const std::string& applies = "",
                         bool stage_tables = false);
/// Declares the keys of one stage of `kind` ("minimize", "langevin", "npt") in the open section
/// of `p`, bound to `s`.
void declare_user_stage(Parameters& p, UserStage& s, const std::string& kind);
/// After the declared reads: exactly one of data_file and restart_file, the file resolved
/// against the recipe's directory and hashed (and compared with a given fnv1a64); sets enabled.
void finish_user_system(UserSystem& u, const std::string& source);
/// Parses "system" (`sys`) and, when given, "equilibrate" (`eq`, may be null) of a recipe.
/// `source` is the recipe file: relative paths are resolved against its directory. Throws
/// pnc::InputError naming source, the dotted field, the value and the rule.
UserSystem parse_user_system(const nlohmann::json& sys, const nlohmann::json* eq,
                             const std::string& source);

/// JSON form of a parsed user system: {"system": {...}, "equilibrate": {"stages": [...]}}, with
/// the absolute input path and its hash (parse_user_system reads it back).
nlohmann::json user_system_json(const UserSystem& u);

/// Checks one force-field command (allow-list, printable ASCII, no `$`, quotes, `&` or `python`).
void check_forcefield_line(const std::string& source, const std::string& field,
                           const std::string& line);

/// Copies the input into `build_dir` (system.data or system.restart) and writes
/// `build_dir`/system.json (original path, hash, atom style, force field). With `resume` and an
/// existing record whose hash differs from `u.fnv1a64`, throws an InputError: the input changed
/// since the run was made. Returns the path of the copy.
std::string prepare_user_input(const UserSystem& u, const std::string& build_dir, bool resume);

/// Throws when `dir` holds a run (`dir`/build/system.json) made from an input whose hash differs
/// from u.fnv1a64 (checked before anything else on --resume).
void check_user_input_unchanged(const UserSystem& u, const std::string& dir);

struct EquilibratedState;

/// Runs the user's stages (one child process each, files `dir`/stage_<i>_<kind>.{log,h5,restart})
/// from `input` (the copy in build/), then the measurement stage "final" (no dynamics): density,
/// virial and total pressure, temperature (at T > 0: means over the second half of the last
/// dynamic stage), smallest distance between any two atoms; it writes `dir`/final.restart, the
/// start state of the deformation cases (decision D123). Finished stages are skipped on resume.
EquilibratedState equilibrate_user(const UserSystem& u, const std::string& input,
                                   const std::string& dir, bool resume,
                                   const std::string& recipe_json, std::uint64_t seed,
                                   int ranks = 1);

/// One paragraph (markdown) describing the user system for report.md.
std::string user_system_report(const UserSystem& u);

} // namespace pnc::rve
