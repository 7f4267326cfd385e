#pragma once
// Command-line errors in pnc's language (docs/errors.md): every CLI11 parse error becomes one
// line "pnc: error: ..." on stderr and exit code 1; a mistyped subcommand or option names the
// nearest valid names ("unknown subcommand 'fitt' (did you mean: fit?)"). `--help` and
// `--version` still print to stdout and exit 0. Also the one place the CLI11 application gets
// the settings every command shares (defaults shown in --help).
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace CLI {
class App;
class ParseError;
} // namespace CLI

namespace pnc::app {

/// Levenshtein distance (insertions, deletions, substitutions; bytes) between a and b.
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The names of `candidates` nearest to `word`: those at the least edit distance when it is
/// at most max(2, |word| / 3), plus those that begin with `word` (3 characters or more);
/// sorted, at most 4. Empty when none is near.
std::vector<std::string> nearest_names(std::string_view word,
                                       const std::vector<std::string>& candidates);

/// Settings of the top-level application, made before any option or subcommand is added
/// (subcommands inherit them): every option's default is captured and shown by --help.
void configure_cli(CLI::App& app);

/// The message for a parse error of `argv` against `app`, without the "pnc: error: " prefix:
/// an unknown subcommand or option named with the nearest valid names when the command line
/// has one, else CLI11's message on one line ending with the help command to run.
std::string parse_error_message(CLI::App& app, const CLI::ParseError& e, int argc,
                                const char* const* argv);

/// Handles a parse error: help and version requests print as CLI11 prints them (stdout) and
/// return 0; anything else prints "pnc: error: <parse_error_message>" on stderr and returns
/// pnc::exit_code::bad_input (1).
int report_parse_error(CLI::App& app, const CLI::ParseError& e, int argc, const char* const* argv);

} // namespace pnc::app
