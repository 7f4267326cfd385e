#pragma once
// pnc/core/version.hpp: the toolkit's version, written into every output file.
#include <string>

namespace pnc {
std::string version();        ///< "MAJOR.MINOR.PATCH"
std::string version_string(); ///< "pnc MAJOR.MINOR.PATCH (git <hash>)"
std::string utc_timestamp();  ///< ISO 8601, UTC, seconds
/// The command line of the running pnc program, recorded in every output's provenance; the pnc
/// CLI sets it first thing (words shell-quoted), a program linking the libraries may set its
/// own. Empty until set.
void set_invocation(std::string command_line);
const std::string& invocation();
} // namespace pnc
