// The `pnc thermo` subcommands end to end on tiny inputs: outputs, --json, --resume, and
// errors that name the input (a LAMMPS error with LAMMPS's message).
#include "common/run_command.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {
using CmdRun = pnc::test::CommandResult;
CmdRun run(const std::string& args) {
  return pnc::test::run_command(std::string(PNC_EXE) + " " + args + " 2>/dev/null");
}
CmdRun run_err(const std::string& args) { // stderr only
  return pnc::test::run_command(std::string(PNC_EXE) + " " + args + " 2>&1 >/dev/null");
}
fs::path tmp(const std::string& tag) {
  const auto d = fs::temp_directory_path() / ("pnc_test_thermo_cli_" + tag);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
} // namespace

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
  // xi_p = EI0 / kT at 300 K (kB in kcal/mol/K)
  EXPECT_NEAR(j["xi_p_A"].get<double>(), j["EI0_kcal_mol_A"].get<double>() / (0.0019872067 * 300),
              1e-6);
  // 2 K l0 with K = 500 and l0 = 1.53
  EXPECT_NEAR(j["expected_EI_continuum_kcal_mol_A"].get<double>(), 1530.0, 1e-9);
  const auto t = fs::last_write_time(d / "rate_0.h5");
  const CmdRun r2 = run(args + " --resume");
  ASSERT_EQ(r2.code, 0);
  EXPECT_EQ(fs::last_write_time(d / "rate_0.h5"), t);
  EXPECT_EQ(nlohmann::json::parse(r2.out)["EI0_kcal_mol_A"], j["EI0_kcal_mol_A"]);
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
