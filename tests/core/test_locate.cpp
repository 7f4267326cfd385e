// core: files pnc ships, found relative to the running executable (locate.hpp, D151). The
// build tree has the install layout: this test runs as <build>/tests/core/test_core and
// finds <build>/share/pnc/scripts two levels up.
#include "pnc/core/error.hpp"
#include "pnc/core/locate.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace {
fs::path fresh_dir(const char* tag) {
  return pnc::test::fresh_dir(std::string("locate_") + tag);
}
} // namespace

TEST(Locate, ExecutableDirIsThisTestsDirectory) {
  const fs::path x = pnc::executable_dir();
  ASSERT_TRUE(x.is_absolute()) << x;
  EXPECT_TRUE(fs::is_regular_file(x / "test_core")) << x;
}

TEST(Locate, FindsTheBuildTreesStagedScriptsWithTheInstallLayout) {
  ::unsetenv("PNC_TEST_LOCATE_DIR");
  const pnc::Located r =
      pnc::locate_shipped(pnc::ShippedDir::scripts, "plot_figures.py", "PNC_TEST_LOCATE_DIR");
  ASSERT_FALSE(r.path.empty()) << r.looked_in();
  EXPECT_EQ(fs::canonical(r.path), fs::canonical(fs::path(PNC_BINARY_DIR) / "share" / "pnc" /
                                                 "scripts" / "plot_figures.py"));
  EXPECT_EQ(pnc::shipped_relative_dir(pnc::ShippedDir::scripts), "share/pnc/scripts");
}

TEST(Locate, AnEnvironmentOverrideIsTheOnlyPlaceLookedAt) {
  const fs::path d = fresh_dir("env");
  std::ofstream(d / "mine.py") << "print('x')\n";
  ::setenv("PNC_TEST_LOCATE_DIR", d.c_str(), 1);
  const pnc::Located r =
      pnc::locate_shipped(pnc::ShippedDir::scripts, "mine.py", "PNC_TEST_LOCATE_DIR");
  EXPECT_EQ(r.path, (d / "mine.py").string());
  // a script that exists in the build tree is not found when the override lacks it
  const pnc::Located miss =
      pnc::locate_shipped(pnc::ShippedDir::scripts, "plot_figures.py", "PNC_TEST_LOCATE_DIR");
  EXPECT_TRUE(miss.path.empty());
  ASSERT_EQ(miss.tried.size(), 1u);
  EXPECT_EQ(miss.tried[0], (d / "plot_figures.py").string());
  try {
    pnc::require_shipped(pnc::ShippedDir::scripts, "plot_figures.py", "PNC_TEST_LOCATE_DIR");
    ADD_FAILURE() << "no error";
  } catch (const pnc::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("$PNC_TEST_LOCATE_DIR"), std::string::npos) << m;
    EXPECT_NE(m.find(d.string()), std::string::npos) << m;
    EXPECT_NE(m.find("has no plot_figures.py"), std::string::npos) << m;
  }
  // set but empty counts as unset
  ::setenv("PNC_TEST_LOCATE_DIR", "", 1);
  EXPECT_FALSE(
      pnc::locate_shipped(pnc::ShippedDir::scripts, "plot_figures.py", "PNC_TEST_LOCATE_DIR")
          .path.empty());
  ::unsetenv("PNC_TEST_LOCATE_DIR");
  fs::remove_all(d);
}

TEST(Locate, AMissingFileNamesEveryPlaceAndTheVariable) {
  ::unsetenv("PNC_TEST_LOCATE_DIR");
  const fs::path x = pnc::executable_dir();
  const pnc::Located r =
      pnc::locate_shipped(pnc::ShippedDir::libexec, "no_such_helper", "PNC_TEST_LOCATE_DIR");
  EXPECT_TRUE(r.path.empty());
  ASSERT_EQ(r.tried.size(), 3u); // next to the executable, then <exe>/../ and <exe>/../../
  EXPECT_EQ(r.tried[0], (x / "no_such_helper").string());
  EXPECT_EQ(r.tried[1], (x.parent_path() / "libexec/pnc/no_such_helper").string());
  EXPECT_EQ(r.tried[2], (x.parent_path().parent_path() / "libexec/pnc/no_such_helper").string());
  try {
    pnc::require_shipped(pnc::ShippedDir::libexec, "no_such_helper", "PNC_TEST_LOCATE_DIR");
    ADD_FAILURE() << "no error";
  } catch (const pnc::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("no_such_helper"), std::string::npos) << m;
    EXPECT_NE(m.find(r.tried[2]), std::string::npos) << m;
    EXPECT_NE(m.find("set PNC_TEST_LOCATE_DIR"), std::string::npos) << m;
  }
}
