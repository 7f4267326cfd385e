#pragma once
// Pieces the input files of `pnc thermo persistence` and `pnc thermo work` share (private to
// thermo/; decisions D301, D321, D322): reading a .toml or .json file as JSON, and the
// command line overriding the file key by key.
#include "pnc/core/parameters.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pnc::thermo::detail {

/// The file `path` as JSON: TOML (".toml", through parse_toml) or JSON (".json"); any other
/// extension refused naming the path, the option --input and "`what` ends in .json or .toml".
nlohmann::json read_input_json(const std::string& path, const std::string& what);

/// `in` with each key of `keys` (declared dotted names) taken from `given`: the keys whose
/// option the command line gave (D301). `declare(x)` returns the declarations bound to x. A
/// name that is not declared throws std::out_of_range (a programming error).
template <class In, class Declare>
void override_keys(In& in, const In& given, const std::vector<std::string>& keys, Declare declare) {
  In g = given; // the declarations bind non-const variables
  const Parameters to = declare(in);
  const Parameters from = declare(g);
  for (const auto& k : keys)
    to.at(k).store(from.at(k).load());
}

} // namespace pnc::thermo::detail
