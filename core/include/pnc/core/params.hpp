#pragma once
// pnc/core/params.hpp: checked reading of input files and values (JSON; TOML is converted to
// JSON by parse_toml, so one set of checks serves both). Inputs declared key by key:
// parameters.hpp.
//
//  - Nesting is capped (kMaxNesting levels of arrays / objects / tables) before a parser runs:
//    deep input would otherwise exhaust the stack in a recursive parser or printer.
//  - Values shown in messages are capped (show_json, clip): an error never prints an
//    unbounded value.
//  - Integers are read with a stated range, refusing non-integers, out-of-range values and
//    values too large for 64 bits; nothing is narrowed silently.
// Every refusal is a pnc::InputError naming the file, the key, the value and the rule.
#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

namespace pnc {

/// Deepest nesting of arrays, objects (JSON) and arrays, tables, dotted keys (TOML) accepted.
constexpr int kMaxNesting = 64;
/// Longest value shown in an error message (characters, before the ellipsis).
constexpr std::size_t kShownValueChars = 80;

/// s cut to at most `max` bytes on a UTF-8 character boundary, with "…" appended when cut.
std::string clip(std::string_view s, std::size_t max = kShownValueChars);

/// A JSON value as compact text for an error message, at most about `max` characters, with
/// "…" when cut. Visits no deeper than `max` levels (safe on any value).
std::string show_json(const nlohmann::json& v, std::size_t max = kShownValueChars);

enum class Syntax { json, toml };

/// Refuses text whose nesting exceeds `max_depth`, naming `source`, the line and the rule.
/// Brackets inside strings (and TOML comments) do not count.
void check_nesting(std::string_view text, const std::string& source, Syntax syntax,
                   int max_depth = kMaxNesting);

/// Parses JSON text: nesting checked first; every parser failure (syntax, a number that does
/// not fit a double such as 1e400) becomes an InputError naming `source`.
nlohmann::json parse_json(std::string_view text, const std::string& source);

/// Parses TOML text into JSON (tables become objects): the text must be UTF-8 and nest at most
/// kMaxNesting levels (both checked before the parser runs); dates and times are refused naming
/// their key; every parser failure becomes an InputError naming `source` ("not valid TOML").
nlohmann::json parse_toml(std::string_view text, const std::string& source);

/// A JSON object printed as TOML: the keys of each table, then its subtables as [a.b] tables,
/// then its arrays of objects as [[a.b]] arrays of tables (D357); parse_toml reads it back to
/// the same JSON (keys quoted where TOML needs it).
std::string to_toml(const nlohmann::json& object);
/// The TOML spelling of a JSON scalar, array or object (an inline table; floats always with a
/// point or an exponent, so that they read back as floats); std::logic_error for null.
std::string toml_value(const nlohmann::json& v);

/// Reads a whole file as text; InputError "cannot open ..." naming the path.
std::string read_text_file(const std::string& path, const std::string& what = "the input file");

/// An input file as JSON, the syntax chosen by its extension (D357): ".toml" through
/// parse_toml, ".json" through parse_json, so one set of checks serves both; any other
/// extension is refused naming `path`, `key` (the option or field that named the file, may be
/// empty), the extension and the rule "`what` ends in .json or .toml".
nlohmann::json read_input_file(const std::string& path, const std::string& what,
                               const std::string& key = "");

/// An integer in [min, max] from a JSON value. Refuses non-numbers, non-integers (2.5, 3.0,
/// 1e3), values outside the range and values beyond 64 bits, with the message
/// "source: field 'key': value 'v': must be an integer in [min, max]".
std::int64_t get_integer(const nlohmann::json& v, const std::string& source, const std::string& key,
                         std::int64_t min, std::int64_t max);

/// get_integer() converted to T; the range must fit T (checked at compile time when constant).
template <class T>
T get_integer_as(const nlohmann::json& v, const std::string& source, const std::string& key,
                 std::int64_t min, std::int64_t max) {
  static_assert(std::is_integral_v<T> && !std::is_same_v<T, bool>, "an integer type");
  using L = std::numeric_limits<T>;
  if (min < static_cast<std::int64_t>(L::min()) ||
      (L::max() <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) &&
       max > static_cast<std::int64_t>(L::max())))
    throw std::logic_error("get_integer_as: the range of '" + key + "' does not fit the type");
  return static_cast<T>(get_integer(v, source, key, min, max));
}

/// A finite number in [min, max] from a JSON value (integers accepted), naming the range.
double get_number(const nlohmann::json& v, const std::string& source, const std::string& key,
                  double min, double max);

/// "[min, max]" as printed in range messages (shortest round-trip form of each bound).
std::string range_text(double min, double max);

} // namespace pnc
