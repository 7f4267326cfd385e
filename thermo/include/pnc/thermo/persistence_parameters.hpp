#pragma once
// pnc/thermo/persistence_parameters.hpp: the input file of `pnc thermo persistence --input
// FILE` (TOML or JSON), every key declared once on the parameter layer
// (pnc/core/parameters.hpp; decision D321, docs/thermo.md "Every key of the persistence
// input").
//
// The keys are the settings the command-line options give, named as the options
// (`--pull-distance` is `pull_distance`, `--angle-k` is `angle_k`), in the options' units:
// LAMMPS real (kcal/mol/rad^2, kcal/mol/A^2, A, fs, K), rates in A/fs. An option given on the
// command line overrides the file's key (override_persistence_input, D301).
#include "pnc/thermo/persistence.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pnc {
class Parameters;
}

namespace pnc::thermo {

/// The declarations bound to `s` (the defaults are its values now).
Parameters persistence_input_parameters(PersistenceSpec& s);
/// The declarations with the defaults of a PersistenceSpec{} (printing: `pnc thermo
/// persistence-parameters`).
Parameters persistence_input_parameters();

/// Reads a persistence input (a JSON object; TOML converted by parse_toml first): unknown keys
/// refused naming the allowed ones, every value checked against its declaration, then the
/// rules between keys (PersistenceSpec::validate: enough samples per pull for the blocks);
/// every refusal names `source`, the key, the value and the rule.
PersistenceSpec parse_persistence_input(const nlohmann::json& j, const std::string& source);
/// The file `path` (.toml or .json) read by parse_persistence_input.
PersistenceSpec read_persistence_input(const std::string& path);

/// `in` with each key of `keys` (declared names, e.g. "seed") taken from `given` (the
/// command-line options given explicitly): the command line overrides the file (D301). A name
/// that is not declared throws std::out_of_range (a programming error).
void override_persistence_input(PersistenceSpec& in, const PersistenceSpec& given,
                                const std::vector<std::string>& keys);

} // namespace pnc::thermo
