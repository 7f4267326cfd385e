#pragma once
// The bridge between the parameter layer (pnc/core/parameters.hpp) and CLI11 (decision D320):
// the command-line option of a declared input key takes its check, its help text and the
// default --help shows from the declaration, so a range or a list of allowed values is written
// once. A refused value reads "--points: value '0': must be an integer in [1, 64]": the option,
// the value and the declaration's rule (Parameter::rule(), the rule a file's key gets).
// Units: each declaration's own, printed in the help text with its range.
#include "registrars.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
class Option;
class Validator;
} // namespace CLI

namespace pnc {
class Parameters;
struct Parameter;
} // namespace pnc

namespace pnc::app {

/// The option of a declared key: "--" + the key with '_' as '-' ("hold_steps" ->
/// "--hold-steps").
std::string option_of_key(const std::string& key);

/// The items of a comma-separated list ("a,b,c"; "none" or "": no item).
std::vector<std::string> split_list(const std::string& text);

/// An option's text as the value its declaration checks: a string entry takes it as it is; a
/// number entry as JSON reads it (integer, or real) and else as strtod reads it ("nan", "inf",
/// "+5" become numbers the declaration refuses by range), else as a string (refused by type);
/// a list entry takes the items of split_list(text), each read so, or, with `one_element` (an
/// option given once per element), the text as a list of that one element.
nlohmann::json option_value(const Parameter& p, const std::string& text, bool one_element);

/// The help text of a declared key: its text, then what its value must be (the rule without
/// "must be": allowed values with their meanings, or the range with the unit), its remark, and
/// for a list given as one option "comma-separated, or none".
std::string declared_help(const Parameter& p, bool one_element);

/// The declared default as an option's text: a string as it is, a number as JSON prints it, a
/// list comma-separated ("none" when empty); "" when the key has no default.
std::string declared_default(const Parameter& p);

/// A CLI11 check of an option's values by the declaration `p` (Parameter::validate, on
/// option_value(p, text, one_element)): refuses with "value 'V': RULE" (V the text as typed; of
/// a list, the element refused), which CLI11 prefixes with the option's name.
CLI::Validator declared_check(const Parameter& p, bool one_element);

/// A declared key and its option.
struct DeclaredOption {
  std::string key;
  CLI::Option* option = nullptr;
};

/// Binds every declared entry of `declared` to its option of `cmd`, named option_of(key)
/// (CLI11 throws CLI::OptionNotFound when it is missing: every declared key needs its option,
/// and pnc then refuses to start). Each option gets declared_check (booleans, i.e. flags,
/// none); one added with an empty description also gets declared_help and declared_default as
/// the default --help shows (an option with its own text keeps it, e.g. the slurm options
/// shared with `pnc characterize`). An option that takes several values (CLI11 expected
/// count > 1) is checked one element at a time; the others' text is the whole list.
std::vector<DeclaredOption>
bind_declared_options(CLI::App* cmd, const Parameters& declared,
                      const std::function<std::string(const std::string&)>& option_of);

/// Binds one declared entry `p` to the option `o` as bind_declared_options does: for a command
/// whose options are only partly keys of its input (`pnc gimp run --threads` is the input's
/// `threads`, its --max-steps is not `time.max_steps`; D359).
DeclaredOption bind_declared_option(CLI::Option* o, const Parameter& p);

/// The keys whose option the command line gave (CLI11 count > 0): they override an input
/// file's (D301).
std::vector<std::string> given_keys(const std::vector<DeclaredOption>& options);

/// What a `parameters` subcommand prints for `--format` F ("markdown", "json" or "toml").
using ParametersPrintout = std::function<std::string(const std::string& format)>;

/// The printout of `declare()`: Markdown tables (heading level 4), JSON (indented 2) or a
/// commented TOML template with every default (Parameters::to_markdown, to_json, to_toml).
ParametersPrintout declared_printout(std::function<Parameters()> declare);

/// Adds --print-parameters[=markdown|json|toml] (default markdown) to `cmd`, the command that
/// reads the input `what` describes ("the run input"): it prints printout(format) on stdout and
/// ends pnc with exit code 0 like --help, before the command's required arguments are checked
/// (D358). The same printout as the command's `parameters` subcommand.
void add_print_parameters_option(CLI::App* cmd, ParametersPrintout printout,
                                 const std::string& what);

/// Adds the subcommand `name` to `parent` ("ti-parameters"): it prints `declare()` as
/// Markdown tables (--format markdown, the default; the generated regions of docs/*.md), JSON
/// or a commented TOML template with every default. `what` ends its description ("of a `pnc
/// thermo ti --input` file"), `toml_note` its --format help ("pnc thermo ti --input reads it").
void add_parameters_command(CLI::App* parent, const std::string& name, const std::string& what,
                            const std::string& toml_note, std::function<Parameters()> declare,
                            Action& action);
/// The same with its own printout (declared_printout or a command's, e.g. `pnc gimp
/// parameters` with --dimension).
CLI::App* add_parameters_command(CLI::App* parent, const std::string& name, const std::string& what,
                                 const std::string& toml_note, ParametersPrintout printout,
                                 Action& action);

} // namespace pnc::app
