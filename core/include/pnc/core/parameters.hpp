#pragma once
// pnc/core/parameters.hpp: inputs declared once (decisions D230-D232).
//
// Each input key is declared once: its dotted name ("deform.hold_steps"), its type, its default,
// its range or allowed values, its unit and one line of text. Types: bool; integer in
// [min, max]; real in a range whose bounds are open or closed (RealRange); string, free or one
// of a list; list of integers or reals with an element range and a length rule; list of
// strings or of tables whose elements `check` reads). A key may be required. From the
// declarations, in the spirit of deal.II's ParameterHandler (declare_entry with a Pattern,
// parse_input, print_parameters):
//
//  - read() checks a JSON object against them (TOML is converted to JSON first: parse_toml in
//    params.hpp), refuses unknown keys naming the keys allowed at that level and the nearest
//    one, stores each given value into the variable the entry is bound to, and returns every
//    value, given or default;
//  - to_json(), to_toml() (a commented template with every default; read back it gives the
//    defaults) and to_markdown() (one table per section: key | type | default | range/allowed |
//    unit | meaning) print them.
//
// Every refusal is pnc::fail(source, field, value, rule), the rule derived from the declaration
// ("must be an integer in [1, 64]", "must be a number in (0, 50] fs", "must be \"npt\" (set
// pressure) or \"nvt\" (set density)"). Rules between keys (exclusive keys, one key bounding
// another) are not declarations: the reader's caller checks them after read().
//
// Units: every entry states its own unit as text ("fs", "K", "atm", "A", "g/cm^3",
// "kcal/mol"); "1" marks a dimensionless number, "" a boolean, a string or a count where no
// unit applies.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace pnc {

enum class ParamType {
  boolean,
  integer,
  real,
  string,
  integer_list,
  real_list,
  string_list, ///< an array of strings (each further checked by `check`, e.g. one command)
  table_list,  ///< an array of objects (TOML tables), each read by `check` (e.g. with its own
               ///< Parameters, read with a field prefix)
  custom       ///< a value of a form the types above cannot state ("all" or a list of axes, a
               ///< list of points): checked by `check` alone; printed as `type_text`, its rule
               ///< "must be " + `extra_rule`
};

/// A range of reals; either bound open or closed, or absent (infinite).
struct RealRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;

  static RealRange any() { return {}; }
  static RealRange closed(double lo, double hi) { return {lo, hi, false, false}; }     // [lo, hi]
  static RealRange open(double lo, double hi) { return {lo, hi, true, true}; }         // (lo, hi)
  static RealRange open_closed(double lo, double hi) { return {lo, hi, true, false}; } // (lo, hi]
  static RealRange closed_open(double lo, double hi) { return {lo, hi, false, true}; } // [lo, hi)
  static RealRange above(double lo) { return open_closed(lo, RealRange{}.hi); }        // > lo
  static RealRange at_least(double lo) { return closed(lo, RealRange{}.hi); }          // >= lo

  /// x is finite and inside.
  bool contains(double x) const;
  /// "(0, 3)", "[0.5, 1.5]", "> 0", ">= 0", "<= 5" or "" (any finite number).
  std::string text() const;
};

/// One allowed value of a string entry and what it means ("" = no comment).
struct Choice {
  std::string value, meaning;
};

/// An extra check of one key beyond its type and range (e.g. "odd"); throws via pnc::fail.
/// `field` is the dotted name, `source` the file.
using ParamCheck = std::function<void(const nlohmann::json& value, const std::string& source,
                                      const std::string& field)>;

struct Parameter {
  std::string path; ///< dotted name, e.g. "deform.hold_steps"
  ParamType type = ParamType::boolean;
  nlohmann::json default_value; ///< null: no default (the key is optional; `absent` says why)
  nlohmann::json unset_value;   ///< no default: the variable's value meaning "not given"
  std::string absent;           ///< what leaving the key out means when there is no default
  std::string unit;             ///< "fs", "K", "1" (dimensionless), "" (none applies)
  std::string text;             ///< one line: what the key is
  std::int64_t int_min = std::numeric_limits<std::int64_t>::min(); ///< integers, list elements
  std::int64_t int_max = std::numeric_limits<std::int64_t>::max();
  RealRange range;             ///< reals, list elements
  std::vector<Choice> choices; ///< strings: the allowed values (empty: any string)
  std::size_t min_size = 0;    ///< lists: length rule
  std::size_t max_size = std::numeric_limits<std::size_t>::max();
  std::string extra_rule;    ///< what `check` enforces, for the printed tables ("odd")
  std::string type_text;     ///< custom: the type as printed ("string or list of strings")
  std::string note;          ///< more text for the printed tables (e.g. a model-dependent default)
  bool omit_default = false; ///< values() leaves the entry out while it holds its default
  bool required = false;     ///< read() refuses an input without it (no default then)
  ParamCheck check;          ///< optional: runs after the type and range checks
  std::function<void(const nlohmann::json&)> store; ///< writes a checked value to its variable
  std::function<nlohmann::json()> load;             ///< the variable's value now

  /// No default: the key is optional and `absent_means` says what leaving it out does; the
  /// variable's value now is the one that means "not given" (values() then leaves it out).
  Parameter& no_default(std::string absent_means);
  /// values() leaves the entry out while its variable holds the default.
  Parameter& omit_when_default();
  /// The key must be given: read() refuses its absence ("is required: must be ...").
  Parameter& require();
  /// A further rule of this key alone, enforced by `c` and printed as `rule`.
  Parameter& also(std::string rule, ParamCheck c);
  /// A remark printed after the text (e.g. "models pnc, kg_platelet: [1, 2, 3, 4, 5, 6]").
  Parameter& remark(std::string r);

  /// The last component of the path.
  std::string key() const;
  /// "bool", "integer", "real", "string", "list of integers", "list of reals", "list of
  /// strings", "list of tables"; a custom entry's `type_text`.
  std::string type_name() const;
  /// The range or the allowed values as printed in tables: "[1, 64]", "(0, 50]", "\"npt\",
  /// \"nvt\"", "1 to 6 elements in [1, 6]"; "" when anything of the type goes.
  std::string range_text() const;
  /// The rule an out-of-range value breaks: "must be an integer in [1, 64]", "must be a number
  /// in (0, 50] fs", "must be \"npt\" (set pressure) or \"nvt\" (set density)".
  std::string rule() const;
  /// Checks `v` (type, range, length, the extra check); fail() naming source, the field (`field`,
  /// or the path when empty; elements of string and table lists as field[i]), value and rule.
  void validate(const nlohmann::json& v, const std::string& source,
                const std::string& field = "") const;
};

/// A JSON object (TOML table) of the input: its entries and subsections are declared after it.
struct ParamSection {
  std::string path;    ///< "" (the top level), "build", "deform", "a.b"
  std::string text;    ///< one line: what the section is
  std::string applies; ///< "" always; else when it applies ("models kg, kg_platelet")
  bool opaque = false; ///< read by other code: its keys are not declared here (read() copies it)
  /// optional_section: whether the input has the section is itself a value, bound to a bool
  std::function<void(bool)> store_given;
  std::function<bool()> load_given;
};

class Parameters {
public:
  /// `title` names the input in printed output ("pnc characterize recipe").
  explicit Parameters(std::string title);

  /// Opens a section at `path` (its parent must be declared before it; "" is the top level,
  /// always there). Entries declared next belong to it. Two sections may share a path only in
  /// a set printed for documentation (different `applies`); read() and to_toml() refuse that.
  Parameters& section(const std::string& path, std::string text, std::string applies = "");
  /// A section that other code reads (declared so that read() accepts it and the tables list
  /// it); read() checks only that it is an object and returns it unchanged.
  Parameters& opaque_section(const std::string& path, std::string text, std::string applies = "");
  /// A section whose presence is itself an input (e.g. a recipe's "slurm": settings kept only
  /// when given): read() sets `given` to whether the input has it (and returns it only then),
  /// values() writes it only while `given` is true, to_toml() writes it commented out. Its
  /// entries are declared next, as in any section.
  Parameters& optional_section(const std::string& path, bool& given, std::string text,
                               std::string applies = "");

  /// Entries of the open section, bound to `target`; the default is target's value now.
  Parameter& boolean(const std::string& key, bool& target, std::string text);
  template <class T>
  Parameter& integer(const std::string& key, T& target, std::int64_t min, std::int64_t max,
                     std::string unit, std::string text);
  Parameter& real(const std::string& key, double& target, RealRange range, std::string unit,
                  std::string text);
  Parameter& string(const std::string& key, std::string& target, std::vector<Choice> choices,
                    std::string text);
  template <class T>
  Parameter& integers(const std::string& key, std::vector<T>& target, std::int64_t min,
                      std::int64_t max, std::size_t min_size, std::size_t max_size,
                      std::string unit, std::string text);
  Parameter& reals(const std::string& key, std::vector<double>& target, RealRange range,
                   std::size_t min_size, std::size_t max_size, std::string unit, std::string text);
  Parameter& strings(const std::string& key, std::vector<std::string>& target, std::size_t min_size,
                     std::size_t max_size, std::string text);
  /// A custom entry (not bound to a variable): `type_text` as printed ("\"all\" or list of
  /// strings"), `rule` what it must be (printed; refusals say "must be " + rule), `check` the
  /// whole check (it should refuse with rule()). No default: `absent_means` says what leaving
  /// it out does.
  Parameter& custom(const std::string& key, std::string type_text, std::string rule,
                    std::string unit, std::string text, std::string absent_means, ParamCheck check);
  /// Any entry, declared field by field (its path is set from the open section and `p.path`).
  Parameter& add(Parameter p);

  /// Keeps `owner` alive as long as these declarations (the variables they are bound to).
  void hold(std::shared_ptr<const void> owner) { owners_.push_back(std::move(owner)); }

  /// Checks `in` (a JSON object) against the declarations: unknown keys at any level are
  /// refused (the rule lists the allowed keys and the nearest one), then every entry and
  /// section in declaration order. Stores each given value into its bound variable. Returns
  /// every value: given, else the default (entries without a default only when given).
  /// `field_prefix` is put before every field named in an error (an input read as one element
  /// of a larger one: "equilibrate.stages[2]").
  nlohmann::json read(const nlohmann::json& in, const std::string& source,
                      const std::string& field_prefix = "") const;
  /// The defaults as read() returns them for an empty object.
  nlohmann::json defaults() const;
  /// The bound variables' values now, every declared entry by its key (an entry without a
  /// default left out while it holds its "not given" value, an entry marked omit_when_default
  /// while it holds its default; opaque sections, and optional ones not given, left out): the
  /// expanded form of an input.
  nlohmann::json values() const;

  /// The declarations as JSON: {"title", "sections": [{"path", "text", "applies", "opaque",
  /// "optional",
  /// "parameters": [{"name", "type", "default", "unit", "text", "range", ...}]}]}.
  nlohmann::json to_json() const;
  /// A commented TOML template: every section as a table, every entry with its default (entries
  /// without one commented out). Parsed back and read, it gives defaults().
  std::string to_toml() const;
  /// One Markdown table per section (key | type | default | range/allowed | unit | meaning),
  /// each under a heading of `heading_level` '#' naming the section.
  std::string to_markdown(int heading_level = 4) const;

  const std::vector<Parameter>& parameters() const { return params_; }
  const std::vector<ParamSection>& sections() const { return sections_; }
  /// The entry with this dotted name (std::out_of_range if none).
  const Parameter& at(const std::string& path) const;

private:
  struct Member {
    bool is_section;
    std::size_t index;
  };
  std::string title_;
  std::vector<ParamSection> sections_;        // [0] is the top level
  std::vector<std::vector<Member>> members_;  // per section, in declaration order
  std::vector<std::size_t> section_of_param_; // per parameter
  std::vector<Parameter> params_;
  std::size_t open_ = 0;
  std::vector<std::shared_ptr<const void>> owners_;

  Parameters& open_section(const std::string& path, std::string text, std::string applies,
                           bool opaque);
  void check_unique_paths(const char* what) const;
  void read_object(std::size_t section, const nlohmann::json& in, const std::string& source,
                   const std::string& prefix, nlohmann::json& out) const;
  void write_values(std::size_t section, nlohmann::json& out) const;
};

/// The name among `names` nearest to `key`: within a third of its length in edit distance, or
/// beginning with `key` (or `key` with it; at least 3 characters); "" when none is close.
std::string nearest_name(const std::string& key, const std::vector<std::string>& names);

// ---- implementation of the templates ----

namespace detail {
std::int64_t param_integer(const nlohmann::json& v);
/// A declaration with its key, type, default, unit and text set; the rest left to the caller.
Parameter param_entry(const std::string& key, ParamType type, nlohmann::json default_value,
                      std::string unit, std::string text);
/// Refuses (std::logic_error: a programming error) a range that the integer type T cannot hold.
template <class T>
void check_integer_range(const std::string& key, std::int64_t min, std::int64_t max) {
  static_assert(std::is_integral_v<T> && !std::is_same_v<T, bool>, "an integer type");
  using L = std::numeric_limits<T>;
  if (min < static_cast<std::int64_t>(L::min()) ||
      (L::max() <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) &&
       max > static_cast<std::int64_t>(L::max())))
    throw std::logic_error("Parameters: the range of '" + key + "' does not fit its type");
}
} // namespace detail

template <class T>
Parameter& Parameters::integer(const std::string& key, T& target, std::int64_t min,
                               std::int64_t max, std::string unit, std::string text) {
  detail::check_integer_range<T>(key, min, max);
  Parameter p =
      detail::param_entry(key, ParamType::integer, target, std::move(unit), std::move(text));
  p.int_min = min;
  p.int_max = max;
  p.store = [&target](const nlohmann::json& v) {
    target = static_cast<T>(detail::param_integer(v));
  };
  p.load = [&target] { return nlohmann::json(target); };
  return add(std::move(p));
}

template <class T>
Parameter& Parameters::integers(const std::string& key, std::vector<T>& target, std::int64_t min,
                                std::int64_t max, std::size_t min_size, std::size_t max_size,
                                std::string unit, std::string text) {
  detail::check_integer_range<T>(key, min, max);
  Parameter p =
      detail::param_entry(key, ParamType::integer_list, target, std::move(unit), std::move(text));
  p.int_min = min;
  p.int_max = max;
  p.min_size = min_size;
  p.max_size = max_size;
  p.store = [&target](const nlohmann::json& v) {
    target.clear();
    for (const auto& e : v)
      target.push_back(static_cast<T>(detail::param_integer(e)));
  };
  p.load = [&target] { return nlohmann::json(target); };
  return add(std::move(p));
}

} // namespace pnc
