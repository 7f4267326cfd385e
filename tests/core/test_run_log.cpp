// pnc.log (core/run_log.hpp): what pnc prints on std::cout and std::cerr still reaches the
// terminal unchanged and is also appended to the run folder's log, one timestamped, tagged line
// per printed line; sessions append; a symbolic link in place of the log is refused.
#include "pnc/core/error.hpp"
#include "pnc/core/run_log.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {
using pnc::test::fresh_dir;

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::string> v;
  for (std::string l; std::getline(f, l);)
    v.push_back(l);
  return v;
}

/// Redirects std::cout and std::cerr into strings for the test's lifetime (the "terminal").
struct Terminal {
  std::ostringstream out, err;
  std::streambuf* old_out = std::cout.rdbuf(out.rdbuf());
  std::streambuf* old_err = std::cerr.rdbuf(err.rdbuf());
  ~Terminal() {
    std::cout.rdbuf(old_out);
    std::cerr.rdbuf(old_err);
  }
};

const std::regex kStamp(R"(^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z (out|err|---) .*)");

} // namespace

TEST(RunLog, EveryPrintedLineReachesTheTerminalAndTheLogWithTimeAndStream) {
  const fs::path d = fresh_dir("run_log_lines");
  Terminal term;
  std::streambuf* const terminal_out = std::cout.rdbuf();
  pnc::start_run_log(d.string(), "pnc demo --out x");
  EXPECT_TRUE(pnc::run_log_active());
  std::cout << "result: " << 42 << "\n";
  std::cerr << "step 1/2\rstep 2/2\n"; // a progress line rewritten in place
  std::cerr << "no newline at the end";
  pnc::finish_run_log(3);
  EXPECT_FALSE(pnc::run_log_active());
  EXPECT_EQ(std::cout.rdbuf(), terminal_out) << "the stream's own buffer is back";
  EXPECT_EQ(term.out.str(), "result: 42\n");
  EXPECT_EQ(term.err.str(), "step 1/2\rstep 2/2\nno newline at the end");

  const auto l = lines_of(pnc::run_log_path(d.string()));
  ASSERT_EQ(l.size(), 5u);
  for (const auto& s : l)
    EXPECT_TRUE(std::regex_match(s, kStamp)) << s;
  EXPECT_NE(l[0].find("started in "), std::string::npos) << l[0];
  EXPECT_NE(l[0].find(": pnc demo --out x"), std::string::npos) << l[0];
  EXPECT_EQ(l[1].substr(24), " out result: 42");
  EXPECT_EQ(l[2].substr(24), " err step 2/2");
  EXPECT_EQ(l[3].substr(24), " err no newline at the end");
  EXPECT_EQ(l[4].substr(24), " --- pnc finished: exit code 3");
  // after the session nothing more is copied
  std::cout << "later\n";
  EXPECT_EQ(lines_of(pnc::run_log_path(d.string())).size(), 5u);
}

TEST(RunLog, AResumedRunAppendsASession) {
  const fs::path d = fresh_dir("run_log_append");
  Terminal term;
  pnc::start_run_log(d.string(), "first");
  std::cerr << "one\n";
  pnc::finish_run_log(130);
  pnc::start_run_log(d.string(), "second");
  std::cerr << "two\n";
  pnc::finish_run_log(0);
  const auto l = lines_of(pnc::run_log_path(d.string()));
  ASSERT_EQ(l.size(), 6u);
  EXPECT_NE(l[0].find(": first"), std::string::npos);
  EXPECT_NE(l[2].find("exit code 130"), std::string::npos);
  EXPECT_NE(l[3].find(": second"), std::string::npos);
  EXPECT_EQ(l[4].substr(24), " err two");
  EXPECT_NE(l[5].find("exit code 0"), std::string::npos);
}

TEST(RunLog, ASymbolicLinkInPlaceOfTheLogIsRefusedAndNothingIsWrittenThrough) {
  const fs::path d = fresh_dir("run_log_link");
  const fs::path target = d / "elsewhere.txt";
  std::ofstream(target) << "keep\n";
  fs::create_symlink(target, d / "pnc.log");
  try {
    pnc::start_run_log(d.string(), "x");
    FAIL() << "a symbolic link was accepted";
  } catch (const pnc::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("pnc.log"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("symbolic link"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(pnc::run_log_active());
  EXPECT_EQ(lines_of(target.string()), std::vector<std::string>{"keep"});
  pnc::finish_run_log(0); // nothing active: does nothing
}

// LAMMPS ends a stage child with exit() while the log is active: static objects are destroyed
// and std::cout is flushed after them. The process must still end with its own exit code and
// the lines it printed must be in the log.
TEST(RunLogDeathTest, ExitWhileTheLogIsActiveKeepsTheExitCodeAndTheLines) {
  const fs::path d = fresh_dir("run_log_exit");
  EXPECT_EXIT(
      {
        pnc::start_run_log(d.string(), "exit test");
        std::cout << "printed before exit\n";
        std::cerr << "pending without newline";
        std::exit(5);
      },
      ::testing::ExitedWithCode(5), "");
  const auto l = lines_of(pnc::run_log_path(d.string()));
  ASSERT_GE(l.size(), 2u);
  EXPECT_EQ(l[1].substr(24), " out printed before exit");
}
