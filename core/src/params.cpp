#include "pnc/core/params.hpp"

#include "pnc/core/error.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace pnc {

namespace {

using json = nlohmann::json;

std::string scalar_text(const json& v) {
  return v.dump(-1, ' ', false, json::error_handler_t::replace);
}

// Appends v to out until out holds more than max characters; one level per character
// written before descending, so the recursion is at most max + 1 deep.
void append_json(const json& v, std::size_t max, std::string& out) {
  if (out.size() > max) return;
  if (v.is_array() || v.is_object()) {
    const bool obj = v.is_object();
    out += obj ? '{' : '[';
    bool first = true;
    for (auto it = v.begin(); it != v.end() && out.size() <= max; ++it) {
      if (!first) out += ',';
      first = false;
      if (obj) out += scalar_text(json(clip(it.key(), max))) + ':';
      append_json(it.value(), max, out);
    }
    out += obj ? '}' : ']';
  } else if (v.is_string()) {
    out += scalar_text(json(clip(v.get_ref<const std::string&>(), max)));
  } else {
    out += scalar_text(v);
  }
}

std::string g17(double x) {
  char b[32];
  if (x == std::floor(x) && std::fabs(x) < 1e15) { // integral bounds without an exponent
    std::snprintf(b, sizeof b, "%.0f", x);
    return b;
  }
  std::snprintf(b, sizeof b, "%.17g", x);
  // shortest form that reads back to the same double
  for (int p = 1; p <= 17; ++p) {
    char c[32];
    std::snprintf(c, sizeof c, "%.*g", p, x);
    if (std::strtod(c, nullptr) == x) return c;
  }
  return b;
}

} // namespace

std::string clip(std::string_view s, std::size_t max) {
  if (s.size() <= max) return std::string(s);
  std::size_t n = max;
  // back up to the first byte of a UTF-8 sequence
  while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80)
    --n;
  return std::string(s.substr(0, n)) + "\xE2\x80\xA6"; // U+2026 HORIZONTAL ELLIPSIS
}

std::string show_json(const json& v, std::size_t max) {
  std::string out;
  append_json(v, max, out);
  return clip(out, max);
}

void check_nesting(std::string_view t, const std::string& source, Syntax syntax, int max_depth) {
  const bool toml = syntax == Syntax::toml;
  std::string open; // the open brackets, innermost last
  int line = 1, key_dots = 0;
  bool in_key = toml; // TOML: reading a key (dots separate nested tables)
  auto too_deep = [&](int depth) {
    if (depth > max_depth)
      fail(source, "", "line " + std::to_string(line),
           "arrays and objects (tables) nest deeper than " + std::to_string(max_depth) +
               " levels; at most " + std::to_string(max_depth) + " are allowed");
  };
  const std::size_t n = t.size();
  for (std::size_t i = 0; i < n; ++i) {
    const char c = t[i];
    if (c == '\n') {
      ++line;
      if (toml && (open.empty() || open.back() == '{')) {
        in_key = true;
        key_dots = 0;
      }
    } else if (c == '"' || (toml && c == '\'')) {
      const bool triple = toml && i + 2 < n && t[i + 1] == c && t[i + 2] == c;
      const bool escapes = c == '"';
      i += triple ? 3 : 1;
      for (; i < n; ++i) {
        if (t[i] == '\n') ++line;
        if (escapes && t[i] == '\\') {
          ++i;
          if (i < n && t[i] == '\n') ++line;
          continue;
        }
        if (t[i] == c && (!triple || (i + 2 < n && t[i + 1] == c && t[i + 2] == c))) {
          if (triple) i += 2;
          break;
        }
        if (!triple && toml && t[i] == '\n') break; // unterminated: the parser will say so
      }
    } else if (toml && c == '#') {
      while (i + 1 < n && t[i + 1] != '\n')
        ++i;
    } else if (c == '[' || c == '{') {
      open += c;
      too_deep(static_cast<int>(open.size()) + key_dots);
      if (c == '{') {
        in_key = toml;
        key_dots = 0;
      }
    } else if (c == ']' || c == '}') {
      if (!open.empty()) open.pop_back();
    } else if (toml && c == '=') {
      in_key = false;
    } else if (toml && c == ',' && !open.empty() && open.back() == '{') {
      in_key = true;
      key_dots = 0;
    } else if (toml && c == '.' && in_key) {
      ++key_dots;
      too_deep(static_cast<int>(open.size()) + key_dots + 1);
    }
  }
}

json parse_json(std::string_view text, const std::string& source) {
  check_nesting(text, source, Syntax::json);
  try {
    return json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {
    fail(source, "", "", "not valid JSON: " + clip(e.what(), 200));
  }
}

std::string read_text_file(const std::string& path, const std::string& what) {
  std::ifstream f(path, std::ios::binary);
  if (!f) fail(path, "", "", "cannot open " + what);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string range_text(double min, double max) {
  return "[" + g17(min) + ", " + g17(max) + "]";
}

std::int64_t get_integer(const json& v, const std::string& source, const std::string& key,
                         std::int64_t min, std::int64_t max) {
  const std::string rule =
      "must be an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (v.is_number_unsigned()) {
    const std::uint64_t u = v.get<std::uint64_t>();
    if (max < 0 || u > static_cast<std::uint64_t>(max)) fail(source, key, show_json(v), rule);
    const auto x = static_cast<std::int64_t>(u);
    if (x < min) fail(source, key, show_json(v), rule);
    return x;
  }
  if (!v.is_number_integer()) fail(source, key, show_json(v), rule);
  const std::int64_t x = v.get<std::int64_t>();
  if (x < min || x > max) fail(source, key, show_json(v), rule);
  return x;
}

double get_number(const json& v, const std::string& source, const std::string& key, double min,
                  double max) {
  const std::string rule = "must be a finite number in " + range_text(min, max);
  if (!v.is_number()) fail(source, key, show_json(v), rule);
  const double x = v.get<double>();
  if (!std::isfinite(x) || x < min || x > max) fail(source, key, show_json(v), rule);
  return x;
}

} // namespace pnc
