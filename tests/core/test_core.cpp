// core: outputs appear whole or not at all; CSV and HDF5 errors name file, field, value.
#include "pnc/core/atomic_file.hpp"
#include "pnc/core/csv.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/params.hpp"

#include "common/temp_dir.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {
fs::path fresh_dir(const char* tag) {
  return pnc::test::fresh_dir(std::string("core_") + tag);
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

// ---------------------------------------------------------------- hardening of inputs
namespace {
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const pnc::InputError& e) {
    return e.what();
  }
  return "<no InputError>";
}
std::string nested(int depth, char open, char close) {
  return std::string(static_cast<std::size_t>(depth), open) +
         std::string(static_cast<std::size_t>(depth), close);
}
bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}
} // namespace

// Deep nesting is refused before any recursive parser or printer runs: 60000 levels is a
// clear error naming the file and the limit, never a crash; the limit itself is accepted.
TEST(InputNesting, DeepJsonIsRefusedWithTheRule) {
  for (const std::string& text :
       {nested(60000, '[', ']'), nested(pnc::kMaxNesting + 1, '[', ']'),
        std::string(60000, '{') /* unterminated: refused by depth, not by a crash */}) {
    const std::string m = message_of([&] { pnc::parse_json(text, "deep.json"); });
    EXPECT_TRUE(has(m, "deep.json")) << m.substr(0, 200);
    EXPECT_TRUE(has(m, "nest deeper than " + std::to_string(pnc::kMaxNesting))) << m;
  }
  EXPECT_NO_THROW(pnc::parse_json(nested(pnc::kMaxNesting, '[', ']'), "ok.json"));
  // Brackets inside strings are text, not nesting.
  const std::string in_string = "{\"s\": \"" + nested(1000, '[', ']') + "\\\"{{\"}";
  EXPECT_EQ(pnc::parse_json(in_string, "s.json").at("s").get<std::string>().size(), 2003u);
}

TEST(InputNesting, DeepTomlArraysTablesAndDottedKeysAreRefused) {
  using pnc::Syntax;
  auto refused = [](const std::string& text) {
    return has(message_of([&] { pnc::check_nesting(text, "r.toml", Syntax::toml); }),
               "r.toml: value 'line");
  };
  EXPECT_TRUE(refused("a = " + nested(60000, '[', ']') + "\n"));
  EXPECT_TRUE(refused("a = " + std::string(60000, '{')));
  std::string dotted = "k";
  for (int i = 0; i < pnc::kMaxNesting + 1; ++i)
    dotted += ".k";
  EXPECT_TRUE(refused(dotted + " = 1\n"));
  EXPECT_TRUE(refused("[" + dotted + "]\n"));
  // Strings (all four forms), comments and numbers with dots do not count.
  const std::string deep = nested(200, '[', ']');
  const std::string text = "a = \"" + deep + "\"\nb = '" + deep + "'\nc = \"\"\"\n" + deep +
                           "\"\"\"\nd = '''" + deep + "'''\n# " + deep +
                           "\n[build]\nx = [1.5, 2.5, 3.5]\ny.z = {w = 2.5}\n";
  EXPECT_NO_THROW(pnc::check_nesting(text, "r.toml", Syntax::toml));
}

TEST(InputNumbers, OverflowingJsonNumberIsAnInputError) {
  const std::string m = message_of([] { pnc::parse_json("{\"a\": 1e400}", "n.json"); });
  EXPECT_TRUE(has(m, "n.json")) << m;
  EXPECT_TRUE(has(m, "not valid JSON")) << m;
}

// Integers are never narrowed: a value is inside the stated range or refused, naming the file,
// the key, the value as written and the range.
TEST(InputNumbers, IntegersAreCheckedAgainstTheirRange) {
  using nlohmann::json;
  const json in = json::parse(R"({"chains": 4294967326, "case": 4294967298,
                                  "big": 18446744073709551615, "neg": -1, "float": 3.0,
                                  "text": "3", "flag": true, "ok": 30})");
  auto refusal = [&](const char* key, std::int64_t lo, std::int64_t hi) {
    return message_of([&] { pnc::get_integer_as<int>(in.at(key), "r.json", key, lo, hi); });
  };
  const std::string m = refusal("chains", 1, 100000);
  EXPECT_TRUE(has(m, "r.json: field 'chains': value '4294967326'")) << m;
  EXPECT_TRUE(has(m, "must be an integer in [1, 100000]")) << m;
  // 4294967298 = 2^32 + 2: a 32-bit wrap would give case 2.
  EXPECT_TRUE(has(refusal("case", 1, 6), "value '4294967298'"));
  EXPECT_TRUE(has(refusal("big", 0, 100), "value '18446744073709551615'"));
  EXPECT_TRUE(has(refusal("neg", 0, 100), "value '-1'"));
  for (const char* k : {"float", "text", "flag"})
    EXPECT_TRUE(has(refusal(k, 0, 100), "must be an integer")) << k;
  EXPECT_EQ(pnc::get_integer_as<int>(in.at("ok"), "r.json", "ok", 1, 100000), 30);
  // 2^64 - 1 does not fit a signed 64-bit integer: refused even with the widest range.
  EXPECT_THROW(
      pnc::get_integer(in.at("big"), "r.json", "big", 0, std::numeric_limits<std::int64_t>::max()),
      pnc::InputError);
  EXPECT_TRUE(has(message_of([] { pnc::get_number(nlohmann::json(1e300), "r", "end", 0, 1e6); }),
                  "must be a finite number in [0, 1000000]"));
}

// Messages never carry an unbounded value: a JSON value is shown in at most 80 characters
// (plus "…", cut on a UTF-8 boundary), however large or deep it is.
TEST(InputMessages, ShownValuesAreCapped) {
  nlohmann::json deep = nlohmann::json::array();
  for (int i = 0; i < 100000; ++i)
    deep = nlohmann::json::array({std::move(deep)});
  const std::string d = pnc::show_json(deep);
  EXPECT_LE(d.size(), pnc::kShownValueChars + 3);
  EXPECT_EQ(d.substr(0, 5), "[[[[[");
  EXPECT_EQ(d.substr(d.size() - 3), "\xE2\x80\xA6");
  std::string e;
  for (int i = 0; i < 100; ++i)
    e += "\xC3\xA9";                                             // e acute, two bytes
  EXPECT_EQ(pnc::clip(e, 81), e.substr(0, 80) + "\xE2\x80\xA6"); // not cut inside a character
  EXPECT_EQ(pnc::clip("short"), "short");
  const std::string m = message_of([] { pnc::fail("f", "k", std::string(100000, 'x'), "rule"); });
  EXPECT_LT(m.size(), 300u);
  EXPECT_TRUE(has(m, ": rule")) << m;
}

TEST(Csv, ByteOrderMarkIsSkippedAndDuplicatedColumnsAreRefused) {
  const fs::path d = fresh_dir("csvbom");
  const std::string f = (d / "t.csv").string();
  std::ofstream(f) << "\xEF\xBB\xBF"
                   << "case,b\n1,2\n";
  const pnc::CsvTable t = pnc::read_csv(f);
  EXPECT_EQ(t.column("case"), 0u);
  EXPECT_DOUBLE_EQ(t.rows.at(0).at(0), 1.0);
  std::ofstream(f) << "a,b,a\n1,2,3\n";
  const std::string m = message_of([&] { pnc::read_csv(f); });
  EXPECT_TRUE(has(m, "t.csv: field 'a': value 'columns 1 and 3'")) << m;
  EXPECT_TRUE(has(m, "duplicated column")) << m;
  fs::remove_all(d);
}
