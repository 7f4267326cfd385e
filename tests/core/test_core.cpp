// core: outputs appear whole or not at all; CSV and HDF5 errors name file, field, value.
#include "pnc/core/atomic_file.hpp"
#include "pnc/core/csv.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {
fs::path fresh_dir(const char* tag) {
  const fs::path d = fs::temp_directory_path() /
                     (std::string("pnc_core_") + tag + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
std::size_t count(const fs::path& d) {
  return static_cast<std::size_t>(
      std::distance(fs::directory_iterator(d), fs::directory_iterator()));
}
} // namespace

TEST(AtomicOutput, UncommittedOutputLeavesNothingAndCommitReplacesWhole) {
  const fs::path d = fresh_dir("atomic");
  const std::string target = (d / "card.h5").string();
  {
    pnc::AtomicOutput out(target);
    std::ofstream(out.temp_path()) << "partial";
    EXPECT_EQ(count(d), 1u);
  } // destroyed without commit: e.g. an exception while writing
  EXPECT_EQ(count(d), 0u);
  std::ofstream(target) << "old";
  {
    pnc::AtomicOutput out(target);
    std::ofstream(out.temp_path()) << "new";
    out.commit();
  }
  std::ifstream in(target);
  std::string s;
  in >> s;
  EXPECT_EQ(s, "new");
  EXPECT_EQ(count(d), 1u);
  fs::remove_all(d);
}

TEST(AtomicOutput, HashIsStableAndContentSensitive) {
  const fs::path d = fresh_dir("hash");
  pnc::write_text_atomically((d / "a").string(), "abc");
  pnc::write_text_atomically((d / "b").string(), "abd");
  // FNV-1a 64 of "abc" (published test vector): e71fa2190541574b
  EXPECT_EQ(pnc::file_fnv1a64((d / "a").string()), "e71fa2190541574b");
  EXPECT_NE(pnc::file_fnv1a64((d / "a").string()), pnc::file_fnv1a64((d / "b").string()));
  fs::remove_all(d);
}

TEST(Csv, CommentsBlankLinesAndWhitespace) {
  const fs::path d = fresh_dir("csv");
  std::ofstream((d / "t.csv").string()) << "# comment\n\n a , b\n1, 2.5e3\n\n-3 ,4\n";
  const pnc::CsvTable t = pnc::read_csv((d / "t.csv").string());
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.column("b"), 1u);
  EXPECT_DOUBLE_EQ(t.rows[0][1], 2500.0);
  EXPECT_DOUBLE_EQ(t.rows[1][0], -3.0);
  EXPECT_EQ(t.line_numbers[1], 6);
  fs::remove_all(d);
}

TEST(Csv, RejectsEmptyCellsInfinityAndTrailingGarbage) {
  const fs::path d = fresh_dir("csvbad");
  for (const char* row : {"1,", "1,inf", "1,2x", "1,nan"}) {
    std::ofstream((d / "t.csv").string()) << "a,b\n" << row << "\n";
    EXPECT_THROW(pnc::read_csv((d / "t.csv").string()), pnc::InputError) << row;
  }
  std::ofstream((d / "e.csv").string()) << "\n# only a comment\n";
  EXPECT_THROW(pnc::read_csv((d / "e.csv").string()), pnc::InputError);
  fs::remove_all(d);
}

TEST(Hdf5, MissingDatasetIsNamed) {
  const fs::path d = fresh_dir("h5");
  const std::string f = (d / "x.h5").string();
  {
    pnc::h5::File w(f, pnc::h5::File::Mode::truncate);
    w.write_scalar("/a/b", 2.0);
    w.set_attr("/a/b", "units", "Pa");
  }
  pnc::h5::File r(f, pnc::h5::File::Mode::read);
  EXPECT_EQ(r.read_scalar("/a/b"), 2.0);
  EXPECT_EQ(r.attr_string("/a/b", "units").value(), "Pa");
  try {
    r.read_scalar("/a/c");
    FAIL();
  } catch (const pnc::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x.h5: field '/a/c'"), std::string::npos) << e.what();
  }
  fs::remove_all(d);
}
