// tests/common/temp_dir.hpp: fresh_dir gives a new, empty, private directory on every call
// (mkdtemp), so two runs of the suite at once never share or delete each other's files.
#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace fs = std::filesystem;

namespace {
bool is_empty_dir(const fs::path& d) {
  return fs::is_directory(d) && fs::directory_iterator(d) == fs::directory_iterator();
}
/// The name is pnc_<tag>_ followed by mkdtemp's six characters.
void expect_named(const fs::path& d, const std::string& tag) {
  const std::string name = d.filename().string(), prefix = "pnc_" + tag + "_";
  EXPECT_EQ(name.substr(0, prefix.size()), prefix) << d;
  EXPECT_EQ(name.size(), prefix.size() + 6) << d;
}
} // namespace

TEST(FreshDir, TwoCallsWithOneTagGiveTwoEmptyPrivateDirectoriesUnderTheTempDirectory) {
  const fs::path a = pnc::test::fresh_dir("fresh_dir_test");
  const fs::path b = pnc::test::fresh_dir("fresh_dir_test");
  EXPECT_NE(a, b);
  for (const fs::path& d : {a, b}) {
    EXPECT_TRUE(is_empty_dir(d)) << d;
    EXPECT_EQ(fs::status(d).permissions(), fs::perms::owner_all) << d; // 0700
    EXPECT_TRUE(fs::equivalent(d.parent_path(), fs::temp_directory_path())) << d;
    expect_named(d, "fresh_dir_test");
  }
  // a file written into one is not seen in the other
  fs::create_directory(a / "x");
  EXPECT_TRUE(is_empty_dir(b));
  fs::remove_all(a);
  fs::remove_all(b);
}

// Blanks and shell characters in the tag reach the name unchanged (tests/md/test_lammps_path.cpp
// relies on them); fresh_dir_in puts the directory under the given base.
TEST(FreshDir, AwkwardTagsAndAnotherBaseKeepTheirName) {
  const fs::path base = pnc::test::fresh_dir("fresh_dir_base");
  const std::string tag = "a b#$x'q\"";
  const fs::path d = pnc::test::fresh_dir_in(base, tag);
  EXPECT_EQ(d.parent_path(), base);
  EXPECT_TRUE(is_empty_dir(d)) << d;
  EXPECT_EQ(fs::status(d).permissions(), fs::perms::owner_all) << d;
  expect_named(d, tag);
  fs::remove_all(base);
}

// A base that does not exist: std::runtime_error naming the template and the system's reason.
TEST(FreshDir, FailureNamesTheTemplateAndTheReason) {
  const fs::path base = pnc::test::fresh_dir("fresh_dir_gone");
  fs::remove(base);
  try {
    pnc::test::fresh_dir_in(base, "t");
    ADD_FAILURE() << "no error for a missing base " << base;
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find((base / "pnc_t_XXXXXX").string()), std::string::npos) << m;
    EXPECT_NE(m.find(std::strerror(ENOENT)), std::string::npos) << m;
  }
}

// The end-of-program clean-up: the list removes its directories when the program has passed so
// far, and never those of another process (a forked child exiting must not remove them).
TEST(FreshDir, TheListRemovesItsDirectoriesOnlyInTheProcessThatMadeThem) {
  const fs::path base = pnc::test::fresh_dir("list");
  const fs::path mine = base / "mine", other = base / "other";
  fs::create_directories(mine / "sub");
  fs::create_directories(other);
  {
    pnc::test::detail::ScratchDirs list;
    list.dirs = {mine};
  }
  EXPECT_FALSE(fs::exists(mine)) << "a passing program's directory was kept";
  {
    pnc::test::detail::ScratchDirs list;
    list.dirs = {other};
    list.owner = ::getpid() + 1; // as if made by another process
  }
  EXPECT_TRUE(fs::exists(other)) << "another process's directory was removed";
  fs::remove_all(base);
}
