// Inputs declared once (pnc/core/parameters.hpp): checks derived from the declarations, and
// the declarations printed as JSON, a TOML template and Markdown tables.
#include "pnc/core/parameters.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace pnc {

namespace {

using json = nlohmann::json;

std::string join_path(const std::string& a, const std::string& b) {
  return a.empty() ? b : b.empty() ? a : a + "." + b;
}

std::string number(double x) {
  return fmt::format("{}", x);
}

// A number as shown in an error: floats in their shortest form ("-1", "0.3"), integers exact.
std::string number_value(const json& v) {
  return v.is_number_float() ? number(v.get<double>()) : show_json(v);
}

std::string unit_suffix(const std::string& unit) {
  return unit.empty() || unit == "1" ? "" : " " + unit;
}

// "an array of", "a non-empty array of", "an array of 2 to 6", ... (then the element type)
std::string array_of(std::size_t lo, std::size_t hi) {
  constexpr auto none = std::numeric_limits<std::size_t>::max();
  if (hi == none)
    return lo == 0   ? "an array of"
           : lo == 1 ? "a non-empty array of"
                     : fmt::format("an array of at least {}", lo);
  if (lo == hi) return fmt::format("an array of exactly {}", lo);
  return fmt::format("an array of {} to {}", lo, hi);
}

// "must be a number in (0, 50] fs", "must be a number > 0", "must be a finite number"
std::string real_rule(const RealRange& range, const std::string& unit) {
  const std::string r = range.text();
  if (r.empty()) return "must be a finite number";
  return (r[0] == '(' || r[0] == '[' ? "must be a number in " : "must be a number ") + r +
         unit_suffix(unit);
}

std::string choices_text(const std::vector<Choice>& c, bool with_meaning) {
  std::string s;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (i > 0) s += i + 1 == c.size() ? " or " : ", ";
    s += json(c[i].value).dump();
    if (with_meaning && !c[i].meaning.empty()) s += " (" + c[i].meaning + ")";
  }
  return s;
}

std::string integer_range(std::int64_t lo, std::int64_t hi) {
  return fmt::format("[{}, {}]", lo, hi);
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

} // namespace

namespace detail {
Parameter param_entry(const std::string& key, ParamType type, json default_value, std::string unit,
                      std::string text) {
  Parameter p;
  p.path = key;
  p.type = type;
  p.default_value = std::move(default_value);
  p.unit = std::move(unit);
  p.text = std::move(text);
  return p;
}

std::int64_t param_integer(const json& v) {
  return v.is_number_unsigned() ? static_cast<std::int64_t>(v.get<std::uint64_t>())
                                : v.get<std::int64_t>();
}
} // namespace detail

// ---- RealRange ----

bool RealRange::contains(double x) const {
  return std::isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
}

std::string RealRange::text() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi)
    return std::string(lo_open ? "(" : "[") + number(lo) + ", " + number(hi) +
           (hi_open ? ")" : "]");
  if (has_lo) return (lo_open ? "> " : ">= ") + number(lo);
  if (has_hi) return (hi_open ? "< " : "<= ") + number(hi);
  return "";
}

// ---- Parameter ----

Parameter& Parameter::no_default(std::string absent_means) {
  unset_value = std::move(default_value);
  default_value = nullptr;
  absent = std::move(absent_means);
  return *this;
}

Parameter& Parameter::require() {
  required = true;
  default_value = nullptr;
  return *this;
}

Parameter& Parameter::omit_when_default() {
  omit_default = true;
  return *this;
}

Parameter& Parameter::also(std::string rule_text, ParamCheck c) {
  extra_rule = std::move(rule_text);
  check = std::move(c);
  return *this;
}

Parameter& Parameter::remark(std::string r) {
  note = std::move(r);
  return *this;
}

std::string Parameter::key() const {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

std::string Parameter::type_name() const {
  switch (type) {
  case ParamType::boolean:
    return "bool";
  case ParamType::integer:
    return "integer";
  case ParamType::real:
    return "real";
  case ParamType::string:
    return "string";
  case ParamType::integer_list:
    return "list of integers";
  case ParamType::real_list:
    return "list of reals";
  case ParamType::string_list:
    return "list of strings";
  case ParamType::table_list:
    return "list of tables";
  case ParamType::custom:
    return type_text;
  }
  return "";
}

std::string Parameter::range_text() const {
  std::string s;
  switch (type) {
  case ParamType::boolean:
  case ParamType::custom: // its rule is extra_rule, appended below
    break;
  case ParamType::integer:
    s = integer_range(int_min, int_max);
    break;
  case ParamType::real:
    s = range.text();
    break;
  case ParamType::string:
    s = choices_text(choices, true);
    break;
  case ParamType::integer_list:
  case ParamType::real_list:
  case ParamType::string_list:
  case ParamType::table_list: {
    const std::string each = type == ParamType::integer_list ? integer_range(int_min, int_max)
                             : type == ParamType::real_list  ? range.text()
                                                             : "";
    constexpr auto none = std::numeric_limits<std::size_t>::max();
    std::string len;
    if (max_size == none)
      len = min_size == 0
                ? ""
                : fmt::format("at least {} element{}", min_size, min_size == 1 ? "" : "s");
    else
      len = min_size == max_size ? fmt::format("exactly {} elements", min_size)
                                 : fmt::format("{} to {} elements", min_size, max_size);
    s = len;
    if (!each.empty()) s += (s.empty() ? "each " : ", each ") + each;
    break;
  }
  }
  if (!extra_rule.empty()) s += (s.empty() ? "" : "; ") + extra_rule;
  return s;
}

std::string Parameter::rule() const {
  switch (type) {
  case ParamType::boolean:
    return "must be true or false";
  case ParamType::integer:
    return "must be an integer in " + integer_range(int_min, int_max);
  case ParamType::real:
    return real_rule(range, unit);
  case ParamType::string:
    return choices.empty() ? "must be a string" : "must be " + choices_text(choices, true);
  case ParamType::integer_list:
    return "must be " + array_of(min_size, max_size) + " integers in " +
           integer_range(int_min, int_max);
  case ParamType::string_list:
    return "must be " + array_of(min_size, max_size) + " strings";
  case ParamType::table_list:
    return "must be " + array_of(min_size, max_size) + " tables (JSON objects)";
  case ParamType::custom:
    return "must be " + extra_rule;
  case ParamType::real_list: {
    const std::string r = range.text();
    return "must be " + array_of(min_size, max_size) + " finite numbers" +
           (r.empty() ? "" : (r[0] == '(' || r[0] == '[' ? " in " : " ") + r) + unit_suffix(unit);
  }
  }
  return "";
}

void Parameter::validate(const json& v, const std::string& source, const std::string& field) const {
  const std::string& f = field.empty() ? path : field;
  auto real_ok = [&](const json& x) {
    if (!x.is_number()) fail(source, f, show_json(x), "must be a number");
    const double d = x.get<double>();
    if (!std::isfinite(d)) fail(source, f, number_value(x), "must be a finite number");
    if (!range.contains(d)) fail(source, f, number_value(x), real_rule(range, unit));
  };
  switch (type) {
  case ParamType::boolean:
    if (!v.is_boolean()) fail(source, f, show_json(v), rule());
    break;
  case ParamType::integer:
    (void)get_integer(v, source, f, int_min, int_max);
    break;
  case ParamType::real:
    real_ok(v);
    break;
  case ParamType::string:
    if (!v.is_string()) fail(source, f, show_json(v), "must be a string");
    if (!choices.empty() && std::none_of(choices.begin(), choices.end(), [&](const Choice& c) {
          return c.value == v.get_ref<const std::string&>();
        }))
      fail(source, f, show_json(v), rule());
    break;
  case ParamType::integer_list:
  case ParamType::real_list:
    if (!v.is_array() || v.size() < min_size || v.size() > max_size)
      fail(source, f, show_json(v), rule());
    for (const auto& e : v) {
      if (type == ParamType::integer_list)
        (void)get_integer(e, source, f, int_min, int_max);
      else
        real_ok(e);
    }
    break;
  case ParamType::string_list:
  case ParamType::table_list:
    if (!v.is_array() || v.size() < min_size || v.size() > max_size)
      fail(source, f, show_json(v), rule());
    for (std::size_t i = 0; i < v.size(); ++i)
      if (type == ParamType::string_list ? !v[i].is_string() : !v[i].is_object())
        fail(source, f + "[" + std::to_string(i) + "]", show_json(v[i]),
             type == ParamType::string_list ? "must be a string" : "must be a JSON object");
    break;
  case ParamType::custom: // `check` is the whole check
    break;
  }
  if (check) check(v, source, f);
}

// ---- Parameters: declarations ----

Parameters::Parameters(std::string title) : title_(std::move(title)) {
  sections_.push_back({"", "", "", false});
  members_.emplace_back();
}

Parameters& Parameters::open_section(const std::string& path, std::string text, std::string applies,
                                     bool opaque) {
  if (path.empty()) throw std::logic_error("Parameters: a section needs a name");
  const auto dot = path.rfind('.');
  const std::string parent = dot == std::string::npos ? "" : path.substr(0, dot);
  std::size_t p = sections_.size();
  for (std::size_t i = sections_.size(); i-- > 0;)
    if (sections_[i].path == parent && !sections_[i].opaque) {
      p = i;
      break;
    }
  if (p == sections_.size())
    throw std::logic_error("Parameters: section '" + path + "' before its parent");
  sections_.push_back({path, std::move(text), std::move(applies), opaque});
  members_.emplace_back();
  members_[p].push_back({true, sections_.size() - 1});
  open_ = opaque ? p : sections_.size() - 1;
  return *this;
}

Parameters& Parameters::section(const std::string& path, std::string text, std::string applies) {
  return open_section(path, std::move(text), std::move(applies), false);
}

Parameters& Parameters::opaque_section(const std::string& path, std::string text,
                                       std::string applies) {
  return open_section(path, std::move(text), std::move(applies), true);
}

Parameters& Parameters::optional_section(const std::string& path, bool& given, std::string text,
                                         std::string applies) {
  open_section(path, std::move(text), std::move(applies), false);
  sections_.back().store_given = [&given](bool g) { given = g; };
  sections_.back().load_given = [&given] { return given; };
  return *this;
}

Parameter& Parameters::add(Parameter p) {
  p.path = join_path(sections_[open_].path, p.path);
  for (const auto& m : members_[open_])
    if (!m.is_section && params_[m.index].path == p.path)
      throw std::logic_error("Parameters: '" + p.path + "' declared twice");
  params_.push_back(std::move(p));
  section_of_param_.push_back(open_);
  members_[open_].push_back({false, params_.size() - 1});
  return params_.back();
}

Parameter& Parameters::boolean(const std::string& key, bool& target, std::string text) {
  Parameter p = detail::param_entry(key, ParamType::boolean, target, "", std::move(text));
  p.store = [&target](const json& v) { target = v.get<bool>(); };
  p.load = [&target] { return json(target); };
  return add(std::move(p));
}

Parameter& Parameters::real(const std::string& key, double& target, RealRange range,
                            std::string unit, std::string text) {
  Parameter p = detail::param_entry(key, ParamType::real, target, std::move(unit), std::move(text));
  p.range = range;
  p.store = [&target](const json& v) { target = v.get<double>(); };
  p.load = [&target] { return json(target); };
  return add(std::move(p));
}

Parameter& Parameters::string(const std::string& key, std::string& target,
                              std::vector<Choice> choices, std::string text) {
  Parameter p = detail::param_entry(key, ParamType::string, target, "", std::move(text));
  p.choices = std::move(choices);
  p.store = [&target](const json& v) { target = v.get<std::string>(); };
  p.load = [&target] { return json(target); };
  return add(std::move(p));
}

Parameter& Parameters::reals(const std::string& key, std::vector<double>& target, RealRange range,
                             std::size_t min_size, std::size_t max_size, std::string unit,
                             std::string text) {
  Parameter p =
      detail::param_entry(key, ParamType::real_list, target, std::move(unit), std::move(text));
  p.range = range;
  p.min_size = min_size;
  p.max_size = max_size;
  p.store = [&target](const json& v) { target = v.get<std::vector<double>>(); };
  p.load = [&target] { return json(target); };
  return add(std::move(p));
}

Parameter& Parameters::strings(const std::string& key, std::vector<std::string>& target,
                               std::size_t min_size, std::size_t max_size, std::string text) {
  Parameter p = detail::param_entry(key, ParamType::string_list, target, "", std::move(text));
  p.min_size = min_size;
  p.max_size = max_size;
  p.store = [&target](const json& v) { target = v.get<std::vector<std::string>>(); };
  p.load = [&target] { return json(target); };
  return add(std::move(p));
}

Parameter& Parameters::custom(const std::string& key, std::string type_text, std::string rule,
                              std::string unit, std::string text, std::string absent_means,
                              ParamCheck check) {
  Parameter p =
      detail::param_entry(key, ParamType::custom, nullptr, std::move(unit), std::move(text));
  p.type_text = std::move(type_text);
  p.extra_rule = std::move(rule);
  p.absent = std::move(absent_means);
  p.check = std::move(check);
  return add(std::move(p));
}

const Parameter& Parameters::at(const std::string& path) const {
  for (const auto& p : params_)
    if (p.path == path) return p;
  throw std::out_of_range("Parameters: no entry '" + path + "'");
}

void Parameters::check_unique_paths(const char* what) const {
  for (std::size_t i = 1; i < sections_.size(); ++i)
    for (std::size_t k = i + 1; k < sections_.size(); ++k)
      if (sections_[i].path == sections_[k].path)
        throw std::logic_error(std::string("Parameters::") + what + ": section '" +
                               sections_[i].path +
                               "' is declared twice (a set for documentation only)");
}

// ---- reading ----

std::string nearest_name(const std::string& key, const std::vector<std::string>& names) {
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  for (const auto& n : names) {
    const std::size_t d = edit_distance(key, n);
    if (d < best_d) best_d = d, best = n;
  }
  // close: at most a third of the longer name changed (and never the whole key), or one name
  // begins with the other ("temp" for "temperature")
  const std::size_t len = std::max(key.size(), best.size());
  if (best_d <= std::max<std::size_t>(1, len / 3) && best_d < key.size()) return best;
  if (key.size() >= 3)
    for (const auto& n : names)
      if (n.rfind(key, 0) == 0 || key.rfind(n, 0) == 0) return n;
  return "";
}

void Parameters::read_object(std::size_t s, const json& in, const std::string& source,
                             const std::string& prefix, json& out) const {
  const std::string path = join_path(prefix, sections_[s].path);
  if (!in.is_object()) fail(source, path, show_json(in), "must be a JSON object");
  std::vector<std::string> names;
  for (const auto& m : members_[s]) {
    const std::string full = m.is_section ? sections_[m.index].path : params_[m.index].path;
    const auto dot = full.rfind('.');
    names.push_back(dot == std::string::npos ? full : full.substr(dot + 1));
  }
  for (auto it = in.begin(); it != in.end(); ++it)
    if (std::find(names.begin(), names.end(), it.key()) == names.end()) {
      std::string allowed;
      for (const auto& n : names)
        allowed += (allowed.empty() ? "" : ", ") + n;
      const std::string near = nearest_name(it.key(), names);
      fail(source, join_path(path, clip(it.key())), show_json(it.value()),
           "unknown key; allowed: " + (allowed.empty() ? std::string("none") : allowed) +
               (near.empty() ? "" : " (did you mean \"" + near + "\"?)"));
    }
  for (std::size_t i = 0; i < names.size(); ++i) {
    const Member& m = members_[s][i];
    const std::string& key = names[i];
    const bool given = in.contains(key);
    if (m.is_section) {
      const ParamSection& sub = sections_[m.index];
      if (sub.opaque) {
        if (!given) continue;
        if (!in.at(key).is_object())
          fail(source, join_path(prefix, sub.path), show_json(in.at(key)), "must be a JSON object");
        out[key] = in.at(key);
        continue;
      }
      if (sub.store_given) {
        sub.store_given(given);
        if (!given) continue;
      }
      json& o = out[key] = json::object();
      static const json empty = json::object();
      read_object(m.index, given ? in.at(key) : empty, source, prefix, o);
      continue;
    }
    const Parameter& p = params_[m.index];
    if (given) {
      const json& v = in.at(key);
      p.validate(v, source, join_path(prefix, p.path));
      if (p.store) p.store(v);
      out[key] = v;
    } else if (p.required) {
      fail(source, join_path(prefix, p.path), "<missing>", "is required: " + p.rule());
    } else if (!p.default_value.is_null()) {
      out[key] = p.default_value;
    }
  }
}

json Parameters::read(const json& in, const std::string& source,
                      const std::string& field_prefix) const {
  check_unique_paths("read");
  json out = json::object();
  read_object(0, in, source.empty() ? std::string("<input>") : source, field_prefix, out);
  return out;
}

json Parameters::defaults() const {
  check_unique_paths("defaults");
  json out = json::object();
  read_object(0, json::object(), "<defaults>", "", out);
  return out;
}

void Parameters::write_values(std::size_t s, json& out) const {
  for (const auto& m : members_[s]) {
    if (m.is_section) {
      const ParamSection& sub = sections_[m.index];
      if (sub.opaque || (sub.load_given && !sub.load_given())) continue;
      const auto dot = sub.path.rfind('.');
      json& o = out[dot == std::string::npos ? sub.path : sub.path.substr(dot + 1)] =
          json::object();
      write_values(m.index, o);
      continue;
    }
    const Parameter& p = params_[m.index];
    if (!p.load) continue;
    json v = p.load();
    if (p.default_value.is_null() ? v == p.unset_value : p.omit_default && v == p.default_value)
      continue;
    out[p.key()] = std::move(v);
  }
}

json Parameters::values() const {
  check_unique_paths("values");
  json out = json::object();
  write_values(0, out);
  return out;
}

} // namespace pnc
