#pragma once
// Test helper: a fresh, empty, private scratch directory per call, and a file's bytes.
#include <stdlib.h> // mkdtemp

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace pnc::test {

/// A NEW directory <base>/pnc_<tag>_XXXXXX made by mkdtemp(3): unique per call (two calls with
/// one tag, two test processes, a CI clone and a developer's worktree running the suite at once
/// never share one), empty, and private (mode 0700, created by this user: no other local user can
/// have made it or write into it). Keep the returned path: a second call gives another directory.
/// Nothing removes it for the caller: a test removes it when done (remove_all).
/// The tag may hold blanks and shell characters, not '/'. Throws std::runtime_error naming the
/// template and the system's reason when the directory cannot be made.
inline std::filesystem::path fresh_dir_in(const std::filesystem::path& base,
                                          const std::string& tag) {
  const std::string tmpl = (base / ("pnc_" + tag + "_XXXXXX")).string();
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  if (::mkdtemp(buf.data()) == nullptr) {
    const int err = errno;
    throw std::runtime_error("fresh_dir: cannot make a directory from the template '" + tmpl +
                             "': " + std::strerror(err));
  }
  return std::filesystem::path(buf.data());
}

/// fresh_dir_in(<temp>, tag): <temp>/pnc_<tag>_XXXXXX, <temp> =
/// std::filesystem::temp_directory_path() (TMPDIR, else /tmp). Unique per call, empty, private (see
/// fresh_dir_in).
inline std::filesystem::path fresh_dir(const std::string& tag) {
  return fresh_dir_in(std::filesystem::temp_directory_path(), tag);
}

/// The whole file as bytes ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

} // namespace pnc::test
