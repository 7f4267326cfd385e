// Command-line errors in pnc's language (cli_errors.hpp).
#include "cli_errors.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <functional>
#include <iostream>
#include <numeric>

namespace pnc::app {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), std::size_t{0});
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0]; // d(i-1, j-1)
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j]; // d(i-1, j)
      row[j] = std::min({up + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::vector<std::string> nearest_names(std::string_view word,
                                       const std::vector<std::string>& candidates) {
  const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  std::size_t best = limit + 1;
  for (const auto& c : candidates)
    best = std::min(best, edit_distance(word, c));
  std::vector<std::string> out;
  for (const auto& c : candidates) {
    const bool nearest = best <= limit && edit_distance(word, c) == best;
    const bool extends = word.size() >= 3 && c.size() > word.size() && c.rfind(word, 0) == 0;
    if ((nearest || extends) && std::find(out.begin(), out.end(), c) == out.end()) out.push_back(c);
  }
  std::sort(out.begin(), out.end());
  if (out.size() > 4) out.resize(4);
  return out;
}

void configure_cli(CLI::App& app) {
  // every option's default value appears in --help ("=200"); subcommands inherit this
  app.option_defaults()->always_capture_default();
}

namespace {

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (const auto& x : v)
    s += (s.empty() ? "" : sep) + x;
  return s;
}

/// "pnc card show": the names from the top-level application down to `a`.
std::string command_path(const CLI::App* a) {
  std::vector<std::string> names;
  for (; a != nullptr && a->get_parent() != nullptr; a = a->get_parent())
    if (!a->get_name().empty()) names.push_back(a->get_name());
  names.push_back("pnc"); // the top level is named after argv[0], a path
  std::reverse(names.begin(), names.end());
  return join(names, " ");
}

/// Every subcommand of `a` as declared (option groups, which have no name, left out).
std::vector<CLI::App*> all_subcommands(CLI::App* a) {
  const std::function<bool(CLI::App*)> named = [](CLI::App* s) { return !s->get_name().empty(); };
  return a->get_subcommands(named);
}

std::vector<std::string> subcommand_names(CLI::App* a) {
  std::vector<std::string> n;
  for (const CLI::App* s : all_subcommands(a))
    n.push_back(s->get_name());
  return n;
}

CLI::App* find_subcommand(CLI::App* a, const std::string& tok) {
  for (CLI::App* s : all_subcommands(a))
    if (s->check_name(tok)) return s;
  return nullptr;
}

const CLI::Option* find_option(CLI::App* a, const std::string& name) {
  for (; a != nullptr; a = a->get_fallthrough() ? a->get_parent() : nullptr)
    for (const CLI::Option* o : static_cast<const CLI::App*>(a)->get_options())
      if (o->nonpositional() && o->check_name(name)) return o;
  return nullptr;
}

std::vector<std::string> option_names(CLI::App* a) {
  std::vector<std::string> n;
  for (const CLI::Option* o : static_cast<const CLI::App*>(a)->get_options()) {
    for (const auto& l : o->get_lnames())
      n.push_back("--" + l);
    for (const auto& s : o->get_snames())
      n.push_back("-" + s);
  }
  return n;
}

std::string suggestion(const std::string& word, const std::vector<std::string>& valid) {
  const auto near = nearest_names(word, valid);
  if (!near.empty()) return " (did you mean: " + join(near, ", ") + "?)";
  return valid.empty() ? std::string() : " (valid: " + join(valid, ", ") + ")";
}

/// What the command line gets wrong that CLI11 reports only vaguely: the first unknown
/// subcommand or option, with the nearest valid names. `where` gets the deepest subcommand
/// the command line reached. Empty when the walk finds nothing wrong.
std::string find_unknown_name(CLI::App& app, int argc, const char* const* argv, CLI::App*& where) {
  where = &app;
  for (int i = 1; i < argc; ++i) {
    const std::string tok = argv[i] ? argv[i] : "";
    if (tok == "--") break; // positionals only from here
    if (tok.size() > 1 && tok[0] == '-' && !(tok[1] >= '0' && tok[1] <= '9') && tok[1] != '.') {
      const bool long_form = tok.rfind("--", 0) == 0;
      const auto eq = tok.find('=');
      const std::string name =
          long_form ? tok.substr(0, eq) : tok.substr(0, 2); // "-j2": option "-j", value "2"
      const CLI::Option* o = find_option(where, name);
      if (o == nullptr) {
        std::vector<std::string> valid = option_names(where);
        std::sort(valid.begin(), valid.end());
        return "unknown option '" + clip(name, 60) + "' for '" + command_path(where) + "'" +
               suggestion(name, valid);
      }
      const bool value_attached = long_form ? eq != std::string::npos : tok.size() > 2;
      if (o->get_expected_min() > 0 && !value_attached) {
        // skip its value(s): one, or every following word for a list option
        const bool list = o->get_expected_max() > 1 || o->get_items_expected_max() > 1;
        do
          ++i;
        while (list && i + 1 < argc && argv[i + 1] && argv[i + 1][0] != '-');
      }
      continue;
    }
    if (CLI::App* sub = find_subcommand(where, tok)) {
      where = sub;
      continue;
    }
    const auto subs = subcommand_names(where);
    // a word where a subcommand is due: no positional argument of this command can take it
    bool takes_positional = false;
    for (const CLI::Option* o : static_cast<const CLI::App*>(where)->get_options())
      if (!o->nonpositional()) takes_positional = true;
    if (!subs.empty() && !takes_positional) {
      const std::string of = where == &app ? "" : " of '" + command_path(where) + "'";
      return "unknown subcommand '" + clip(tok, 60) + "'" + of + suggestion(tok, subs);
    }
  }
  return "";
}

/// CLI11's message on one line.
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  std::string out;
  for (char c : s)
    if (!(c == ' ' && !out.empty() && out.back() == ' ')) out += c;
  while (!out.empty() && out.back() == ' ')
    out.pop_back();
  return out;
}

} // namespace

std::string parse_error_message(CLI::App& app, const CLI::ParseError& e, int argc,
                                const char* const* argv) {
  CLI::App* where = &app;
  const std::string unknown = find_unknown_name(app, argc, argv, where);
  if (!unknown.empty()) return clip(unknown, 600); // names the valid names itself
  std::string msg = one_line(e.what());
  if (msg.empty()) msg = e.get_name();
  return clip(msg, 600) + "; see '" + command_path(where) + " --help'";
}

int report_parse_error(CLI::App& app, const CLI::ParseError& e, int argc, const char* const* argv) {
  if (e.get_exit_code() == 0) return app.exit(e); // --help, --help-all, --version: stdout, 0
  std::cerr << "pnc: error: " << parse_error_message(app, e, argc, argv) << std::endl;
  return exit_code::bad_input;
}

} // namespace pnc::app
