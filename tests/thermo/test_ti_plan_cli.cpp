// `pnc thermo ti` as a plan of units (decisions D285-D287, docs/thermo.md): one unit per
// (state, lambda node) and the join unit `analysis`, run by the local executor; `pnc status`
// and `pnc run-unit` on its run folder; --resume reruns only what is missing.
#include "common/page_check.hpp"
#include "common/run_command.hpp"
#include "common/spawn.hpp"
#include "common/temp_dir.hpp"

#include "pnc/core/hdf5_io.hpp"
#include "pnc/md/forcefield.hpp"
#include "pnc/thermo/ti.hpp"

#include "tiny_polymer.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <map>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

pnc::test::CommandResult pnc_run(const std::string& args, const fs::path& err) {
  return pnc::test::run_command(std::string(PNC_EXE) + " " + args + " 2>" + err.string());
}

nlohmann::json status_of(const fs::path& dir) {
  const auto s = pnc::test::run_command(std::string(PNC_EXE) + " status " + dir.string() +
                                        " --json 2>/dev/null");
  return nlohmann::json::parse(s.out, nullptr, false);
}

/// The numbers of ti.h5 per state: dA, its standard error, then <dH/dl> and its standard
/// error at every node (kcal/mol).
std::map<std::string, std::vector<double>> ti_numbers(const fs::path& h5) {
  pnc::h5::File f(h5.string(), pnc::h5::File::Mode::read);
  std::map<std::string, std::vector<double>> m;
  for (const auto& id : f.children("/states")) {
    const std::string g = "/states/" + id;
    auto& v = m[id];
    v = {f.read_scalar(g + "/dA"), f.read_scalar(g + "/dA_stderr")};
    for (const char* n : {"/dhdl_mean", "/dhdl_stderr"})
      for (double x : f.read_vector(g + n))
        v.push_back(x);
  }
  return m;
}

std::map<std::string, nlohmann::json> units_by_id(const nlohmann::json& st) {
  std::map<std::string, nlohmann::json> m;
  for (const auto& u : st["units"])
    m[u["unit"].get<std::string>()] = u;
  return m;
}

} // namespace

// The tiny TI of the report test (tiny polymer, a reference and one dilated state, 2 Gauss
// nodes, short sampling) through the plan equals thermo::run_ti, the library's loop over the
// same points with the same seeds: same LAMMPS, same inputs, one rank per point, so the numbers
// agree to round-off (relative 1e-12; a different seed or node would differ by the sampling
// error, percent level). pnc status lists 4 point units and the analysis, all done. Without a
// node's file the analysis fails naming that unit; --resume then reruns that point only and
// gives the same numbers again.
TEST(ThermoTiPlan, LocalPlanEqualsRunTiAndResumeRerunsOnlyTheMissingNode) {
  const auto d = pnc::test::fresh_dir("test_ti_plan");
  const std::string rs = pnc::test::tiny_polymer_restart(d);
  const fs::path out = d / "plan";
  const std::string args = "thermo ti --restart " + rs +
                           " --vol 0,0.005 --dev none --points 2 --equil-steps 20 --prod-steps 60 "
                           "--sample-every 10 --blocks 3 --no-plots --jobs 2 --out " +
                           out.string();
  const auto r1 = pnc_run(args, d / "run1.err");
  ASSERT_EQ(r1.code, 0) << pnc::test::slurp((d / "run1.err").string());
  const auto n1 = ti_numbers(out / "ti.h5");

  pnc::thermo::TiSpec spec;
  spec.vol = {0, 0.005};
  spec.dev = {};
  spec.points = 2;
  spec.sampling.equil_steps = 20;
  spec.sampling.prod_steps = 60;
  spec.sampling.sample_every = 10;
  spec.sampling.blocks = 3;
  const auto lib = pnc::thermo::run_ti(spec, rs, pnc::md::polymer_forcefield_commands({}),
                                       (d / "lib").string(), false, "", nullptr);
  const auto nl = ti_numbers(lib.h5);
  ASSERT_EQ(n1.size(), 2u);
  ASSERT_EQ(nl.size(), 2u);
  for (const auto& [id, v] : nl) {
    ASSERT_TRUE(n1.count(id)) << id;
    ASSERT_EQ(n1.at(id).size(), 6u) << id; // dA, se, 2 node means, 2 node errors
    ASSERT_EQ(v.size(), n1.at(id).size()) << id;
    for (std::size_t i = 0; i < v.size(); ++i)
      EXPECT_NEAR(n1.at(id)[i], v[i], 1e-12 * std::fabs(v[i])) << id << " value " << i;
  }
  EXPECT_TRUE(fs::exists(out / "ti.h5"));
  EXPECT_TRUE(fs::exists(out / "report.html"));

  // pnc status: the 4 points and the analysis, done
  const auto st1 = status_of(out);
  ASSERT_TRUE(st1.is_object());
  auto u1 = units_by_id(st1);
  const std::vector<std::string> ids = {"ref/lambda_0", "ref/lambda_1", "vol_0p005/lambda_0",
                                        "vol_0p005/lambda_1", "analysis"};
  ASSERT_EQ(u1.size(), ids.size());
  for (const auto& id : ids) {
    ASSERT_TRUE(u1.count(id)) << id;
    EXPECT_EQ(u1[id]["state"], "done") << u1[id].dump();
  }
  EXPECT_EQ(u1["analysis"]["kind"], "analysis");
  EXPECT_EQ(u1["analysis"]["needs"].size(), 4u);

  // a node's file gone: the analysis names the unit that is missing
  fs::remove(out / "vol_0.005" / "lambda_1.h5");
  fs::remove(out / "state" / "analysis.json");
  const auto an = pnc_run("run-unit " + out.string() + " analysis", d / "analysis.err");
  EXPECT_EQ(an.code, 1);
  const auto a2 = units_by_id(status_of(out))["analysis"];
  EXPECT_EQ(a2["state"], "failed");
  EXPECT_NE(a2["message"].get<std::string>().find("vol_0p005/lambda_1"), std::string::npos)
      << a2.dump();

  // --resume: that point runs again, the other three are reused; same numbers
  const auto r2 = pnc_run(args + " --resume", d / "run2.err");
  ASSERT_EQ(r2.code, 0) << pnc::test::slurp((d / "run2.err").string());
  auto u2 = units_by_id(status_of(out));
  for (const auto& id : ids) {
    EXPECT_EQ(u2[id]["state"], "done") << u2[id].dump();
    const double s1 = u1[id]["started_s"].get<double>(), s2 = u2[id]["started_s"].get<double>();
    if (id == "vol_0p005/lambda_1" || id == "analysis")
      EXPECT_GT(s2, s1) << id << " ran again";
    else
      EXPECT_EQ(s2, s1) << id << " was not rerun";
  }
  EXPECT_EQ(ti_numbers(out / "ti.h5"), n1); // the rerun point has the same seed: same samples
  if (!::testing::Test::HasFailure()) fs::remove_all(d);
}

// SIGINT while the lambda points run: exit 128 + SIGINT as every long command, and the run
// folder has a report whose first block says the TI did not finish, why, how many units are
// done out of the five, which are not finished, and the command that continues it
// (app/stopped_report.hpp). The points sample long enough (10^5 steps each) to be running.
TEST(ThermoTiPlan, SigintLeavesAReportSayingWhatIsDoneAndHowToResume) {
  const auto d = pnc::test::fresh_dir("test_ti_stop");
  const std::string rs = pnc::test::tiny_polymer_restart(d);
  const fs::path out = d / "plan";
  const std::string cmd = std::string(PNC_EXE) + " thermo ti --restart " + rs +
                          " --vol 0,0.005 --dev none --points 2 --equil-steps 20 --prod-steps "
                          "100000 --sample-every 10 --blocks 3 --no-plots --jobs 2 --out " +
                          out.string();
  const std::string err = (d / "err.txt").string();
  const pid_t pid = pnc::test::spawn(cmd + " 2>" + err);
  ASSERT_TRUE(pnc::test::wait_for_text(err, "unit(s), 2 at a time", 60)) << pnc::test::slurp(err);
  ::usleep(1500 * 1000); // the first two points are running
  ::kill(pid, SIGINT);
  const auto e = pnc::test::wait_for(pid, 60);
  ASSERT_TRUE(e.ended) << "still running 60 s after SIGINT";
  const std::string msg = pnc::test::slurp(err);
  EXPECT_EQ(e.code, 128 + SIGINT) << msg;
  EXPECT_NE(msg.find("pnc: interrupted by SIGINT"), std::string::npos) << msg;
  EXPECT_NE(msg.find("report (stopped early): " + (out / "report.html").string()),
            std::string::npos)
      << msg;
  const std::string md = pnc::test::slurp((out / "report.md").string());
  const auto banner = md.find("## Did not finish: interrupted by SIGINT");
  ASSERT_NE(banner, std::string::npos) << md;
  EXPECT_LT(banner, md.find("What was run")) << md;
  EXPECT_NE(md.find(" of 5 units done"), std::string::npos) << md;
  EXPECT_NE(md.find("not finished: "), std::string::npos) << md;
  EXPECT_NE(md.find("analysis"), std::string::npos) << "the analysis did not run\n" << md;
  EXPECT_NE(md.find(cmd + " --resume`"), std::string::npos) << md;
  EXPECT_FALSE(fs::exists(out / "ti.h5"));
  if (!::testing::Test::HasFailure()) fs::remove_all(d);
}
