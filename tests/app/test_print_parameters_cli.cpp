// `--print-parameters[=markdown|json|toml]` on the commands that read a declared input (D358):
// the same text as the command's `parameters` subcommand, printed and exit 0 without the
// command's required arguments; a format that is not one of the three is refused. Options that
// are keys of the input are checked by the key's declaration (D359).
#include "common/run_command.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace {

using pnc::test::run_command;

/// Each format of `cmd --print-parameters` equals `subcommand --format F` byte for byte
/// (`format_default`: the subcommand's default selector output, which the option prints), the
/// bare option prints Markdown, the JSON parses, and `--print-parameters=yaml` is refused.
void expect_same_printout(const std::string& cmd, const std::string& subcommand) {
  const std::string exe = PNC_EXE;
  for (const std::string f : {"markdown", "json", "toml"}) {
    const auto a = run_command(exe + " " + cmd + " --print-parameters=" + f + " 2>/dev/null");
    const auto b = run_command(exe + " " + subcommand + " --format " + f + " 2>/dev/null");
    ASSERT_EQ(a.code, 0) << cmd << " " << f;
    ASSERT_EQ(b.code, 0) << subcommand << " " << f;
    EXPECT_GT(a.out.size(), 200u) << cmd << " " << f;
    EXPECT_EQ(a.out, b.out) << cmd << " --print-parameters=" << f;
    if (f == "json") EXPECT_FALSE(nlohmann::json::parse(a.out).empty()) << cmd;
  }
  const auto bare = run_command(exe + " " + cmd + " --print-parameters 2>/dev/null");
  EXPECT_EQ(bare.code, 0) << cmd;
  EXPECT_EQ(bare.out, run_command(exe + " " + subcommand + " 2>/dev/null").out) << cmd;
  const auto bad = run_command(exe + " " + cmd + " --print-parameters=yaml 2>&1");
  EXPECT_NE(bad.code, 0) << cmd;
  EXPECT_NE(bad.out.find("yaml"), std::string::npos) << bad.out;
}

} // namespace

#ifdef PNC_TEST_HAVE_GIMP_COUPLER
TEST(PrintParameters, GimpRunPrintsTheGimpParametersText) {
  expect_same_printout("gimp run", "gimp parameters");
}
#endif

#ifdef PNC_TEST_HAVE_ESCM
TEST(PrintParameters, GimpCouplePrintsTheCoupleParametersText) {
  expect_same_printout("gimp couple", "gimp couple-parameters");
}
#endif

#ifdef PNC_TEST_HAVE_RVE
TEST(PrintParameters, CharacterizePrintsTheRecipeParametersText) {
  expect_same_printout("characterize", "recipe parameters");
}

// --jobs is the recipe's run.jobs and is checked by its declaration (D359): the rule a
// recipe's `jobs = 0` gets, before anything runs.
TEST(PrintParameters, CharacterizeJobsIsCheckedByTheRecipeDeclaration) {
  for (const char* v : {"0", "65"}) {
    const auto r = run_command(std::string(PNC_EXE) + " characterize demo --out /nonexistent/x" +
                               " --jobs " + v + " 2>&1");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("--jobs: value '" + std::string(v) + "': must be an integer in [1, 64]"),
              std::string::npos)
        << r.out;
  }
}
#endif

#ifdef PNC_TEST_HAVE_THERMO
TEST(PrintParameters, ThermoTiAndPersistencePrintTheirParametersText) {
  expect_same_printout("thermo ti", "thermo ti-parameters");
  expect_same_printout("thermo persistence", "thermo persistence-parameters");
}
#endif
