// TOML <-> JSON (pnc/core/params.hpp): TOML inputs are converted to JSON so that one set of
// checks (pnc/core/parameters.hpp) serves both formats; an input file is read by its extension
// (read_input_file, D357); JSON objects are printed as TOML.
#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <toml.hpp>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace pnc {

namespace {

using json = nlohmann::json;

// Dates and times have no meaning in a pnc input and are refused with the key that holds them.
json toml_to_json(const toml::value& v, const std::string& path, const std::string& source) {
  switch (v.type()) {
  case toml::value_t::boolean:
    return v.as_boolean();
  case toml::value_t::integer:
    return static_cast<std::int64_t>(v.as_integer());
  case toml::value_t::floating:
    return v.as_floating();
  case toml::value_t::string:
    return v.as_string().str;
  case toml::value_t::array: {
    json a = json::array();
    std::size_t i = 0;
    for (const auto& e : v.as_array())
      a.push_back(toml_to_json(e, fmt::format("{}[{}]", path, i++), source));
    return a;
  }
  case toml::value_t::table: {
    json o = json::object();
    for (const auto& [k, e] : v.as_table())
      o[k] = toml_to_json(e, path.empty() ? k : path + "." + k, source);
    return o;
  }
  default:
    fail(source, path, clip(toml::format(v)), "dates and times are not pnc input values");
  }
}

// Offset of the first byte that is not valid UTF-8 (RFC 3629: no overlong forms, no
// surrogates, at most U+10FFFF), or npos. TOML files are UTF-8; toml11 3.7's own error path
// for invalid UTF-8 inside a literal string reads out of bounds (found by fuzz_recipe_toml),
// so the text is checked before toml11 sees it.
std::size_t invalid_utf8_at(std::string_view s) {
  const auto* b = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned c = b[i];
    std::size_t len = 0;
    unsigned lo = 0x80, hi = 0xbf; // allowed range of the second byte
    if (c < 0x80)
      len = 1;
    else if (c >= 0xc2 && c <= 0xdf)
      len = 2;
    else if (c == 0xe0)
      len = 3, lo = 0xa0;
    else if ((c >= 0xe1 && c <= 0xec) || c == 0xee || c == 0xef)
      len = 3;
    else if (c == 0xed)
      len = 3, hi = 0x9f;
    else if (c == 0xf0)
      len = 4, lo = 0x90;
    else if (c >= 0xf1 && c <= 0xf3)
      len = 4;
    else if (c == 0xf4)
      len = 4, hi = 0x8f;
    else
      return i;
    if (i + len > n) return i;
    for (std::size_t k = 1; k < len; ++k) {
      const unsigned d = b[i + k];
      if (k == 1 ? (d < lo || d > hi) : (d < 0x80 || d > 0xbf)) return i;
    }
    i += len;
  }
  return std::string::npos;
}

/// A key as TOML writes it: bare when it is letters, digits, '_' and '-', else quoted.
std::string toml_key(const std::string& k) {
  const bool bare = !k.empty() && std::all_of(k.begin(), k.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  return bare ? k : json(k).dump();
}

/// A non-empty array of objects: written as an array of tables ([[name]]).
bool is_table_array(const json& v) {
  return v.is_array() && !v.empty() &&
         std::all_of(v.begin(), v.end(), [](const json& e) { return e.is_object(); });
}

/// The table `t` under the header `head` ("" at the top, "[a.b]" or "[[a.b]]"): its values,
/// then its subtables, then its arrays of tables (D357: the GIMP input's materials, bodies, ...).
void write_toml_table(const json& t, const std::string& name, const std::string& head,
                      std::string& out) {
  if (!head.empty()) out += "\n" + head + "\n";
  const auto sub = [&](const std::string& k) { return name.empty() ? k : name + "." + k; };
  for (const auto& [k, v] : t.items())
    if (!v.is_object() && !is_table_array(v)) out += toml_key(k) + " = " + toml_value(v) + "\n";
  for (const auto& [k, v] : t.items())
    if (v.is_object()) write_toml_table(v, sub(toml_key(k)), "[" + sub(toml_key(k)) + "]", out);
  for (const auto& [k, v] : t.items())
    if (is_table_array(v))
      for (const auto& e : v)
        write_toml_table(e, sub(toml_key(k)), "[[" + sub(toml_key(k)) + "]]", out);
}

} // namespace

json parse_toml(std::string_view text, const std::string& source) {
  if (const auto at = invalid_utf8_at(text); at != std::string::npos)
    fail(source, "",
         fmt::format("byte 0x{:02x} at offset {}", static_cast<unsigned char>(text[at]), at),
         "not valid TOML: a TOML file must be UTF-8");
  check_nesting(text, source, Syntax::toml); // toml11 parses nested values recursively
  toml::value t;
  try {
    std::istringstream in{std::string(text)};
    t = toml::parse(in, source);
  } catch (const std::exception& e) {
    fail(source, "", "", "not valid TOML: " + clip(e.what(), 400));
  }
  return toml_to_json(t, "", source);
}

// Floats in their shortest exact form (fmt), always with a decimal point or exponent so that
// they read back as floats.
std::string toml_value(const json& j) {
  if (j.is_number_float()) {
    std::string f = fmt::format("{}", j.get<double>());
    if (f.find_first_of(".eEn") == std::string::npos) f += ".0";
    return f;
  }
  if (j.is_array()) {
    std::string a = "[";
    for (std::size_t i = 0; i < j.size(); ++i)
      a += (i ? ", " : "") + toml_value(j[i]);
    return a + "]";
  }
  if (j.is_object()) { // an inline table (objects inside arrays that also hold non-objects)
    std::string t = "{";
    for (const auto& [k, v] : j.items())
      t += (t.size() > 1 ? ", " : "") + toml_key(k) + " = " + toml_value(v);
    return t + "}";
  }
  if (j.is_null()) throw std::logic_error("toml_value: null is not a TOML value");
  return j.dump(); // booleans, integers, strings: JSON's spelling is TOML's
}

json read_input_file(const std::string& path, const std::string& what, const std::string& key) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext != ".json" && ext != ".toml") fail(path, key, ext, what + " ends in .json or .toml");
  const std::string text = read_text_file(path, what);
  return ext == ".toml" ? parse_toml(text, path) : parse_json(text, path);
}

std::string to_toml(const json& object) {
  std::string out;
  write_toml_table(object, "", "", out);
  return out;
}

} // namespace pnc
