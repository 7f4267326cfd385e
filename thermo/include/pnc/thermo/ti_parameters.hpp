#pragma once
// pnc/thermo/ti_parameters.hpp: the input file of `pnc thermo ti --input FILE` (TOML or JSON),
// every key declared once on the parameter layer (pnc/core/parameters.hpp; decisions D301-D303,
// docs/thermo.md "Every key of the TI input").
//
// The top-level keys are the TI settings the command-line options give, named as the options
// (`--equil-steps` is `equil_steps`), in the options' units: LAMMPS real (kcal/mol, A, fs, K);
// strains dimensionless. The optional section "slurm" is the one of a `pnc characterize` recipe
// without the rank keys (campaign::declare_slurm_section; its `mpi` key too, D332); the ranks per
// (state, lambda) unit are the top-level key `ranks` (D324).
// An option given on the command line overrides the file's key (override_ti_input, D301).
#include "pnc/campaign/slurm_parameters.hpp"
#include "pnc/thermo/ti.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pnc {
class Parameters;
}

namespace pnc::thermo {

/// What a TI input file sets: the TI spec (points, states, LJ path, sampling, seed, jobs), the
/// executor and the Slurm settings.
struct TiInput {
  TiSpec spec;
  std::string executor = "local"; ///< "local" or "slurm"
  campaign::SlurmSpec slurm;      ///< the "slurm" section (slurm.given: the file has it)
  /// The top-level keys the file gives (parse_ti_input; none for TiInput{}): e.g. whether its
  /// `ranks` and `jobs` were set rather than defaulted (D333).
  std::vector<std::string> file_keys;
};

/// The declarations bound to `in` (the defaults are its values now).
Parameters ti_input_parameters(TiInput& in);
/// The declarations with the defaults of a TiInput{} (printing: `pnc thermo ti-parameters`).
Parameters ti_input_parameters();

/// Reads a TI input (a JSON object; TOML converted by parse_toml first): unknown keys refused
/// naming the allowed ones, every value checked against its declaration, then the rules
/// between keys (TiSpec::validate: a state at least, the quadrature rule's points, cutoff >=
/// sigma); every refusal names `source`, the key, the value and the rule.
TiInput parse_ti_input(const nlohmann::json& j, const std::string& source);
/// The file `path` (.toml or .json) read by parse_ti_input.
TiInput read_ti_input(const std::string& path);

/// `in` with each key of `keys` (dotted declared names, e.g. "seed", "slurm.time") taken from
/// `given` (the command-line options given explicitly): the command line overrides the file
/// (D301). A name that is not declared throws std::out_of_range (a programming error).
void override_ti_input(TiInput& in, const TiInput& given, const std::vector<std::string>& keys);

/// The command-line option of a declared key: "--" + the key with '_' as '-' ("equil_steps"
/// -> "--equil-steps", "dhdl" -> "--dhdl"); the slurm section's as their options
/// ("slurm.time" -> "--time", "slurm.template" -> "--sbatch-template").
std::string ti_option_of(const std::string& key);

} // namespace pnc::thermo
