#pragma once
// Inputs that made a fuzz target (fuzz/) crash or throw something other than pnc::InputError,
// kept in fuzz/regressions/<target>/ once the bug was fixed (docs/hardening-fuzz.md). Each is
// read through the same reader as in its fuzz target and must be refused with a clean
// pnc::InputError. Needs PNC_SOURCE_DIR.
#include "pnc/core/error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace pnc::test {

/// The regression inputs of one fuzz target, sorted; empty if there are none.
inline std::vector<std::string> fuzz_regressions(const std::string& target) {
  std::vector<std::string> out;
  const std::filesystem::path dir =
      std::filesystem::path(PNC_SOURCE_DIR) / "fuzz" / "regressions" / target;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    if (e.is_regular_file()) out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

/// Every regression input of `target` through read(path): a pnc::InputError that names the file
/// is the only accepted outcome. Fails (not skips) when the folder holds no input.
template <class Read> void expect_regressions_refused(const std::string& target, Read read) {
  const auto files = fuzz_regressions(target);
  ASSERT_FALSE(files.empty()) << "no inputs in fuzz/regressions/" << target;
  for (const auto& f : files) {
    SCOPED_TRACE(f);
    try {
      read(f);
      ADD_FAILURE() << "accepted; a regression input must be refused";
    } catch (const pnc::InputError& e) {
      EXPECT_EQ(e.context().source.rfind(f, 0), 0u) << e.what(); // names the file
      EXPECT_FALSE(e.context().rule.empty()) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a pnc::InputError: " << e.what();
    } catch (...) {
      ADD_FAILURE() << "a non-standard exception";
    }
  }
}

} // namespace pnc::test
