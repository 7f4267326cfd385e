// core/error.hpp: the error kinds of pnc, their one-line messages and their exit codes, and
// the table of docs/errors.md that users read (it must list the same codes under the same
// names as pnc::exit_code).
#include "pnc/core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace ec = pnc::exit_code;

namespace {
int code_of_thrown(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return pnc::exit_code_of(e);
  }
  return -1;
}
} // namespace

TEST(ErrorKinds, EachKindIsOneLineNamingItsPartsWithItsExitCode) {
  const pnc::InputError in({"d.csv", "s22 (line 2)", "oops", "must be a number"});
  EXPECT_STREQ(in.what(), "d.csv: field 's22 (line 2)': value 'oops': must be a number");
  EXPECT_EQ(in.exit_code(), ec::bad_input);

  const pnc::SimulationError sim(
      {"RVE box", 4000, 4.0, "ps", "cavitated: void fraction 0.31 > 0.2 (fatal in this stage)"});
  EXPECT_STREQ(sim.what(),
               "RVE box: step 4000, t = 4 ps: cavitated: void fraction 0.31 > 0.2 (fatal in "
               "this stage)");
  EXPECT_EQ(sim.exit_code(), ec::simulation_failed);
  EXPECT_EQ(sim.context().step, 4000);

  // a tool's message spanning lines becomes one line; the log path closes it
  const pnc::ToolError tool({"LAMMPS", "running stage equilibrate/hot",
                             "ERROR: Unknown command: foo\nLast command: foo\n", "/r/hot.log"});
  EXPECT_STREQ(tool.what(), "LAMMPS failed while running stage equilibrate/hot: ERROR: Unknown "
                            "command: foo | Last command: foo (log /r/hot.log)");
  EXPECT_EQ(tool.exit_code(), ec::tool_failed);
  EXPECT_EQ(tool.context().log_path, "/r/hot.log");
  const std::vector<const pnc::Error*> all{&in, &sim, &tool};
  for (const pnc::Error* e : all)
    EXPECT_EQ(std::string(e->what()).find('\n'), std::string::npos) << e->what();
}

TEST(ErrorKinds, UnknownStepOrTimeIsLeftOutAndATimeWithoutUnitIsFlagged) {
  EXPECT_STREQ(
      pnc::SimulationError({"crack 'c1'", -1, std::nan(""), "", "front left the body"}).what(),
      "crack 'c1': front left the body");
  EXPECT_STREQ(pnc::SimulationError({"particle 12", -1, 2.5e-6, "s", "left the grid"}).what(),
               "particle 12: t = 2.5e-06 s: left the grid");
  const std::string no_unit = pnc::SimulationError({"box", 3, 1.0, "", "m"}).what();
  EXPECT_NE(no_unit.find("(unit not stated)"), std::string::npos) << no_unit;
  EXPECT_STREQ(pnc::ToolError({"python3", "", "", ""}).what(), "python3 failed: no message");
}

TEST(ErrorKinds, ThrowHelpersAndTheMappingOfAnyException) {
  EXPECT_EQ(code_of_thrown([] { pnc::fail("f", "k", "v", "rule"); }), ec::bad_input);
  EXPECT_EQ(code_of_thrown([] { pnc::fail_simulation("box", 1, 0.1, "ps", "exploded"); }),
            ec::simulation_failed);
  EXPECT_EQ(code_of_thrown([] { pnc::fail_tool("mpirun", "starting", "exit 1", "m.log"); }),
            ec::tool_failed);
  // anything that is not a pnc::Error is a bug
  EXPECT_EQ(code_of_thrown([] { throw std::runtime_error("x"); }), ec::internal_error);
  EXPECT_EQ(code_of_thrown([] { throw std::out_of_range("x"); }), ec::internal_error);
  // catch sites written for std::runtime_error still catch every kind
  EXPECT_THROW(pnc::fail_tool("LAMMPS", "", "", ""), std::runtime_error);
  EXPECT_THROW(pnc::fail_simulation("box", 1, 0.1, "ps", "x"), pnc::Error);
  EXPECT_THROW(pnc::fail("f", "", "", "r"), pnc::Error);
}

TEST(ExitCodes, SignalsMapTo128PlusTheSignalAndCodesAreDistinct) {
  EXPECT_EQ(ec::stopped_by_signal(SIGINT), 130);
  EXPECT_EQ(ec::stopped_by_signal(SIGTERM), 143);
  EXPECT_EQ(ec::stopped_by_signal(0), 130); // a stop that no signal asked for reads as SIGINT
  const std::set<int> codes{ec::ok,
                            ec::bad_input,
                            ec::internal_error,
                            ec::not_converged,
                            ec::card_not_usable,
                            ec::outside_reference,
                            ec::simulation_failed,
                            ec::tool_failed};
  EXPECT_EQ(codes.size(), 8u);
  EXPECT_LT(*codes.rbegin(), ec::signal_base); // never mistaken for a signal
}

// docs/errors.md is the table users read: every pnc::exit_code constant appears there with
// its value, and the table has no code the program does not have.
TEST(ExitCodes, TheUserTableListsTheSameCodesUnderTheSameNames) {
  const std::map<std::string, int> constants{{"ok", ec::ok},
                                             {"bad_input", ec::bad_input},
                                             {"internal_error", ec::internal_error},
                                             {"not_converged", ec::not_converged},
                                             {"card_not_usable", ec::card_not_usable},
                                             {"outside_reference", ec::outside_reference},
                                             {"simulation_failed", ec::simulation_failed},
                                             {"tool_failed", ec::tool_failed}};
  std::ifstream f(std::string(PNC_SOURCE_DIR) + "/docs/errors.md");
  ASSERT_TRUE(f) << "docs/errors.md";
  // rows "| 1 | `bad_input` | ..."
  const std::regex row(R"(^\|\s*(\d+)\s*\|\s*`([a-z_]+)`\s*\|)");
  std::map<std::string, int> table;
  for (std::string line; std::getline(f, line);) {
    std::smatch m;
    if (std::regex_search(line, m, row)) table[m[2]] = std::stoi(m[1]);
  }
  EXPECT_EQ(table, constants);
}

// A failure names its log once: a ToolError's message already ends with "(log PATH)", and the
// unit listings that add the unit's log must not repeat it.
TEST(ErrorKinds, WithLogNamesTheLogOnce) {
  const std::string tool = pnc::ToolError(pnc::ToolContext{"LAMMPS", "running stage case 6",
                                                           "ERROR: Lost atoms", "/r/case.log"})
                               .what();
  EXPECT_EQ(pnc::with_log(tool, "/r/case.log"), tool);
  EXPECT_EQ(pnc::with_log("failed", "/r/case.log"), "failed (log /r/case.log)");
  EXPECT_EQ(pnc::with_log("failed", ""), "failed");
  EXPECT_EQ(pnc::with_log(tool, "/r/other.log"), tool + " (log /r/other.log)");
}
