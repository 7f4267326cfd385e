// `pnc gimp run` end to end: --json on stdout, exit codes, bad input naming the key.
#include "common/run_command.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {
using Result = pnc::test::CommandResult;
Result sh(const std::string& cmd) {
  return pnc::test::run_command(cmd);
}
} // namespace

TEST(GimpCli, RunsExampleWithJsonAndResumes) {
  const fs::path d = fs::temp_directory_path() / "pnc_gimp_cli";
  fs::remove_all(d);
  fs::create_directories(d);
  const std::string in = std::string(PNC_SOURCE_DIR) + "/examples/gimp/bar_impact_3d.json";
  const std::string exe = PNC_EXE;
  Result r = sh(exe + " gimp run " + in + " --out " + (d / "out").string() +
                " --json --quiet --no-plot --max-steps 10 2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.out;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["dimension"], 3);
  EXPECT_EQ(j["steps"], 10);
  EXPECT_GT(j["particles"].get<int>(), 1000);
  r = sh(exe + " gimp run " + in + " --out " + (d / "out").string() +
         " --json --quiet --no-plot --resume --max-steps 20 2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.out;
  j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["resumed"].get<bool>());
  EXPECT_EQ(j["steps"], 20);
  EXPECT_EQ(j["steps_this_run"], 10);
  // The bar hits a wall of fixed nodes: the layer of mass at the wall nodes stops at once
  // (an inelastic nodal impact), so a few per cent of the kinetic energy is lost.
  const double e0 = 0.5 * 1200 * 0.05 * 0.008 * 0.008 * 100.0;
  EXPECT_LT(j["energy_J"]["balance"].get<double>(), 0.0);
  EXPECT_GT(j["energy_J"]["balance"].get<double>(), -0.05 * e0);
}

TEST(GimpCli, BadInputExitsWithOneAndNamesTheKey) {
  const fs::path d = fs::temp_directory_path() / "pnc_gimp_cli_bad";
  fs::create_directories(d);
  {
    std::ofstream f(d / "bad.json");
    f << R"({"dimension": 2, "grid": {"cells": [4, 4], "cell_size": 0.1},
            "materials": [{"name": "a", "type": "linear_elastic", "density": 1, "E": 1, "nu": 0.7}],
            "bodies": [], "time": {"end": 1}})";
  }
  const Result r = sh(std::string(PNC_EXE) + " gimp run " + (d / "bad.json").string() + " --out " +
                      (d / "out").string() + " 2>&1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("materials[0].nu"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0.7"), std::string::npos) << r.out;
}
