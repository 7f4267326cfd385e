#pragma once
// Helpers that declare one key of the `pnc gimp run` input on the parameter layer
// (pnc/core/parameters.hpp): used by input_parameters.cpp (the sections and tables) and by
// material_kinds.cpp (the keys of each material law). Private to the solver library.
#include "pnc/core/parameters.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pnc::gimp::declare {

/// A real key with its default (null: none), range and SI unit.
inline Parameter& real(Parameters& p, const std::string& key, nlohmann::json def, RealRange r,
                       std::string unit, std::string text) {
  Parameter e =
      detail::param_entry(key, ParamType::real, std::move(def), std::move(unit), std::move(text));
  e.range = r;
  return p.add(std::move(e));
}

/// An integer key in [lo, hi].
inline Parameter& integer(Parameters& p, const std::string& key, std::int64_t def, std::int64_t lo,
                          std::int64_t hi, std::string text) {
  Parameter e = detail::param_entry(key, ParamType::integer, def, "", std::move(text));
  e.int_min = lo;
  e.int_max = hi;
  return p.add(std::move(e));
}

/// A string key; `choices` empty: any string.
inline Parameter& string(Parameters& p, const std::string& key, nlohmann::json def,
                         std::vector<Choice> choices, std::string text) {
  Parameter e = detail::param_entry(key, ParamType::string, std::move(def), "", std::move(text));
  e.choices = std::move(choices);
  return p.add(std::move(e));
}

} // namespace pnc::gimp::declare
