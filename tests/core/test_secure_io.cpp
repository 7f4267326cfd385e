// core: outputs are created without following links or clobbering non-files; errors name the
// user's path and the rule.
#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

namespace fs = std::filesystem;

namespace {
using pnc::test::slurp;

fs::path fresh_dir(const char* tag) {
  return pnc::test::fresh_dir(std::string("secio_") + tag);
}

/// The InputError thrown by `f`, or a test failure if none.
pnc::ErrorContext error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const pnc::InputError& e) {
    return e.context();
  }
  ADD_FAILURE() << "expected a pnc::InputError";
  return {};
}

} // namespace

TEST(SecureOutput, TemporaryIsANewUniqueFileNextToTheTarget) {
  const fs::path d = fresh_dir("tmp");
  const std::string target = (d / "card.h5").string();
  // the name the old code used, planted as a link to a file we must not touch
  const fs::path victim = d / "victim.txt";
  std::ofstream(victim) << "keep";
  fs::create_symlink(victim, target + ".tmp." + std::to_string(::getpid()));
  {
    pnc::AtomicOutput a(target), b(target);
    EXPECT_NE(a.temp_path(), b.temp_path());
    EXPECT_EQ(fs::path(a.temp_path()).parent_path(), d);
    struct stat st {};
    ASSERT_EQ(::lstat(a.temp_path().c_str(), &st), 0);
    EXPECT_TRUE(S_ISREG(st.st_mode)); // created by us, not a link
    std::ofstream(a.temp_path(), std::ios::trunc) << "new";
    a.commit();
  }
  EXPECT_EQ(slurp(target), "new");
  EXPECT_EQ(slurp(victim), "keep");
  // the planted link and the victim remain, no temporary file is left behind
  EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 3);
  fs::remove_all(d);
}

TEST(SecureOutput, TemporaryModeIs0644LessTheUmask) {
  const fs::path d = fresh_dir("mode");
  for (const mode_t mask : {mode_t(022), mode_t(077)}) {
    const mode_t old = ::umask(mask);
    {
      pnc::AtomicOutput a((d / "x.csv").string());
      struct stat st {};
      ASSERT_EQ(::stat(a.temp_path().c_str(), &st), 0);
      EXPECT_EQ(st.st_mode & 0777, 0644 & ~mask) << "umask " << mask;
    }
    ::umask(old);
  }
  fs::remove_all(d);
}

TEST(SecureOutput, RefusesTargetsThatAreNotRegularFiles) {
  const fs::path d = fresh_dir("kinds");
  const fs::path victim = d / "victim.txt";
  std::ofstream(victim) << "keep";
  const fs::path link = d / "link.csv", fifo = d / "fifo.csv", dir = d / "dir.csv";
  fs::create_symlink(victim, link);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  fs::create_directory(dir);
  const std::pair<fs::path, const char*> cases[] = {
      {link, "symbolic link"}, {fifo, "fifo"}, {dir, "directory"}};
  for (const auto& c : cases) {
    const fs::path& path = c.first; // not a structured binding: Clang 14 cannot capture those
    const char* kind = c.second;
    const auto e = error_of([&] { pnc::write_text_atomically(path.string(), "x"); });
    EXPECT_EQ(e.source, path.string()); // the user's path, not a temporary name
    EXPECT_NE(e.rule.find(kind), std::string::npos) << e.rule;
    EXPECT_NE(e.rule.find("regular file"), std::string::npos) << e.rule;
  }
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(fs::is_directory(dir));
  EXPECT_EQ(slurp(victim), "keep");
  EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 4);
  fs::remove_all(d);
}

TEST(SecureOutput, CommitRefusesATargetReplacedWhileWriting) {
  const fs::path d = fresh_dir("race");
  const fs::path target = d / "out.csv", victim = d / "victim.txt";
  std::ofstream(victim) << "keep";
  const auto e = error_of([&] {
    pnc::AtomicOutput a(target.string());
    std::ofstream(a.temp_path(), std::ios::trunc) << "new";
    fs::create_symlink(victim, target); // appears between the check and the rename
    a.commit();
  });
  EXPECT_EQ(e.source, target.string());
  EXPECT_TRUE(fs::is_symlink(target));
  EXPECT_EQ(slurp(victim), "keep");
  EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 2);
  fs::remove_all(d);
}

TEST(SecureOutput, BadOutputPathsNameThePathAndTheRule) {
  const fs::path d = fresh_dir("paths");
  std::ofstream(d / "file.txt") << "a file";
  const auto empty = error_of([] { pnc::check_output_file("", "--out"); });
  EXPECT_EQ(empty.field, "--out");
  EXPECT_NE(empty.rule.find("must not be empty"), std::string::npos);
  const std::string under_file = (d / "file.txt" / "out.h5").string();
  const auto nodir = error_of([&] { pnc::AtomicOutput a(under_file); });
  EXPECT_EQ(nodir.source, under_file);
  EXPECT_NE(nodir.rule.find("not a directory"), std::string::npos) << nodir.rule;
  const std::string missing = (d / "no" / "such" / "out.h5").string();
  EXPECT_EQ(error_of([&] { pnc::write_text_atomically(missing, "x"); }).source, missing);
  // directories: mkdir -p, refused through or onto a regular file, empty refused
  const std::string deep = (d / "a" / "b" / "c").string();
  pnc::make_output_directory(deep);
  EXPECT_TRUE(fs::is_directory(deep));
  pnc::make_output_directory(deep); // existing is fine
  const std::string onto = (d / "file.txt").string(), through = (d / "file.txt" / "x").string();
  for (const auto& p : {onto, through}) {
    const auto e = error_of([&] { pnc::make_output_directory(p, "--out"); });
    EXPECT_EQ(e.source, p);
    EXPECT_EQ(e.field, "--out");
    EXPECT_NE(e.rule.find("not a directory"), std::string::npos) << e.rule;
  }
  EXPECT_NE(error_of([] { pnc::make_output_directory(""); }).rule.find("empty"), std::string::npos);
  EXPECT_EQ(slurp(d / "file.txt"), "a file");
  fs::remove_all(d);
}
