// `pnc thermo ti` on a glass run (model kg, D393) and the refusal of a start state whose pair
// style it would drop (a Coulomb pair with its kspace partner, D394), end to end.
#include "common/run_command.hpp"
#include "common/temp_dir.hpp"

#include "pnc/md/lammps_path.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/rve/bead_spring.hpp"
#include "pnc/rve/recipe.hpp"
#include "pnc/thermo/ti.hpp"

#include <fmt/format.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {

pnc::test::CommandResult run_err(const std::string& args) { // stderr only
  return pnc::test::run_command(std::string(PNC_EXE) + " " + args + " 2>&1 >/dev/null");
}

fs::path tmp(const std::string& tag) {
  return pnc::test::fresh_dir("test_ti_glass_" + tag);
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream f(p);
  return nlohmann::json::parse(f);
}

// A glass force field unlike both the PP one and the model's defaults, so that neither
// default path can end on it by accident.
pnc::rve::BeadSpringForceField odd_glass() {
  pnc::rve::BeadSpringForceField ff;
  ff.sigma = 4.0;
  ff.epsilon = 0.6;
  ff.cutoff_sigma = 2.2;
  return ff;
}

/// A `pnc characterize`-like run folder of model kg with `ff`: recipe.json (the demo_glass preset
/// with that force field, temperature 90 K) and equilibrate/final.restart (60 beads, minimised).
/// Returns the LJ pair energy LAMMPS computes for the restart's configuration with the glass's
/// own commands (kcal/mol).
double glass_run_folder(const fs::path& run, const pnc::rve::BeadSpringForceField& ff) {
  nlohmann::json r = pnc::rve::preset_json("demo_glass");
  r["forcefield"]["sigma"] = ff.sigma;
  r["forcefield"]["epsilon"] = ff.epsilon;
  r["forcefield"]["cutoff_sigma"] = ff.cutoff_sigma;
  r["equilibrate"]["temperature"] = 90.0;
  fs::create_directories(run / "equilibrate");
  std::ofstream(run / "recipe.json") << r.dump(2);
  pnc::md::BuildSpec b;
  b.chains = 6;
  b.beads_per_chain = 10;
  b.density = 0.9;
  b.min_distance = 3.0;
  const std::string data = (run / "glass.data").string();
  const std::string rs = (run / "equilibrate" / "final.restart").string();
  pnc::md::write_data_file(data, pnc::rve::build_bead_spring(b, ff), "ti glass test");
  double evdwl = std::nan("");
  const auto o =
      pnc::md::run_stage({"prep", (run / "prep.log").string(), {}}, [&](pnc::md::Lammps& l) {
        l.cmd("units real");
        l.cmd("atom_style molecular");
        l.cmd("read_data " + pnc::md::lammps_path(data, "data"));
        l.cmds(pnc::rve::bead_spring_commands(ff));
        l.cmd("minimize 1e-4 1e-6 100 1000");
        l.cmd("write_restart " + pnc::md::lammps_path(rs, "restart"));
        l.cmd("run 0");
        std::ofstream(run / "evdwl.txt") << fmt::format("{:.17g}\n", l.thermo("evdwl"));
      });
  if (!o.ok) throw std::runtime_error(o.error);
  std::ifstream(run / "evdwl.txt") >> evdwl;
  return evdwl;
}

} // namespace

// D393: without path keys, lambda = 1 is the glass's own pair (eps, sigma, cut-off of its recipe)
// and the TI runs at the glass's temperature; lambda = 0 keeps the dissertation's ratios. The
// pair energy the lambda = 1 point reads on the start configuration (no equilibration) is the one
// LAMMPS gives with the glass's own force-field commands: same pairs, same numbers, to round-off.
TEST(ThermoTiGlass, LambdaOneIsTheGlassPairAtTheGlassTemperature) {
  const auto d = tmp("end");
  const auto ff = odd_glass();
  const double evdwl = glass_run_folder(d / "run", ff);
  const auto out = d / "ti";
  const auto r = run_err("thermo ti --from " + (d / "run").string() + " --out " + out.string() +
                         " --vol 0 --dev none --rule trapezoid --points 2 --equil-steps 0 "
                         "--prod-steps 30 --sample-every 10 --blocks 3 --timestep 1 --no-plots");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto s = read_json(out / "ti_spec.json");
  EXPECT_DOUBLE_EQ(s["eps1_kcal_mol"].get<double>(), ff.epsilon);
  EXPECT_DOUBLE_EQ(s["sig1_A"].get<double>(), ff.sigma);
  EXPECT_DOUBLE_EQ(s["cutoff_A"].get<double>(), ff.cutoff());
  EXPECT_NEAR(s["eps0_kcal_mol"].get<double>(), ff.epsilon * 0.1, 1e-15);
  EXPECT_NEAR(s["sig0_A"].get<double>(), ff.sigma * 0.95 / 2.95, 1e-14);
  EXPECT_DOUBLE_EQ(s["temperature_K"].get<double>(), 90.0);
  ASSERT_TRUE(std::isfinite(evdwl));
  ASSERT_LT(evdwl, 0) << "the minimised glass must have cohesive LJ energy";
  // the lambda = 1 point's check: LAMMPS's evdwl after `run 0` on the start configuration
  const auto h5 = out / "ref" / "lambda_1.h5";
  ASSERT_TRUE(fs::exists(h5));
  const pnc::thermo::PointResult pt = pnc::thermo::read_point(h5.string());
  ASSERT_DOUBLE_EQ(pt.lambda, 1.0);
  const double u1 = pt.checks.at("u_lammps");
  EXPECT_NEAR(u1, evdwl, 1e-9 * std::fabs(evdwl));
  if (!::testing::Test::HasFailure()) fs::remove_all(d);
}

// D393: a path key that would end the TI on another system than the glass is refused before
// anything runs, naming the key, the value, the glass's value and the recipe.
TEST(ThermoTiGlass, AnEndOtherThanTheGlassIsRefused) {
  const auto d = tmp("bad_end");
  const auto ff = odd_glass();
  fs::create_directories(d / "run" / "equilibrate");
  nlohmann::json rj = pnc::rve::preset_json("demo_glass");
  rj["forcefield"]["sigma"] = ff.sigma;
  std::ofstream(d / "run" / "recipe.json") << rj.dump(2);
  std::ofstream(d / "run" / "equilibrate" / "final.restart") << "never read\n";
  const auto r = run_err("thermo ti --from " + (d / "run").string() + " --sig1 2.95 --out " +
                         (d / "ti").string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("sig1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2.95"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("own value 4 A"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("recipe.json"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("D393"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(d / "ti" / "ti_spec.json"));
  if (!::testing::Test::HasFailure()) fs::remove_all(d);
}

// D394: a start state with a Coulomb pair and a kspace partner (the restart of a small charged LJ
// system) is refused by the restart check, before any lambda point runs: the message names the
// restart file, LAMMPS's pair style and the rule; no state folder or spec is written.
TEST(ThermoTiGlass, ACoulombPairWithKspaceIsRefusedBeforeAnyPointRuns) {
  const auto d = tmp("coul");
  const std::string rs = (d / "charged.restart").string();
  const auto o =
      pnc::md::run_stage({"charged", (d / "charged.log").string(), {}}, [&](pnc::md::Lammps& l) {
        l.cmd("units real");
        l.cmd("atom_style full");
        l.cmd("region b block 0 20 0 20 0 20");
        l.cmd("create_box 2 b");
        l.cmd("create_atoms 1 random 10 11 NULL");
        l.cmd("create_atoms 2 random 10 12 NULL");
        l.cmd("mass * 39.9");
        l.cmd("set type 1 charge 0.5");
        l.cmd("set type 2 charge -0.5");
        l.cmd("pair_style lj/cut/coul/long 8.0");
        l.cmd("pair_coeff * * 0.238 3.405");
        l.cmd("kspace_style pppm 1e-4");
        l.cmd("run 0");
        l.cmd("write_restart " + pnc::md::lammps_path(rs, "restart"));
      });
  ASSERT_TRUE(o.ok) << o.error;
  const auto r = run_err("thermo ti --restart " + rs + " --vol 0 --dev none --points 2 " +
                         "--equil-steps 10 --prod-steps 30 --sample-every 10 --blocks 3 " +
                         "--no-plots --out " + (d / "ti").string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find(rs), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("pair_style"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("lj/cut/coul/long"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("kspace"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("D394"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(d / "ti" / "ref")) << "a lambda point ran";
  EXPECT_FALSE(fs::exists(d / "ti" / "ti_spec.json"));
  if (!::testing::Test::HasFailure()) fs::remove_all(d);
}

// D394: `--from` a run of your own charged system (recipe "system" with lj/cut/coul/long and a
// kspace_style) is refused naming the recipe, the Coulomb command and the system's file, before
// LAMMPS is started.
TEST(ThermoTiGlass, YourOwnSystemWithKspaceIsRefusedNamingTheCommand) {
  const auto d = tmp("user_coul");
  const auto run = d / "run";
  fs::create_directories(run / "equilibrate");
  std::ofstream(run / "q.data") << "never read by thermo ti\n";
  std::ofstream(run / "equilibrate" / "final.restart") << "never read\n";
  const nlohmann::json recipe = {
      {"name", "charged"},
      {"model", "pp"},
      {"system",
       {{"data_file", "q.data"},
        {"atom_style", "charge"},
        {"units", "real"},
        {"forcefield",
         {"pair_style lj/cut/coul/long 8.5", "pair_coeff * * 0.2381 3.405", "mass 1 39.948",
          "kspace_style pppm 1e-4"}}}},
      {"equilibrate", {{"stages", nlohmann::json::array()}}}};
  std::ofstream(run / "recipe.json") << recipe.dump(2);
  const auto r = run_err("thermo ti --from " + run.string() + " --out " + (d / "ti").string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find((run / "recipe.json").string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("pair_style lj/cut/coul/long 8.5"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("kspace"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("q.data"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("D394"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(d / "ti" / "restart_check.log")) << "LAMMPS was started";
  if (!::testing::Test::HasFailure()) fs::remove_all(d);
}
