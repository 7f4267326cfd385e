#pragma once
// pnc/thermo/work_parameters.hpp: the input file of `pnc thermo work --input FILE` (TOML or
// JSON), its keys declared once on the parameter layer (pnc/core/parameters.hpp; decision
// D322, docs/thermo.md "Every key of the work input").
//
// One key: `from`, the `pnc characterize` output directories, as `--from` gives them (one, or
// two at different temperatures). In a file, a relative path is relative to the file's folder
// (read_work_input, D322); on the command line, to the current directory. An option given on
// the command line overrides the file's key (override_work_input, D301). No units apply.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pnc {
class Parameters;
}

namespace pnc::thermo {

/// What a work input file sets.
struct WorkInput {
  std::vector<std::string> from; ///< run directories: one, or two at T1 != T2 (empty: not given)
};

/// The declarations bound to `in`.
Parameters work_input_parameters(WorkInput& in);
/// The declarations of a WorkInput{} (printing: `pnc thermo work-parameters`).
Parameters work_input_parameters();

/// Reads a work input (a JSON object; TOML converted by parse_toml first): unknown keys refused
/// naming the allowed ones, `from` checked against its declaration; every refusal names
/// `source`, the key, the value and the rule. Paths are returned as written.
WorkInput parse_work_input(const nlohmann::json& j, const std::string& source);
/// The file `path` (.toml or .json) read by parse_work_input, each relative path of `from` then
/// taken from the file's folder (D322).
WorkInput read_work_input(const std::string& path);

/// `in` with each key of `keys` taken from `given` (the command-line options given explicitly,
/// D301). A name that is not declared throws std::out_of_range (a programming error).
void override_work_input(WorkInput& in, const WorkInput& given,
                         const std::vector<std::string>& keys);

} // namespace pnc::thermo
