// pnc characterize interrupted (app/run_control.hpp, md/stage_stop.hpp): SIGINT to the parent
// alone stops it while its case children run: they end too (no orphan keeps the run directory's
// lock), the exit code is 128 + SIGINT with one line naming the command that continues the run,
// every finished strain step stays in the case checkpoints, and --resume continues from them
// without recomputing them.
#include "common/run_command.hpp"
#include "common/spawn.hpp"
#include "common/temp_dir.hpp"

#include "pnc/rve/deform.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using pnc::test::slurp;

namespace {
// The tiny recipe of test_characterize_cli.cpp with more strain steps, so that the cases run
// for a few seconds.
const char* tiny_long = R"({
  "name": "tiny", "seed": 3,
  "build": { "chains": 8 },
  "equilibrate": { "pushoff_steps": 500, "hot_steps": 1000, "cool_steps": 500,
                   "langevin_chunk_steps": 200, "langevin_max_chunks": 2,
                   "npt_steps": 1000, "final_steps": 200 },
  "deform": { "cases": [2, 6], "strain_max": 0.06, "steps": 12, "timestep_fs": 1.0,
              "hold_steps": 400, "sample_every": 10, "blocks": 4, "reference_holds": 1 },
  "analysis": { "moving_average": 1 },
  "run": { "jobs": 2 }
})";
} // namespace

TEST(RveCharacterizeStop, SigintStopsTheCasesAndResumeContinuesTheirCheckpoints) {
  const auto d = pnc::test::fresh_dir("test_rve_char_stop");
  std::ofstream(d / "tiny.json") << tiny_long;
  const std::string out = (d / "out").string();
  const std::string cmd = std::string(PNC_EXE) + " characterize " + (d / "tiny.json").string() +
                          " --out " + out + " --no-plots";
  const std::string err = (d / "err.txt").string();
  const pid_t pid = pnc::test::spawn(cmd + " 2>" + err);
  // a case child has written a checkpoint after its first strain step
  ASSERT_TRUE(pnc::test::wait_for_text(err, "case 2 deformation: 2/13 strain points", 60))
      << slurp(err);
  ::kill(pid, SIGINT); // the parent only: it must stop its children itself
  const auto e = pnc::test::wait_for(pid, 30);
  ASSERT_TRUE(e.ended) << "still running 30 s after SIGINT";
  const std::string msg = slurp(err);
  EXPECT_EQ(e.code, 128 + SIGINT) << msg;
  EXPECT_NE(msg.find("pnc: interrupted by SIGINT"), std::string::npos) << msg;
  EXPECT_NE(msg.find("continue with: " + cmd + " --resume"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(fs::path(out) / "cases.h5")) << "stopped before the end";
  // the run folder still has a report that says first why and where it stopped, what is kept,
  // and how to continue (app/stopped_report.hpp)
  const std::string md = slurp(out + "/report.md");
  const auto banner = md.find("Did not finish: interrupted by SIGINT");
  ASSERT_NE(banner, std::string::npos) << md;
  EXPECT_LT(banner, md.find("What was run")) << md;
  EXPECT_NE(md.find("units done; not finished: "), std::string::npos) << md;
  EXPECT_NE(md.find("unit `replica_1/equilibrate` (done)"), std::string::npos) << md;
  EXPECT_NE(md.find(cmd + " --resume`"), std::string::npos) << md;
  const pnc::rve::CaseResult at_stop = pnc::rve::read_case(out + "/cases/case_2");
  ASSERT_GE(at_stop.rows_done, 2);
  ASSERT_LT(at_stop.rows_done, 13) << "the case finished before the signal";

  // no orphan stage holds the directory: the resume is accepted at once, and continues
  const std::string err2 = (d / "err2.txt").string();
  const auto r = pnc::test::run_command(cmd + " --resume 2>" + err2);
  ASSERT_TRUE(r.code == 0 || r.code == 3 || r.code == 4) << r.code << " " << slurp(err2);
  EXPECT_NE(slurp(err2).find("[case 2] resuming after step"), std::string::npos) << slurp(err2);
  const pnc::rve::CaseResult done = pnc::rve::read_case(out + "/cases/case_2");
  EXPECT_EQ(done.rows_done, 13);
  // the steps finished before the signal are kept as they were, not recomputed
  for (int k = 0; k < at_stop.rows_done; ++k) {
    EXPECT_EQ(done.strain.row(k), at_stop.strain.row(k)) << k;
    EXPECT_EQ(done.stress_virial.row(k), at_stop.stress_virial.row(k)) << k;
  }
  EXPECT_TRUE(fs::exists(fs::path(out) / "cases.h5"));
  EXPECT_EQ(slurp(out + "/report.md").find("Did not finish"), std::string::npos)
      << "the finished run's report replaces the stopped one";
  fs::remove_all(d);
}
