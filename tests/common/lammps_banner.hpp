#pragma once
// Test helper: the release date of the installed LAMMPS as its own executable prints it, an
// outside view of the version that pnc's md/ layer reports (D366).
#include "run_command.hpp"

#include <cstdio>
#include <regex>
#include <string>

namespace pnc::test {

/// The release date YYYYMMDD of the installed `lmp` from its banner ("Large-scale
/// Atomic/Molecular Massively Parallel Simulator - 29 Sep 2021 - Update 2" gives "20210929");
/// "" when `lmp -h` prints no such banner (no `lmp` on PATH, another format).
inline std::string lmp_banner_date() {
  const auto h = run_command("lmp -h 2>&1");
  std::smatch m;
  if (!std::regex_search(h.out, m, std::regex(R"(Simulator - (\d{1,2}) ([A-Z][a-z]{2}) (\d{4}))")))
    return "";
  static const std::string months = "JanFebMarAprMayJunJulAugSepOctNovDec";
  const auto at = months.find(m[2].str());
  if (at == std::string::npos || at % 3 != 0) return "";
  char date[16];
  std::snprintf(date, sizeof date, "%s%02d%02d", m[3].str().c_str(), static_cast<int>(at / 3) + 1,
                std::stoi(m[1].str()));
  return date;
}

} // namespace pnc::test
