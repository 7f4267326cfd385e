#pragma once
// pnc/gimp_coupler/input.hpp: the input file of `pnc gimp run` (docs/gimp.md).
//
// One JSON object (".json"), or the same keys as TOML (".toml", tables for objects; read into
// the same JSON by pnc::read_input_file, D357); SI units (m, kg, s, Pa). Every key is declared once
// (input_parameters): unknown keys are refused naming the allowed ones and the nearest, every value
// is checked against its type and range, then the rules between keys. Every error is a
// pnc::InputError naming the file, the key (e.g. "bodies[1].radius"), the value and the rule it
// broke.
#include "pnc/core/parameters.hpp"
#include "pnc/gimp_coupler/solver.hpp"

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace pnc::gimp {

/// Run controls read from the input (everything that is not the mechanical problem).
struct RunConfig {
  std::string source; ///< input file path (errors and relative paths)
  int dimension = 2;  ///< 2 (plane strain) or 3
  double t_end = 0.0; ///< s
  double cfl = 0.5;   ///< safety factor on the CFL step
  double dt = 0.0;    ///< fixed step, s (0: CFL step every step)
  long max_steps = 0; ///< 0: no limit
  int threads = 1;
  double output_interval = 0.0; ///< s between VTU frames (0: first and last only)
  bool vtu_binary = false;      ///< base64 binary arrays instead of ASCII
  long history_every = 1;       ///< steps between history rows
  int checkpoint_every = 1;     ///< VTU frames between checkpoints
  long fracture_every = 10;     ///< steps between J evaluations / crack growth checks (2-D)
  std::vector<std::string> material_names;
  /// The input with every default filled in (JSON text, keys sorted): what `--resume` compares
  /// with the checkpoint's (D339)
  std::string expanded_input;
};

/// The keys of the input, each declared once with its type, default, range and SI unit
/// (input_parameters.cpp, D290): `dimension` 2 or 3 as read for that dimension; 0 for the
/// documentation of both (vectors of 2 or 3 numbers). With `tables`, the keys of the tables'
/// elements follow as sections "materials[]", "bodies[]", ... (one per kind: a set for
/// printing as Markdown or JSON only; to_toml() and read() need tables = false).
/// `pnc gimp parameters` prints them.
pnc::Parameters input_parameters(int dimension, bool tables = true);

/// The `dimension` of an input file (2 or 3); throws InputError.
int input_dimension(const std::string& path);

/// Reads an input file (".json" or ".toml", by its extension) into a solver (particles,
/// materials, BCs, loads) and the run controls. Does not call Solver::initialize(). Relative
/// paths (cards, particle CSVs) are relative to the input file's folder.
template <int D> RunConfig load_input(const std::string& path, Solver<D>& solver);
/// Same from JSON text; `source` names it in errors; `base_dir` resolves relative paths.
template <int D>
RunConfig load_input_text(const std::string& text, const std::string& source,
                          const std::string& base_dir, Solver<D>& solver);

/// Same from the input already read as JSON (from either syntax).
template <int D>
RunConfig load_input_json(const nlohmann::json& input, const std::string& source,
                          const std::string& base_dir, Solver<D>& solver);

extern template RunConfig load_input<2>(const std::string&, Solver<2>&);
extern template RunConfig load_input<3>(const std::string&, Solver<3>&);
extern template RunConfig load_input_text<2>(const std::string&, const std::string&,
                                             const std::string&, Solver<2>&);
extern template RunConfig load_input_text<3>(const std::string&, const std::string&,
                                             const std::string&, Solver<3>&);

extern template RunConfig load_input_json<2>(const nlohmann::json&, const std::string&,
                                             const std::string&, Solver<2>&);
extern template RunConfig load_input_json<3>(const nlohmann::json&, const std::string&,
                                             const std::string&, Solver<3>&);

} // namespace pnc::gimp
