#pragma once
// Test helper: a fresh, empty scratch directory per test and process, and a file's bytes.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace pnc::test {

/// <temp>/pnc_<tag>_<pid>, emptied and created: two test processes (a CI run and a developer's
/// run on the same machine) never share one.
inline std::filesystem::path fresh_dir(const std::string& tag) {
  namespace fs = std::filesystem;
  const fs::path d = fs::temp_directory_path() / ("pnc_" + tag + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// The whole file as bytes ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

} // namespace pnc::test
