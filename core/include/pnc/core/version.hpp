#pragma once
// pnc/core/version.hpp: the toolkit's version, written into every output file.
#include <string>

namespace pnc {
std::string version();        ///< "MAJOR.MINOR.PATCH"
std::string version_string(); ///< "pnc MAJOR.MINOR.PATCH (git <hash>)"
std::string utc_timestamp();  ///< ISO 8601, UTC, seconds
} // namespace pnc
