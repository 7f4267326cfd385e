// `pnc gimp run` end to end: --json on stdout, exit codes, bad input naming the key.
#include "common/declarations_check.hpp"
#include "common/page_check.hpp"
#include "common/run_command.hpp"
#include "common/temp_dir.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {
using Result = pnc::test::CommandResult;
Result sh(const std::string& cmd) {
  return pnc::test::run_command(cmd);
}
} // namespace

TEST(GimpCli, RunsExampleWithJsonAndResumes) {
  const fs::path d = pnc::test::fresh_dir("gimp_cli");
  const std::string in = std::string(PNC_SOURCE_DIR) + "/examples/gimp/bar_impact_3d.json";
  const std::string exe = PNC_EXE;
  Result r = sh(exe + " gimp run " + in + " --out " + (d / "out").string() +
                " --json --quiet --no-plot --max-steps 10 2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.out;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["dimension"], 3);
  EXPECT_FALSE(j.contains("energy_J_per_m")); // 3-D: J and N (D281)
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
  // the run report of the resumed part: stopped by --max-steps, 3-D energies in J
  EXPECT_EQ(j["report"], (d / "out" / "report.html").string());
  const std::string html = pnc::test::slurp((d / "out" / "report.html").string());
  EXPECT_EQ(pnc::test::self_contained_problems(html), std::vector<std::string>{});
  // the "stopped early" banner comes first: why, where, and how to continue (with --resume)
  const auto banner = html.find("Did not finish: --max-steps (20) reached");
  EXPECT_NE(banner, std::string::npos);
  EXPECT_LT(banner, html.find("What was run"));
  EXPECT_NE(html.find("Stopped after step 20 at t = "), std::string::npos);
  EXPECT_NE(html.find("--resume --max-steps 20</code>"), std::string::npos) << "the resume command";
  EXPECT_NE(html.find("Energies at the end (J)"), std::string::npos);
  EXPECT_NE(html.find("Not drawn (--no-plot)."), std::string::npos);
}

// A coarse centre-cracked plate (half model of examples/gimp/plate_centre_crack_growth.json at
// twice the cell size) whose crack may grow twice: the report states the stop reason
// (max_increments), the relative energy error against its 1 % threshold (D271) with the
// warning exactly when above it, 2-D quantities per unit thickness, and embeds energy.png and
// G.png (critical-G line and stop marker drawn by plot_G.py); headless Chromium decodes both.
TEST(GimpCli, CrackRunReportShowsTheStopReasonAndRendersInABrowser) {
  const fs::path d = pnc::test::fresh_dir("gimp_cli_report");
  std::ofstream(d / "crack.json") << R"({
  "dimension": 2, "units": "SI",
  "grid": {"origin": [-0.0025, -0.0325], "cells": [19, 52], "cell_size": 0.00125},
  "particles_per_cell": 2,
  "materials": [{"name": "polymer", "type": "hyperelastic_polymer", "density": 1200,
                 "E": 1.5e9, "nu": 0.33}],
  "bodies": [{"material": "polymer", "shape": "box", "min": [0.0, -0.03], "max": [0.02, 0.03]}],
  "cracks": [{"name": "centre", "points": [[-0.001875, 1.25e-9], [0.010625, 1.25e-9]],
              "j_radius": [0.002, 0.008],
              "growth": {"Gc": 1000, "increment": 0.00125, "max_increments": 2}}],
  "boundaries": [{"name": "symmetry", "min": [-1, -1], "max": [0, 1], "symmetry": "x"}],
  "loads": {"tractions": [
    {"name": "top", "min": [0.0, 0.0294], "max": [0.02, 0.03], "axis": "y",
     "traction": [0.0, 1.0e7], "ramp": [0.0, 4.0e-4]},
    {"name": "bottom", "min": [0.0, -0.03], "max": [0.02, -0.0294], "axis": "y",
     "traction": [0.0, -1.0e7], "ramp": [0.0, 4.0e-4]}]},
  "damping": 1.2e5, "fracture_every": 10,
  "time": {"end": 5.0e-4, "cfl": 0.5},
  "output": {"interval": 2.5e-4, "history_every": 10}, "threads": 1
})";
  const Result r = sh(std::string(PNC_EXE) + " gimp run " + (d / "crack.json").string() +
                      " --out " + (d / "out").string() + " --json --quiet 2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  // the handbook G of the full load (2.6 kJ/m^2 at a = 10.3 mm, docs/gimp.md) exceeds Gc =
  // 1 kJ/m^2 by far, so the crack must use up its two increments
  EXPECT_EQ(j["crack_increments"], 2);
  // 2-D: energies and reactions per metre of thickness, and the keys say so (D281)
  EXPECT_FALSE(j.contains("energy_J"));
  EXPECT_TRUE(j.contains("reactions_N_per_m"));
  const auto& e = j["energy_J_per_m"];
  const double scale = std::max(
      {std::fabs(e["initial"].get<double>()),
       std::fabs(e["external_work"].get<double>()) + std::fabs(e["boundary_work"].get<double>()),
       e["kinetic"].get<double>() + e["strain"].get<double>()});
  const double rel = e["max_abs_balance"].get<double>() / scale;
  EXPECT_NEAR(j["relative_energy_error"].get<double>(), rel, 1e-12 * rel);
  const std::string html = pnc::test::slurp((d / "out" / "report.html").string());
  EXPECT_EQ(pnc::test::self_contained_problems(html), std::vector<std::string>{});
  EXPECT_NE(html.find("pnc gimp run: crack.json"), std::string::npos);
  EXPECT_NE(html.find("max_increments (2) reached"), std::string::npos);
  EXPECT_NE(html.find("threshold 1 %"), std::string::npos);
  EXPECT_EQ(html.find("above the threshold") != std::string::npos, rel > 0.01);
  EXPECT_NE(html.find("Energies at the end (J/m)"), std::string::npos);
  EXPECT_NE(html.find("Reactions at the last step (N/m"), std::string::npos);
  ASSERT_TRUE(fs::exists(d / "out" / "G.png")) << "python3-matplotlib is a test dependency";
  EXPECT_NE(pnc::test::slurp((d / "out" / "report.md").string()).find("](G.png)"),
            std::string::npos);
  const auto b = pnc::test::render_in_chromium((d / "out" / "report.html").string(), d.string());
  ASSERT_EQ(b.error, "");
  EXPECT_EQ(b.images, (std::vector<std::string>{"ok", "ok"})) << "energy.png and G.png decode";
  EXPECT_EQ(b.console, std::vector<std::string>{});
  // not a blank page: tables and two figures leave ink (an empty or unstyled white page is
  // below 1 % of the 1200 x 3000 screenshot)
  EXPECT_GT(b.ink, 0.02);
  if (!::testing::Test::HasFailure()) fs::remove_all(d); // kept for a look on failure
}

TEST(GimpCli, BadInputExitsWithOneAndNamesTheKey) {
  const fs::path d = pnc::test::fresh_dir("gimp_cli_bad");
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

// A simulation failure (a law that cannot take the deformation: a compressive traction of
// 1e12 Pa, far beyond the modulus of 1.5 GPa, inverts particles within the first step) ends
// with exit code 6 and the error as before, and the output folder still has a report whose
// first block says the run did not finish, why (the failure message), where (step and time with
// its unit), what is valid, and that resuming would meet the same failure; headless Chromium
// renders it.
TEST(GimpCli, SimulationFailureLeavesAReportSayingWhyAndWhere) {
  const fs::path d = pnc::test::fresh_dir("gimp_cli_fail");
  std::ofstream(d / "crush.json") << R"({
  "dimension": 2, "units": "SI",
  "grid": {"origin": [-0.002, -0.002], "cells": [14, 14], "cell_size": 0.001},
  "particles_per_cell": 2,
  "materials": [{"name": "polymer", "type": "hyperelastic_polymer", "density": 1200,
                 "E": 1.5e9, "nu": 0.33}],
  "bodies": [{"material": "polymer", "shape": "box", "min": [0.0, 0.0], "max": [0.01, 0.01]}],
  "boundaries": [{"name": "wall", "min": [-0.002, -0.002], "max": [0.0, 0.012], "fix": ["x"]}],
  "loads": {"tractions": [{"name": "push", "min": [0.009, 0.0], "max": [0.01, 0.01], "axis": "x",
                           "traction": [-1.0e12, 0.0], "ramp": [0.0, 1.0e-9]}]},
  "time": {"end": 1.0e-4, "cfl": 0.5},
  "output": {"interval": 2.0e-5, "vtu": "binary", "history_every": 10, "checkpoint_every": 1},
  "threads": 1
})";
  const fs::path out = d / "out";
  const Result r = sh(std::string(PNC_EXE) + " gimp run " + (d / "crush.json").string() +
                      " --out " + out.string() + " --no-plot 2>&1");
  EXPECT_EQ(r.code, 6) << r.out;
  EXPECT_NE(r.out.find("pnc: error: gimp: particle "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("det F"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("report (failed): " + (out / "report.html").string()), std::string::npos)
      << r.out;
  const std::string md = pnc::test::slurp((out / "report.md").string());
  const auto banner = md.find("## Did not finish: gimp: particle ");
  ASSERT_NE(banner, std::string::npos) << md;
  EXPECT_LT(banner, md.find("What was run")) << md;
  EXPECT_NE(md.find("det F", banner), std::string::npos) << md;
  EXPECT_NE(md.find("- Stopped at step "), std::string::npos) << md;
  EXPECT_NE(md.find(", t = "), std::string::npos) << md;
  EXPECT_NE(md.find("Resuming would meet the same failure"), std::string::npos) << md;
  EXPECT_EQ(md.find("--resume"), std::string::npos) << "no resume offered\n" << md;
  const std::string html = pnc::test::slurp((out / "report.html").string());
  EXPECT_EQ(pnc::test::self_contained_problems(html), std::vector<std::string>{});
  const auto b = pnc::test::render_in_chromium((out / "report.html").string(), d.string());
  ASSERT_EQ(b.error, "");
  EXPECT_EQ(b.console, std::vector<std::string>{});
  EXPECT_GT(b.ink, 0.0) << "the banner and tables are drawn";
  if (!::testing::Test::HasFailure()) fs::remove_all(d);
}

// `pnc gimp parameters` prints the declared input keys (D292): JSON with every section and
// entry (the rules derived from the declared ranges and SI units), Markdown tables, and the
// TOML list of one dimension with its defaults.
TEST(GimpCli, ParametersPrintsTheDeclarations) {
  const std::string cmd = std::string(PNC_EXE) + " gimp parameters";
  const auto rules = pnc::test::declared_rules(cmd);
  EXPECT_EQ(rules.at("time.cfl"), "must be a number in (0, 1]");
  EXPECT_EQ(rules.at("grid.cell_size"), "must be a number > 0 m");
  EXPECT_EQ(rules.at("materials[].density"), "must be a number > 0 kg/m^3");
  EXPECT_EQ(rules.at("cracks[].growth.Gc"), "must be a number > 0 J/m^2");
  EXPECT_EQ(rules.count("loads.tractions[].traction"), 1u);
  pnc::test::expect_prints(cmd, "#### `bodies[]` (shape = \"particles\")");
  pnc::test::expect_prints(cmd + " --format toml --dimension 3", "\ncfl = 0.5\n");
  pnc::test::expect_prints(cmd + " --format toml --dimension 3", "exactly 3 elements");
  EXPECT_NE(sh(cmd + " --dimension 4 2>&1").code, 0);
}

// The TOML template of `pnc gimp run --print-parameters=toml` (= `pnc gimp parameters --format
// toml`, D358) is an input `pnc gimp run` reads as a .toml file (D357) once its six lines marked
// "(required)" get values; every other key keeps the default the template states. A --threads
// the input's declaration refuses is refused with that rule (D359).
TEST(GimpCli, PrintedTomlTemplateRunsOnceTheRequiredKeysAreGiven) {
  const fs::path d = pnc::test::fresh_dir("gimp_cli_template");
  const std::string exe = PNC_EXE;
  const Result t = sh(exe + " gimp run --print-parameters=toml 2>/dev/null");
  ASSERT_EQ(t.code, 0);
  const std::vector<std::pair<std::string, std::string>> fill = {
      {"# dimension =   (required)", "dimension = 2"},
      {"# materials =   (required)",
       "materials = [{name = \"m\", type = \"linear_elastic\", density = 1000.0, E = 1.0e7, "
       "nu = 0.3}]"},
      {"# bodies =   (required)",
       "bodies = [{material = \"m\", shape = \"box\", min = [0.25, 0.125], max = [0.75, "
       "0.375]}]"},
      {"# cells =   (required)", "cells = [8, 4]"},
      {"# cell_size =   (required)", "cell_size = 0.125"},
      {"# end =   (required)", "end = 1.0"}};
  std::string toml = t.out;
  for (const auto& [from, to] : fill) {
    const auto at = toml.find(from + "\n");
    ASSERT_NE(at, std::string::npos) << "the template has no line '" << from << "'";
    toml.replace(at, from.size(), to);
  }
  EXPECT_EQ(toml.find("(required)"), std::string::npos) << "a required key left unfilled";
  std::ofstream(d / "template.toml") << toml;
  const Result r = sh(exe + " gimp run " + (d / "template.toml").string() + " --out " +
                      (d / "out").string() + " --json --quiet --no-plot --max-steps 3 2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["dimension"], 2);
  EXPECT_EQ(j["steps"], 3);
  EXPECT_EQ(j["threads"], 1);               // the template's default
  EXPECT_EQ(j["particles"], 4 * 2 * 2 * 2); // 4 x 2 cells, particles_per_cell 2 per axis
  const Result bad = sh(exe + " gimp run " + (d / "template.toml").string() + " --out " +
                        (d / "bad").string() + " --threads 0 2>&1");
  EXPECT_EQ(bad.code, 1) << bad.out;
  EXPECT_NE(bad.out.find("--threads: value '0': must be an integer in [1, 256]"), std::string::npos)
      << bad.out;
  if (!::testing::Test::HasFailure()) fs::remove_all(d);
}
