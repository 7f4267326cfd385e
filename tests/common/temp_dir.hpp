#pragma once
// Test helper: a fresh, empty, private scratch directory per call, and a file's bytes.
#include <stdlib.h> // mkdtemp
#include <unistd.h> // getpid

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace pnc::test {

namespace detail {
/// The directories fresh_dir made in this process. At the process's end they are removed when
/// every test of the program passed (a failing run keeps them to look at); only by the process
/// that made them (a forked child that exits never removes its parent's directories).
struct ScratchDirs {
  std::vector<std::filesystem::path> dirs;
  pid_t owner = ::getpid();
  ~ScratchDirs() {
    if (::getpid() != owner || !::testing::UnitTest::GetInstance()->Passed()) return;
    std::error_code ec;
    for (const auto& d : dirs)
      std::filesystem::remove_all(d, ec);
  }
};
inline ScratchDirs& scratch_dirs() {
  ::testing::UnitTest::GetInstance(); // constructed first, so destroyed after the list
  static ScratchDirs list;
  return list;
}
} // namespace detail

/// A NEW directory <base>/pnc_<tag>_XXXXXX made by mkdtemp(3): unique per call (two calls with
/// one tag, two test processes, a CI clone and a developer's worktree running the suite at once
/// never share one), empty, and private (mode 0700, created by this user: no other local user can
/// have made it or write into it). Keep the returned path: a second call gives another directory.
/// It is removed at the end of the test program when every test passed (a test may remove it
/// earlier); after a failure it stays, to be looked at.
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
  detail::scratch_dirs().dirs.emplace_back(buf.data());
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
