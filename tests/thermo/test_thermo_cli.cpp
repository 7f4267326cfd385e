// The `pnc thermo` subcommands end to end on tiny inputs: outputs, --json, --resume, and
// errors that name the input (a LAMMPS error with LAMMPS's message).
#include "common/page_check.hpp"
#include "common/run_command.hpp"
#include "common/spawn.hpp"
#include "common/temp_dir.hpp"

#include "pnc/md/builder.hpp"
#include "pnc/md/forcefield.hpp"
#include "pnc/md/runner.hpp"

#include <fmt/format.h>

#include "tiny_polymer.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {
using CmdRun = pnc::test::CommandResult;

/// The header and the rows (cells as text) of a CSV file the plots are drawn from.
std::vector<std::vector<std::string>> csv_cells(const fs::path& p) {
  std::ifstream f(p);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(f, line);) {
    rows.emplace_back();
    std::istringstream l(line);
    for (std::string c; std::getline(l, c, ',');)
      rows.back().push_back(c);
  }
  return rows;
}
CmdRun run(const std::string& args) {
  return pnc::test::run_command(std::string(PNC_EXE) + " " + args + " 2>/dev/null");
}
CmdRun run_err(const std::string& args) { // stderr only
  return pnc::test::run_command(std::string(PNC_EXE) + " " + args + " 2>&1 >/dev/null");
}
fs::path tmp(const std::string& tag) {
  return pnc::test::fresh_dir("test_thermo_cli_" + tag);
}
} // namespace

/// The page `pnc thermo ...` wrote into `out`: report.html, checked self-contained.
std::string report_page(const fs::path& out) {
  EXPECT_TRUE(fs::exists(out / "report.md"));
  const std::string html = pnc::test::slurp((out / "report.html").string());
  EXPECT_EQ(pnc::test::self_contained_problems(html), std::vector<std::string>{});
  return html;
}

/// `v ± se` as the report prints a value with its error (4 and 2 significant digits).
std::string pm(double v, double se) {
  return fmt::format("{:.4g} ± {:.2g}", v, se);
}

// The harmonic-chain persistence run needs no input file: JSON keys, relations between
// them, and --resume (no rerun, same numbers).
TEST(ThermoCli, PersistenceHarmonicJsonAndResume) {
  const auto d = tmp("pers");
  const std::string args = "thermo persistence --chain harmonic --supports roller --angle-k 500 "
                           "--spring-k 100 --pull-distance 1 --rates 0.002,0.004,0.006 "
                           "--timestep 1 --hold-steps 200 --no-plots --json --out " +
                           d.string();
  const CmdRun r = run(args);
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["rates"].size(), 3u);
  EXPECT_TRUE(fs::exists(d / "persistence.h5"));
  // --json is SI (D280): xi_p = EI0 / kT at 300 K, with the k_B of LAMMPS real units
  // (0.0019872067 kcal/mol/K, 1.2e-6 above CODATA's) that xi_p is computed with: round-off only
  const double si = 4184.0 / 6.02214076e23 * 1e-10;        // N m^2 per kcal/mol A
  const double kB = 0.0019872067 * 4184.0 / 6.02214076e23; // J/K
  EXPECT_NEAR(j["xi_p_m"].get<double>() / (j["EI0_N_m2"].get<double>() / (kB * 300)), 1.0, 1e-12);
  // 2 K l0 with K = 500 and l0 = 1.53 A, in N m^2
  EXPECT_NEAR(j["expected_EI_continuum_N_m2"].get<double>() / (1530.0 * si), 1.0, 1e-12);
  // the anchor speeds in m/s: 1 A/fs = 1e5 m/s
  EXPECT_NEAR(j["rates"][0]["rate_m_per_s"].get<double>(), 0.002 * 1e5, 1e-9);
  // the run report (in the field's units): the command, EI(0) and xi_p with their 95 %
  // intervals, no figures
  const double ei = j["EI0_N_m2"].get<double>() / si, ci = j["EI0_ci95_N_m2"].get<double>() / si;
  const double xi = j["xi_p_m"].get<double>() * 1e10, xci = j["xi_p_ci95_m"].get<double>() * 1e10;
  EXPECT_EQ(j["report"], (d / "report.html").string());
  std::string html = report_page(d);
  EXPECT_NE(html.find("pnc thermo persistence"), std::string::npos);
  EXPECT_NE(html.find(pm(ei, ci) + " kcal/mol Å"), std::string::npos);
  EXPECT_NE(html.find(pm(xi, xci) + " Å"), std::string::npos);
  EXPECT_NE(html.find("Not drawn (--no-plots)."), std::string::npos);
  EXPECT_EQ(html.find("data:image/png"), std::string::npos);
  // D270: the verdict follows the interval (resolved beyond twice, noise within once)
  EXPECT_NE(html.find(ei > 2 * ci ? "Resolved:" : ei > ci ? "Weak:" : "Noise:"), std::string::npos);
  const auto t = fs::last_write_time(d / "rate_0.h5");
  const CmdRun r2 = run(args + " --resume");
  ASSERT_EQ(r2.code, 0);
  EXPECT_EQ(fs::last_write_time(d / "rate_0.h5"), t);
  EXPECT_EQ(nlohmann::json::parse(r2.out)["EI0_N_m2"], j["EI0_N_m2"]);
  // resumed again with plots asked for, under a Python whose matplotlib import fails (as
  // without python3-matplotlib): exit code 0, and the page says why there is no figure
  fs::create_directories(d / "nompl" / "matplotlib");
  std::ofstream(d / "nompl" / "matplotlib" / "__init__.py")
      << "raise ModuleNotFoundError(\"No module named 'matplotlib'\")\n";
  std::string plots = args;
  plots.erase(plots.find("--no-plots "), 11);
  const CmdRun r3 = pnc::test::run_command("PYTHONPATH='" + (d / "nompl").string() + "' " +
                                           PNC_EXE + " " + plots + " --resume 2>/dev/null");
  ASSERT_EQ(r3.code, 0) << r3.out;
  EXPECT_TRUE(nlohmann::json::parse(r3.out)["plots"].empty());
  html = report_page(d);
  EXPECT_NE(html.find("Not drawn: "), std::string::npos);
  EXPECT_NE(html.find("plotting: "), std::string::npos) << "in the warnings";
  EXPECT_NE(html.find("matplotlib"), std::string::npos);
  EXPECT_EQ(html.find("data:image/png"), std::string::npos);
}

// The persistence page in a real browser, on the smallest run (the harmonic chain of
// PersistenceHarmonicJsonAndResume, plots drawn): it loads with no console message, every
// figure plot_thermo.py drew is embedded and decodes, and the screenshot is not blank. The
// screenshot is left in the test's working directory: persistence_report_screenshot.png.
TEST(ThermoCli, PersistencePageRendersInHeadlessChromium) {
  const auto d = tmp("pers_page");
  const fs::path out = d / "out";
  const CmdRun r = run("thermo persistence --chain harmonic --supports roller --angle-k 500 "
                       "--spring-k 100 --pull-distance 1 --rates 0.002,0.004,0.006 "
                       "--timestep 1 --hold-steps 200 --json --out " +
                       out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_FALSE(j["plots"].empty()) << "python3-matplotlib is a test dependency";
  const std::string html = report_page(out);
  std::size_t embedded = 0;
  for (auto at = html.find("src=\"data:image/png;base64,iVBORw0KGgo"); at != std::string::npos;
       at = html.find("src=\"data:image/png;base64,iVBORw0KGgo", at + 1))
    ++embedded;
  EXPECT_EQ(embedded, j["plots"].size()) << "every figure drawn is on the page";
  // the CSV the figure is drawn from: SI names and the numbers of --json (12 digits written)
  const auto c = csv_cells(out / "EI_vs_rate.csv");
  ASSERT_EQ(c.size(), 5u); // header, 3 rates, the fit
  EXPECT_EQ(c[0], (std::vector<std::string>{"kind", "rate_m_per_s", "EI_N_m2", "EI_err_N_m2",
                                            "EI_end_N_m2"}));
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& jr = j["rates"][i];
    ASSERT_EQ(c[i + 1].size(), 5u);
    EXPECT_NEAR(std::stod(c[i + 1][1]), jr["rate_m_per_s"].get<double>(),
                1e-11 * jr["rate_m_per_s"].get<double>());
    EXPECT_NEAR(std::stod(c[i + 1][2]), jr["EI_N_m2"].get<double>(),
                1e-11 * std::fabs(jr["EI_N_m2"].get<double>()));
    EXPECT_NEAR(std::stod(c[i + 1][3]), jr["EI_stderr_N_m2"].get<double>(),
                1e-11 * std::fabs(jr["EI_stderr_N_m2"].get<double>()));
  }
  EXPECT_EQ(c[4][0], "fit");
  EXPECT_NEAR(std::stod(c[4][2]), j["EI0_N_m2"].get<double>(),
              1e-11 * std::fabs(j["EI0_N_m2"].get<double>()));
  const auto b = pnc::test::render_in_chromium((out / "report.html").string(), d.string());
  ASSERT_EQ(b.error, "");
  EXPECT_EQ(b.images, std::vector<std::string>(j["plots"].size(), "ok"))
      << "the embedded figures decode";
  EXPECT_EQ(b.console, std::vector<std::string>{});
  // not a blank page (an empty or unstyled white page is below 1 % of the 1200 x 3000 shot)
  EXPECT_GT(b.ink, 0.02);
  // the screenshot for a human, in the test's working directory (the build tree)
  fs::copy_file(d / "screenshot.png", "persistence_report_screenshot.png",
                fs::copy_options::overwrite_existing);
  if (!::testing::Test::HasFailure()) fs::remove_all(d); // kept for a look on failure
}

// SIGINT during the first bending rate (5e6 hold steps: minutes, far longer than the wait):
// exit 128 + SIGINT, and the folder has a report whose first block says the run did not finish,
// why, how many rates are done (none) and the command that continues it.
TEST(ThermoCli, PersistenceStoppedBySigintLeavesAReport) {
  const auto d = tmp("pers_stop");
  const fs::path out = d / "out";
  const std::string cmd = std::string(PNC_EXE) +
                          " thermo persistence --chain harmonic --supports roller --angle-k 500 "
                          "--spring-k 100 --pull-distance 1 --rates 0.002,0.004 --timestep 1 "
                          "--hold-steps 5000000 --no-plots --out " +
                          out.string();
  const std::string err = (d / "err.txt").string();
  const pid_t pid = pnc::test::spawn(cmd + " 2>" + err);
  ASSERT_TRUE(pnc::test::wait_for_text(err, "pnc thermo persistence: harmonic chain", 60))
      << pnc::test::slurp(err);
  ::usleep(1000 * 1000); // the first rate's LAMMPS child is running
  ::kill(pid, SIGINT);
  const auto e = pnc::test::wait_for(pid, 60);
  ASSERT_TRUE(e.ended) << "still running 60 s after SIGINT";
  const std::string msg = pnc::test::slurp(err);
  EXPECT_EQ(e.code, 128 + SIGINT) << msg;
  const std::string md = pnc::test::slurp((out / "report.md").string());
  const auto banner = md.find("## Did not finish: interrupted by SIGINT");
  ASSERT_NE(banner, std::string::npos) << md << msg;
  EXPECT_LT(banner, md.find("What was run")) << md;
  EXPECT_NE(md.find("Stopped with 0 of 2 bending rates done."), std::string::npos) << md;
  EXPECT_NE(md.find(cmd + " --resume`"), std::string::npos) << md;
  EXPECT_FALSE(fs::exists(out / "persistence.h5"));
  if (!::testing::Test::HasFailure()) fs::remove_all(d);
}

TEST(ThermoCli, TiErrorsNameTheInput) {
  const auto d = tmp("err");
  { std::ofstream(d / "bad.restart") << "not a restart\n"; }
  CmdRun r = run_err("thermo ti --restart " + (d / "bad.restart").string() +
                     " --vol 0 --dev none --points 2 --equil-steps 10 --prod-steps 30 "
                     "--sample-every 10 --blocks 3 --no-plots --out " +
                     (d / "o").string());
  EXPECT_EQ(r.code, 7) << r.out; // LAMMPS refused the file: a tool failure (docs/errors.md)
  EXPECT_NE(r.out.find("pnc: error: LAMMPS failed while running lambda point"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("ERROR"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("read_restart"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(".log)"), std::string::npos) << r.out; // the stage log to read
  r = run_err("thermo ti --restart " + (d / "missing").string() + " --out " + (d / "o2").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("no such LAMMPS restart file"), std::string::npos) << r.out;
  r = run_err("thermo ti --demo --vol 0,0.5 --out " + (d / "o3").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("vol"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0.5"), std::string::npos) << r.out;
}

using pnc::test::tiny_polymer_restart;

// `pnc thermo ti` on a tiny polymer (a reference and one dilated state, 2 Gauss points, short
// sampling): report.html names the command and every Delta A of --json with its standard
// error, embeds both figures, and renders in headless Chromium with every image decoded.
TEST(ThermoCli, TiReportHoldsTheKeyNumbersAndRendersInABrowser) {
  const auto d = tmp("ti_report");
  const std::string rs = tiny_polymer_restart(d);
  const fs::path out = d / "ti";
  const CmdRun r = run("thermo ti --restart " + rs +
                       " --vol 0,0.005 --dev none --points 2 --equil-steps 20 --prod-steps 60 "
                       "--sample-every 10 --blocks 3 --json --out " +
                       out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["report"], (out / "report.html").string());
  const std::string html = report_page(out);
  EXPECT_NE(html.find("pnc thermo ti"), std::string::npos);
  ASSERT_EQ(j["states"].size(), 2u);
  // --json in J of the box (D280), the page in kcal/mol
  const double kcal_mol = 4184.0 / 6.02214076e23; // J
  for (const auto& st : j["states"])
    EXPECT_NE(html.find(pm(st["dA_J"].get<double>() / kcal_mol,
                           st["dA_stderr_J"].get<double>() / kcal_mol)),
              std::string::npos)
        << st["id"];
  // the two PNGs plot_thermo.py drew, embedded (base64 of the PNG signature is iVBORw0KGgo)
  // the CSVs the figures are drawn from: SI names, Delta A of --json in J (12 digits written)
  const auto dA = csv_cells(out / "plots" / "dA.csv");
  ASSERT_EQ(dA.size(), 3u); // header, one row per state (both on the volumetric path)
  EXPECT_EQ(dA[0],
            (std::vector<std::string>{"kind", "strain", "strain_measure", "dA_J", "dA_se_J"}));
  for (std::size_t i = 0; i < 2; ++i) {
    const double want = j["states"][i]["dA_J"].get<double>();
    ASSERT_EQ(dA[i + 1].size(), 5u);
    EXPECT_NEAR(std::stod(dA[i + 1][3]), want, 1e-11 * std::fabs(want)) << i;
  }
  EXPECT_EQ(csv_cells(out / "plots" / "dhdl.csv").at(0),
            (std::vector<std::string>{"state", "lambda", "dhdl_J", "dhdl_se_J"}));
  ASSERT_EQ(j["plots"].size(), 2u) << "python3-matplotlib is a test dependency";
  const std::string img = "src=\"data:image/png;base64,iVBORw0KGgo";
  const auto first = html.find(img);
  ASSERT_NE(first, std::string::npos);
  EXPECT_NE(html.find(img, first + 1), std::string::npos) << "both figures";
  EXPECT_NE(pnc::test::slurp((out / "report.md").string()).find("](plots/dA_vs_strain.png)"),
            std::string::npos);
  const auto b = pnc::test::render_in_chromium((out / "report.html").string(), d.string());
  ASSERT_EQ(b.error, "");
  EXPECT_EQ(b.images, (std::vector<std::string>{"ok", "ok"})) << "the embedded figures decode";
  EXPECT_EQ(b.console, std::vector<std::string>{});
  // not a blank page: the tables and two figures leave ink (an empty or unstyled white page
  // is below 1 % of the 1200 x 3000 screenshot)
  EXPECT_GT(b.ink, 0.02);
  if (!::testing::Test::HasFailure()) fs::remove_all(d); // kept for a look on failure
}
