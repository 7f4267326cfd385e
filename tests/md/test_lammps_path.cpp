// Paths in LAMMPS commands (lammps_path.hpp): quoted so that blanks, '#', '$' and quotes are
// literal, refused when LAMMPS cannot take them literally; a real restart round trip through
// a directory whose name holds all of those.
#include "pnc/core/error.hpp"
#include "pnc/md/lammps_path.hpp"
#include "pnc/md/runner.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

using namespace pnc::md;
namespace fs = std::filesystem;

namespace {

/// The word LAMMPS's parser makes of `quoted`: the text between the outer quotes when the
/// word starts with triple, double or single quotes (matched by the first closing quote of
/// the same kind, as LAMMPS does); the whole text otherwise.
std::string lammps_word(const std::string& quoted) {
  if (quoted.rfind("\"\"\"", 0) == 0) {
    const auto end = quoted.find("\"\"\"", 3);
    EXPECT_EQ(end + 3, quoted.size()) << "the triple quote closes early: " << quoted;
    return quoted.substr(3, end - 3);
  }
  if (quoted[0] == '\'' || quoted[0] == '"') {
    const auto end = quoted.find(quoted[0], 1);
    EXPECT_EQ(end + 1, quoted.size()) << "the quote closes early: " << quoted;
    return quoted.substr(1, end - 1);
  }
  return quoted;
}

pnc::ErrorContext error_of(const std::string& p) {
  try {
    lammps_path(p, "--out");
  } catch (const pnc::InputError& e) {
    return e.context();
  }
  ADD_FAILURE() << "expected an InputError for " << p;
  return {};
}

} // namespace

TEST(LammpsPath, QuotesSoThatTheWholePathIsOneLiteralWord) {
  for (const char* path :
       {"/tmp/plain.restart", "/tmp/with blank/x.restart", "/tmp/a#b/x", "/tmp/$HOME/${x}/$(1+1)",
        "/tmp/it's/x", "/tmp/say \"hi\"/x", "/tmp/both 'a' and \"b\"/x", "/tmp/&/x"}) {
    const std::string p = path;
    const std::string q = lammps_path(p);
    EXPECT_TRUE(q[0] == '\'' || q[0] == '"') << q; // always quoted: '#' and '$' are literal
    EXPECT_EQ(lammps_word(q), p) << q;
  }
}

TEST(LammpsPath, RefusesWhatLammpsCannotTakeLiterally) {
  for (const std::string& p :
       {std::string("/tmp/new\nline"), std::string("/tmp/tab\tx"),
        std::string("/tmp/star*.restart"), std::string("/tmp/per%cent"),
        std::string("/tmp/\"\"adjacent' quotes"), std::string("/tmp/ends 'with' \""),
        std::string("/tmp/caf\xc3\xa9")}) {
    const auto e = error_of(p);
    EXPECT_EQ(e.source, p); // names the user's path
    EXPECT_EQ(e.field, "--out");
    EXPECT_NE(e.rule.find("LAMMPS"), std::string::npos) << e.rule;
  }
  EXPECT_THROW(lammps_path(""), pnc::InputError);
}

// A restart written and read back by LAMMPS in a directory whose name holds a blank, '#',
// '$' and a quote: both commands must reach exactly that file.
TEST(LammpsPath, RestartRoundTripThroughAnAwkwardDirectory) {
  const fs::path d = pnc::test::fresh_dir("test lammps #path $x 'q'");
  const std::string restart = (d / "state.restart").string();
  const std::string out = (d / "natoms.txt").string();
  const auto o = run_stage({"awkward path", (d / "log.lammps").string(), {}}, [&](Lammps& l) {
    l.cmds({"units lj", "lattice fcc 0.8442", "region box block 0 2 0 2 0 2", "create_box 1 box",
            "create_atoms 1 box", "mass 1 1.0"});
    const long n = l.natoms();
    l.cmd("write_restart " + lammps_path(restart));
    l.cmd("clear");
    l.cmd("read_restart " + lammps_path(restart));
    std::ofstream(out) << n << " " << l.natoms() << "\n";
  });
  ASSERT_TRUE(o.ok) << o.error;
  EXPECT_TRUE(fs::is_regular_file(restart));
  long before = -1, after = -2;
  std::ifstream(out) >> before >> after;
  EXPECT_EQ(before, 32); // 2x2x2 fcc cells, 4 atoms each
  EXPECT_EQ(after, before);
  // nothing was written beside it under a truncated name (e.g. at the blank or '#')
  int files = 0;
  for (const auto& e : fs::directory_iterator(d.parent_path()))
    files += e.path().filename().string().rfind("pnc_test lammps", 0) == 0 ||
             e.path().filename().string() == "pnc_test";
  EXPECT_EQ(files, 1);
  fs::remove_all(d);
}
