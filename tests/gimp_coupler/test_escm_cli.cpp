// `pnc gimp couple` end to end (docs/escm.md): the Case I example in short mode, --json on stdout,
// bad input exits with 1 and names the key before LAMMPS starts.
#include "common/declarations_check.hpp"
#include "common/page_check.hpp"
#include "common/run_command.hpp"
#include "common/temp_dir.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {
using Result = pnc::test::CommandResult;
Result sh(const std::string& cmd) {
  return pnc::test::run_command(cmd);
}
/// Point data of an ASCII VTU written by `pnc gimp couple`: name -> values (point-major);
/// "Points" for the coordinates.
std::map<std::string, std::vector<double>> read_vtu(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string s = ss.str();
  std::map<std::string, std::vector<double>> out;
  std::size_t pos = 0;
  while ((pos = s.find("<DataArray", pos)) != std::string::npos) {
    const std::size_t end = s.find('>', pos);
    const std::string tag = s.substr(pos, end - pos);
    std::string name = "Points";
    const std::size_t q = tag.find("Name=\"");
    if (q != std::string::npos) name = tag.substr(q + 6, tag.find('"', q + 6) - q - 6);
    const std::size_t stop = s.find("</DataArray>", end);
    std::istringstream body(s.substr(end + 1, stop - end - 1));
    std::vector<double> v;
    double x;
    while (body >> x)
      v.push_back(x);
    out[name] = v;
    pos = stop;
  }
  return out;
}
} // namespace

// Short mode of examples/escm/case1_lj_tension.json: 24 x 14 cells, block 10 x 10 cells with
// 2 SVC + 1 IVC rings, slab 3 unit cells (12 atoms per cell): the zone counts follow from the
// geometry (INT 4 x 4, IVC ring 6 x 6 - 4 x 4, SVC 10 x 10 - 6 x 6 cells). The left reaction
// after the damped hold is the strip's static force (C11 - C12^2/C11) eps H within 10 % (the
// hold is only ~3 decay times of the fundamental mode and the coupled stiffness differs from
// the continuum's by ~5 %, escm.LjCrystalTensionMatchesContinuum).
TEST(EscmCli, ShortCaseOneRunsWithJson) {
  const fs::path d = pnc::test::fresh_dir("escm_cli");
  const std::string in = std::string(PNC_SOURCE_DIR) + "/examples/escm/case1_lj_tension.json";
  const Result r = sh(std::string(PNC_EXE) + " gimp couple " + in + " --out " +
                      (d / "out").string() + " --short --json --quiet --no-plot 2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["atoms"]["interior"], 16 * 12);
  EXPECT_EQ(j["atoms"]["ivc"], 20 * 12);
  EXPECT_EQ(j["atoms"]["svc"], 64 * 12);
  const double F = j["reaction_left_N_per_m"].get<double>();
  const double F0 = j["expected_reaction_N_per_m"].get<double>();
  EXPECT_NEAR(F / F0, 1.0, 0.10);
  EXPECT_TRUE(fs::exists(d / "out" / "energy.csv"));
  EXPECT_TRUE(fs::exists(d / "out" / "profile.csv"));
  EXPECT_EQ(j["frames"].size(), 3u);
  // the run report: the command, the reaction in N/m, the relative energy error |balance -
  // created| / max(|W_bc|, |created|) (created = the handshake's works) against its 15 %
  // threshold (D271), no figures
  const auto& e = j["energy_J"];
  const double created = e["work_cont_on_md"].get<double>() + e["work_md_on_cont"].get<double>();
  const double rel = std::fabs(e["balance"].get<double>() - created) /
                     std::max(std::fabs(e["work_boundary"].get<double>()), std::fabs(created));
  EXPECT_NEAR(j["relative_energy_error"].get<double>(), rel, 1e-12 * rel);
  EXPECT_EQ(j["report"], (d / "out" / "report.html").string());
  const std::string html = pnc::test::slurp((d / "out" / "report.html").string());
  EXPECT_EQ(pnc::test::self_contained_problems(html), std::vector<std::string>{});
  EXPECT_TRUE(fs::exists(d / "out" / "report.md"));
  EXPECT_NE(html.find("pnc gimp couple: case1_lj_tension.json"), std::string::npos);
  EXPECT_NE(html.find(fmt::format("{:.6g} N/m", F)), std::string::npos);
  EXPECT_NE(html.find(fmt::format("{:.3g} % (threshold 15 %", 100 * rel)), std::string::npos);
  EXPECT_EQ(html.find("above the threshold") != std::string::npos, rel > 0.15);
  // the tension test measures this error at 9 % (docs/escm.md): the short run stays below 15 %
  EXPECT_LT(rel, 0.15);
  EXPECT_NE(html.find("Not drawn (--no-plot)."), std::string::npos);
}

// Stopped by --max-steps (exit 0, a checkpoint, no summary.json): the folder still has a
// report whose first block says the run did not finish, why, after which coupled step (time
// in ps), what is valid and the command that continues it.
TEST(EscmCli, MaxStepsStopLeavesAReportWithTheResumeCommand) {
  const fs::path d = pnc::test::fresh_dir("escm_cli_stop");
  const std::string in = std::string(PNC_SOURCE_DIR) + "/examples/escm/case1_lj_tension.json";
  const std::string cmd = std::string(PNC_EXE) + " gimp couple " + in + " --out " +
                          (d / "out").string() + " --short --quiet --no-plot --max-steps 20";
  const Result r = sh(cmd + " 2>&1");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_FALSE(fs::exists(d / "out" / "summary.json"));
  EXPECT_NE(r.out.find("report (stopped early): " + (d / "out" / "report.html").string()),
            std::string::npos)
      << r.out;
  const std::string md = pnc::test::slurp((d / "out" / "report.md").string());
  const auto banner = md.find("## Did not finish: --max-steps (20) reached");
  ASSERT_NE(banner, std::string::npos) << md;
  EXPECT_LT(banner, md.find("What was run")) << md;
  EXPECT_NE(md.find("Stopped after coupled step 20 at t = "), std::string::npos) << md;
  EXPECT_NE(md.find(" ps."), std::string::npos) << md;
  EXPECT_NE(md.find("`checkpoint.h5`: the whole state after step 20"), std::string::npos) << md;
  EXPECT_NE(md.find("`energy.csv`"), std::string::npos) << md;
  EXPECT_NE(md.find(cmd + " --resume`"), std::string::npos) << md;
  const std::string html = pnc::test::slurp((d / "out" / "report.html").string());
  EXPECT_EQ(pnc::test::self_contained_problems(html), std::vector<std::string>{});
  if (!::testing::Test::HasFailure()) fs::remove_all(d);
}

TEST(EscmCli, BadInputExitsWithOneAndNamesTheKey) {
  const fs::path d = pnc::test::fresh_dir("escm_cli_bad");
  {
    std::ofstream f(d / "bad.json");
    f << R"({"cells": [40, 20], "substeps": 0})";
  }
  Result r = sh(std::string(PNC_EXE) + " gimp couple " + (d / "bad.json").string() + " --out " +
                (d / "out").string() + " 2>&1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("substeps"), std::string::npos) << r.out;
  {
    std::ofstream f(d / "bad2.json");
    f << R"({"cells": [40, 20], "strian": 0.01})";
  }
  r = sh(std::string(PNC_EXE) + " gimp couple " + (d / "bad2.json").string() + " --out " +
         (d / "out").string() + " 2>&1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("strian"), std::string::npos) << r.out;
  {
    std::ofstream f(d / "bad3.json");
    f << R"({"cells": [40, 20], "gradient_spacing_cells": 0.1})";
  }
  r = sh(std::string(PNC_EXE) + " gimp couple " + (d / "bad3.json").string() + " --out " +
         (d / "out").string() + " 2>&1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("gradient_spacing_cells"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[0.5, 10]"), std::string::npos) << r.out;
}

// `pnc gimp couple-parameters` prints the declared keys of the couple input (D294): JSON with
// every section and entry (the rules derived from the declared ranges and units), Markdown
// tables (the generated region of docs/escm.md) and the TOML list of the defaults.
TEST(EscmCli, CoupleParametersPrintsTheDeclarations) {
  const std::string cmd = std::string(PNC_EXE) + " gimp couple-parameters";
  const auto rules = pnc::test::declared_rules(cmd);
  EXPECT_EQ(rules.at("md_timestep_fs"), "must be a number in [0.0001, 20] fs");
  EXPECT_EQ(rules.at("crack.Gc"), "must be a number in (0, 1000) J/m^2");
  EXPECT_EQ(rules.at("lj.epsilon"), "must be a number > 0 kcal/mol");
  EXPECT_EQ(rules.at("md.density"), "must be a number in [0.05, 3] g/cm^3");
  EXPECT_EQ(rules.count("md.forcefield.cutoff_sigma"), 1u);
  pnc::test::expect_prints(cmd, "#### `md.forcefield`");
  pnc::test::expect_prints(cmd + " --format toml", "\nsubsteps = 20\n");
  EXPECT_NE(sh(cmd + " --format yaml 2>&1").code, 0);
}

// The MD region kinds come from a registry keyed by md.type (docs/escm.md "Code layout",
// D201): an unknown kind is an input error at md.type that names the value and lists the kinds
// this build registered (the LJ crystal always; the polymer when rve/ is built).
TEST(EscmCli, UnknownMdRegionKindListsTheKnownOnes) {
  const fs::path d = pnc::test::fresh_dir("escm_cli_kind");
  {
    std::ofstream f(d / "kind.json");
    f << R"({"md": {"type": "nanotube"}})";
  }
  const Result r = sh(std::string(PNC_EXE) + " gimp couple " + (d / "kind.json").string() +
                      " --out " + (d / "out").string() + " 2>&1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("field 'md.type'"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("nanotube"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"lj\""), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(d / "out" / "lammps.log")) << "refused before LAMMPS starts";
  fs::remove_all(d);
}

// Validation (3) of the displacement gradients (docs/theory.md §6.3, D79) in the short Case I run
// (24 x 14 cells, block 10 x 10 at cell 7, strain 0.2 %): the mean du/dX over the ordinary
// continuum particles at least 2 cells away from the atom block (x < 5 h or x > 19 h, read
// from the last particles_<k>.vtu), with all grid nodes of their element supported, against
// the applied strain eps = (right-edge displacement) / L. The far field is not at exactly eps:
// the coupled block is ~5 % softer than the continuum (escm.LjCrystalTensionMatchesContinuum)
// and strains more, so the columns outside it strain less. The tolerance is derived from the
// run's raw displacements, without any gradient: eps_far = least-squares slope of u_x against
// X over the same regions (left and right, separately, pooled by count), and
// tol = |eps_far - eps| + 3 s / sqrt(n) (s: standard deviation of du/dX over the n particles)
// + 1e-2 eps (the two estimates weight the particles differently across the residual
// profile; 1 % of eps). Measured: 96 particles, mean 1.892e-3 (sd 7.8e-5),
// eps_far 1.872e-3, |mean - eps| = 1.08e-4 <= tol 1.72e-4. Also the post-processed du/dX of
// the far particles against the GIMP solver's own F_11 - 1 there (F_solver, a different
// gradient route, 1.902e-3): 0.5 %, bound 2 %.
TEST(EscmCli, ShortCaseOneGradientMatchesAppliedStrain) {
  const fs::path d = pnc::test::fresh_dir("escm_cli_grad");
  const std::string in = std::string(PNC_SOURCE_DIR) + "/examples/escm/case1_lj_tension.json";
  const Result r = sh(std::string(PNC_EXE) + " gimp couple " + in + " --out " +
                      (d / "out").string() + " --short --json --quiet --no-plot 2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  nlohmann::json input;
  std::ifstream(in) >> input;
  const double eps = input["short"]["strain"].get<double>();
  const double h = j["lj_fcc"]["a0_m"].get<double>();
  ASSERT_EQ(j["particle_frames"].size(), 3u);
  EXPECT_EQ(j["gradient"]["increments"].get<long>(), j["steps"].get<long>());
  const auto v = read_vtu(j["particle_frames"].back().get<std::string>());
  const auto& P = v.at("Points");
  const auto& U = v.at("displacement_m");
  const auto& Z = v.at("zone_index");
  const auto& S = v.at("gradient_supported_1");
  const auto& H = v.at("displacement_gradient_1"); // 9 components, row-major (D236)
  const auto& F = v.at("deformation_gradient_solver_1");
  const std::size_t n = Z.size();
  ASSERT_EQ(H.size(), 9 * n);
  ASSERT_EQ(F.size(), 9 * n);
  double sum = 0, sum2 = 0, sumF = 0;
  std::size_t m = 0;
  double slope_w = 0;
  std::size_t slope_n = 0;
  for (int side = 0; side < 2; ++side) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    std::size_t k = 0;
    for (std::size_t p = 0; p < n; ++p) {
      const double X = P[3 * p] - U[3 * p];
      const bool far = side == 0 ? X < 5 * h : X > 19 * h;
      if (Z[p] != -1 || !far) continue;
      sx += X;
      sy += U[3 * p];
      sxx += X * X;
      sxy += X * U[3 * p];
      ++k;
      if (S[p] != 1) continue;
      sum += H[9 * p];
      sum2 += H[9 * p] * H[9 * p];
      sumF += F[9 * p] - 1;
      ++m;
    }
    ASSERT_GT(k, 10u);
    const double kk = static_cast<double>(k);
    slope_w += kk * (kk * sxy - sx * sy) / (kk * sxx - sx * sx);
    slope_n += k;
  }
  ASSERT_GT(m, 40u);
  const double mm = static_cast<double>(m);
  const double mean = sum / mm, sd = std::sqrt(std::max(0.0, sum2 / mm - mean * mean));
  const double eps_far = slope_w / static_cast<double>(slope_n);
  const double tol = std::abs(eps_far - eps) + 3 * sd / std::sqrt(mm) + 1e-2 * eps;
  std::printf("far field (%zu particles): mean du/dX %.5e (sd %.2e), solver F11-1 %.5e; applied "
              "eps %.5e; displacement slope %.5e; tol %.3e\n",
              m, mean, sd, sumF / mm, eps, eps_far, tol);
  EXPECT_NEAR(mean, eps, tol);
  EXPECT_NEAR(mean / (sumF / mm), 1.0, 0.02);
}
