// The bridge between the parameter layer and CLI11 (cli_parameters.hpp, D320).
#include "cli_parameters.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

namespace pnc::app {

using nlohmann::json;

std::string option_of_key(const std::string& key) {
  std::string o = "--" + key;
  for (char& c : o)
    if (c == '_') c = '-';
  return o;
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  if (text == "none" || text.empty()) return items;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    items.push_back(item);
  if (text.back() == ',') items.emplace_back(); // "1," has an empty second item
  return items;
}

namespace {

bool is_list(ParamType t) {
  return t == ParamType::integer_list || t == ParamType::real_list || t == ParamType::string_list ||
         t == ParamType::table_list;
}

/// One item as an entry of type `t` (a scalar type, or a list's element type) reads it.
json item_value(ParamType t, const std::string& text) {
  if (t == ParamType::string || t == ParamType::string_list || t == ParamType::custom)
    return json(text);
  try {
    const json v = json::parse(text);
    if (v.is_number() || (t == ParamType::boolean && v.is_boolean())) return v;
  } catch (const json::exception&) {
    // not JSON: strtod below ("nan", "inf", "+5", ".5")
  }
  if (t != ParamType::boolean && !text.empty()) {
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (end != nullptr && *end == '\0') return json(x);
  }
  return json(text);
}

/// The rule without its "must be " (the words after the option's text in --help).
std::string what_it_must_be(const Parameter& p) {
  const std::string r = p.rule();
  const std::string head = "must be ";
  return r.rfind(head, 0) == 0 ? r.substr(head.size()) : r;
}

std::string json_text(const json& v) {
  return v.is_string() ? v.get<std::string>() : v.dump();
}

} // namespace

json option_value(const Parameter& p, const std::string& text, bool one_element) {
  if (!is_list(p.type)) return item_value(p.type, text);
  json a = json::array();
  if (one_element) {
    a.push_back(item_value(p.type, text));
    return a;
  }
  for (const auto& item : split_list(text))
    a.push_back(item_value(p.type, item));
  return a;
}

std::string declared_help(const Parameter& p, bool one_element) {
  std::string h = p.text + ": " + what_it_must_be(p);
  if (!p.note.empty()) h += "; " + p.note;
  if (is_list(p.type))
    h += one_element ? " (give the option once per element)" : " (comma-separated, or none)";
  return h;
}

std::string declared_default(const Parameter& p) {
  const json& d = p.default_value;
  if (d.is_null()) return "";
  if (!d.is_array()) return json_text(d);
  if (d.empty()) return "none";
  std::string s;
  for (const auto& e : d)
    s += (s.empty() ? "" : ",") + json_text(e);
  return s;
}

CLI::Validator declared_check(const Parameter& p, bool one_element) {
  // a copy without the bound variables, which may not outlive the declarations
  auto decl = std::make_shared<Parameter>(p);
  decl->store = nullptr;
  decl->load = nullptr;
  if (one_element) { // one element at a time: the length is checked once all are given
    decl->min_size = 0;
    decl->max_size = std::numeric_limits<std::size_t>::max();
  }
  return CLI::Validator(
      [decl, one_element](std::string& in) -> std::string {
        try {
          decl->validate(option_value(*decl, in, one_element), "<command line>");
        } catch (const InputError& e) {
          // a scalar as typed; of a list the element refused, a string one without its quotes
          std::string v = is_list(decl->type) ? e.context().value : in;
          if (v.size() >= 2 && v.front() == '"' && v.back() == '"') v = v.substr(1, v.size() - 2);
          return "value '" + v + "': " + e.context().rule;
        }
        return std::string();
      },
      "", "DECLARED");
}

std::vector<DeclaredOption>
bind_declared_options(CLI::App* cmd, const Parameters& declared,
                      const std::function<std::string(const std::string&)>& option_of) {
  std::vector<DeclaredOption> out;
  for (const auto& p : declared.parameters())
    out.push_back(
        bind_declared_option(cmd->get_option(option_of(p.path)), p)); // throws when missing
  return out;
}

DeclaredOption bind_declared_option(CLI::Option* o, const Parameter& p) {
  const bool one_element = o->get_expected_max() > 1;
  if (p.type != ParamType::boolean) o->check(declared_check(p, one_element));
  if (o->get_description().empty()) {
    o->description(declared_help(p, one_element));
    o->default_str(declared_default(p));
  }
  return {p.path, o};
}

std::vector<std::string> given_keys(const std::vector<DeclaredOption>& options) {
  std::vector<std::string> keys;
  for (const auto& d : options)
    if (d.option->count() > 0) keys.push_back(d.key);
  return keys;
}

ParametersPrintout declared_printout(std::function<Parameters()> declare) {
  return [declare = std::move(declare)](const std::string& format) {
    const Parameters p = declare();
    if (format == "toml") return p.to_toml();
    if (format == "json") return p.to_json().dump(2) + "\n";
    return p.to_markdown(4);
  };
}

void add_print_parameters_option(CLI::App* cmd, ParametersPrintout printout,
                                 const std::string& what) {
  cmd->add_option_function<std::string>(
         "--print-parameters",
         [printout](const std::string& format) {
           std::cout << printout(format) << std::flush;
           throw CLI::Success(); // D358: like --help, before the required arguments
         },
         "Print every key of " + what +
             " and exit: markdown (tables, the default), json, or toml (a commented template "
             "with the defaults); the same as the `parameters` subcommand")
      ->expected(0, 1)
      ->default_str("markdown")
      ->check(CLI::IsMember({"markdown", "json", "toml"}));
}

void add_parameters_command(CLI::App* parent, const std::string& name, const std::string& what,
                            const std::string& toml_note, std::function<Parameters()> declare,
                            Action& action) {
  add_parameters_command(parent, name, what, toml_note, declared_printout(std::move(declare)),
                         action);
}

CLI::App* add_parameters_command(CLI::App* parent, const std::string& name, const std::string& what,
                                 const std::string& toml_note, ParametersPrintout printout,
                                 Action& action) {
  auto format = std::make_shared<std::string>("markdown");
  auto* c = parent->add_subcommand(name, "Print every key " + what +
                                             ": type, default, range, unit, meaning");
  c->add_option("--format", *format,
                "markdown (tables, default), json or toml (a commented template with the "
                "defaults; " +
                    toml_note + ")")
      ->check(CLI::IsMember({"markdown", "json", "toml"}));
  c->callback([format, printout, &action] {
    action = [format, printout] {
      std::cout << printout(*format);
      return 0;
    };
  });
  return c;
}

} // namespace pnc::app
