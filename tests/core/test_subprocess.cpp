// core: programs run with an argument vector, never through a shell (subprocess.hpp).
#include "pnc/core/error.hpp"
#include "pnc/core/subprocess.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

namespace fs = std::filesystem;

namespace {
fs::path fresh_dir(const char* tag) {
  return pnc::test::fresh_dir(std::string("spawn_") + tag);
}
} // namespace

TEST(Subprocess, ArgumentsAreDataNotShellSyntax) {
  const fs::path d = fresh_dir("spawn");
  const fs::path marker = d / "X";
  const std::string evil = "'; touch " + marker.string() + "; echo '$(touch " + marker.string() +
                           ")`touch " + marker.string() + "`";
  const auto r = pnc::run_subprocess({"echo", evil});
  ASSERT_TRUE(r.started) << r.error;
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.output, evil + "\n"); // one argv entry, byte for byte
  EXPECT_FALSE(fs::exists(marker));
  fs::remove_all(d);
}

TEST(Subprocess, CapturesStderrExitCodeAndMissingPrograms) {
  const auto r = pnc::run_subprocess({"ls", "/no/such/path/for/pnc"});
  ASSERT_TRUE(r.started);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.output.find("/no/such/path/for/pnc"), std::string::npos) << r.output; // stderr
  const auto m = pnc::run_subprocess({"/no/such/program-pnc"});
  EXPECT_FALSE(m.started);
  EXPECT_FALSE(m.error.empty());
  EXPECT_THROW(pnc::run_subprocess({}), pnc::InputError);
}
