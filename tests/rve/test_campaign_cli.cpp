// The commands on a plan of units (pnc run-unit, pnc status, pnc characterize --executor slurm
// without a cluster), the recipe's "slurm" section and the Slurm peer check of the stage
// channel (decisions D244, D245, D300, D332). The plan layer itself is tested in
// tests/campaign/test_campaign.cpp, the runs through a real Slurm cluster in test_slurm_cli.cpp.
#include "pnc/campaign/campaign.hpp"
#include "pnc/md/private_channel.hpp"
#include "pnc/rve/recipe.hpp"

#include "common/run_command.hpp"
#include "common/slurm_stand_ins.hpp"
#include "common/temp_dir.hpp"
#include "common/toy_plan.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using pnc::test::slurp;
using namespace pnc::campaign;
using namespace pnc::md;
using namespace pnc::rve;
using pnc::test::plan_dir;
using pnc::test::toy_plan;

// D245: a recipe's slurm section is kept in the expanded recipe; without one nothing is added
TEST(RveCampaign, RecipeSlurmSectionIsKeptInTheExpandedRecipe) {
  nlohmann::json j = preset_json("demo_glass");
  EXPECT_FALSE(expanded_json(parse_recipe(j, "t")).contains("slurm"));
  j["slurm"] = {{"partition", "short"}, {"time", "0:30:00"}, {"ranks", 2}};
  const Recipe r = parse_recipe(j, "t");
  EXPECT_EQ(r.slurm.partition, "short");
  EXPECT_EQ(r.slurm.ranks, 2);
  EXPECT_EQ(expanded_json(r)["slurm"]["time"], "0:30:00");
  EXPECT_EQ(parse_recipe(expanded_json(r), "t").slurm.partition, "short");
}

TEST(RveCampaign, RunUnitAndStatusCommandsOnAPlanWithoutWork) {
  const auto d = plan_dir("test_campaign_cli");
  write_plan(d.string(), toy_plan());
  const std::string pnc = PNC_EXE;
  auto r = pnc::test::run_command(pnc + " run-unit " + d.string() + " nope 2>&1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("no such unit"), std::string::npos) << r.out;
  r = pnc::test::run_command(pnc + " run-unit " + d.string() + " a/u_1 a/u_2 2>&1");
  EXPECT_EQ(r.code, 1); // several units outside a job array
  EXPECT_NE(r.out.find("SLURM_ARRAY_TASK_ID"), std::string::npos) << r.out;
  r = pnc::test::run_command(pnc + " status " + d.string() + " --json 2>/dev/null");
  EXPECT_EQ(r.code, 0);
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["units"].size(), 4u);
  EXPECT_EQ(j["units"][0]["state"], "pending");
  UnitStatus f;
  f.state = UnitState::failed;
  f.message = "case 2: ERROR: Lost atoms: original 160 current 159";
  f.log_path = "replica_1/cases/case_2/lammps.log";
  write_status(d.string(), "b", f);
  r = pnc::test::run_command(pnc + " status " + d.string() + " 2>&1");
  EXPECT_EQ(r.code, 1); // a failed unit
  EXPECT_NE(r.out.find("Lost atoms"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("lammps.log"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 failed"), std::string::npos) << r.out;
  // a local plan: its driver writes its own page (D297); pnc status writes none
  EXPECT_FALSE(fs::exists(d / "report.md"));
  EXPECT_EQ(r.out.find("report (stopped early)"), std::string::npos) << r.out;
  fs::remove_all(d);
}

// D429: pnc status says how long the rest takes if the units running now keep running this
// many at a time. a/u_1 done in 100 s; a/u_2 running for 40 s in this (live) process, b and the
// fit pending: a/u_2 has 60 s left (its kind's mean), b and the fit 100 s each (the mean of
// every finished unit, none of their kind having finished), one at a time: 260 s.
TEST(RveCampaign, StatusGivesTheTimeLeftFromTheFinishedUnitsOfEachKind) {
  const auto d = plan_dir("test_campaign_eta");
  write_plan(d.string(), toy_plan());
  const std::string pnc = PNC_EXE;
  auto r = pnc::test::run_command(pnc + " status " + d.string() + " --json 2>/dev/null");
  EXPECT_TRUE(nlohmann::json::parse(r.out)["eta_s"].is_null()) << "nothing runs: no ETA";
  const double now = epoch_seconds();
  UnitStatus done;
  done.state = UnitState::done;
  done.started_s = now - 200;
  done.ended_s = now - 100;
  write_status(d.string(), "a/u_1", done);
  UnitStatus run;
  run.state = UnitState::running;
  run.host = host_name();
  run.pid = ::getpid();
  run.started_s = now - 40;
  write_status(d.string(), "a/u_2", run);
  r = pnc::test::run_command(pnc + " status " + d.string() + " --json 2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.out;
  // the 40 s of a/u_2 are counted from when pnc status ran, up to a few seconds after `now`
  const double eta = nlohmann::json::parse(r.out)["eta_s"].get<double>();
  EXPECT_LE(eta, 260.0);
  EXPECT_GT(eta, 250.0);
  r = pnc::test::run_command(pnc + " status " + d.string() + " 2>&1");
  EXPECT_NE(r.out.find("1 done, 1 running, 2 pending; about 4 min "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("left at 1 at a time"), std::string::npos) << r.out;
  fs::remove_all(d);
}

// D300: `pnc status` on a Slurm plan whose jobs ended without its final unit (a unit cancelled,
// the join unit failed naming what it missed) writes the stopped report: the units done, failed
// (job id, message) and not finished, the plan's command with --resume; while a unit is still
// queued it writes nothing. The state files are written as the Slurm units write them; a
// stand-in squeue on PATH says which jobs are alive.
TEST(RveCampaign, StatusOfAnEndedSlurmPlanWritesTheStoppedReport) {
  const auto d = plan_dir("test_campaign_slurm_report");
  const auto bin = d / "bin";
  fs::create_directories(bin);
  Plan p = toy_plan();
  const std::string made =
      "pnc characterize r.json --out " + (d / "run").string() + " --executor slurm";
  p.parameters["command_line"] = made;
  const std::string dir = (d / "run").string();
  fs::create_directories(dir);
  write_plan(dir, p);
  UnitStatus s;
  s.state = UnitState::done;
  s.job_id = "41_0";
  write_status(dir, "a/u_1", s);
  s.state = UnitState::pending; // stopped by scancel's SIGTERM: pending again
  s.job_id = "41_1";
  s.message = "stopped by SIGTERM at a checkpoint";
  write_status(dir, "a/u_2", s);
  s.job_id = "42";
  s.state = UnitState::queued; // its job is in the queue (the stand-in squeue lists it)
  s.message = "";
  write_status(dir, "b", s);
  s.state = UnitState::failed;
  s.job_id = "43";
  s.message = "the fit needs a/u_2, which is not done";
  write_status(dir, "fit", s);
  const auto squeue = bin / "squeue";
  std::ofstream(squeue) << "#!/bin/sh\necho '42|PENDING|Dependency'\n";
  fs::permissions(squeue, fs::perms::owner_all);
  const std::string status =
      "PATH=" + bin.string() + ":\"$PATH\" " + std::string(PNC_EXE) + " status " + dir + " 2>&1";
  // b is still queued: no page
  auto r = pnc::test::run_command(status);
  EXPECT_EQ(r.code, 1) << r.out; // a unit failed
  EXPECT_FALSE(fs::exists(fs::path(dir) / "report.md")) << r.out;
  EXPECT_EQ(r.out.find("report (stopped early)"), std::string::npos) << r.out;

  // b's job left the queue without a report: every unit ended, the fit not done
  std::ofstream(squeue) << "#!/bin/sh\nexit 0\n";
  fs::permissions(squeue, fs::perms::owner_all);
  r = pnc::test::run_command(status);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("report (stopped early): " + dir + "/report.html"), std::string::npos)
      << r.out;
  ASSERT_TRUE(fs::exists(fs::path(dir) / "report.html"));
  const std::string md = slurp(fs::path(dir) / "report.md");
  const auto banner = md.find("Did not finish: ");
  ASSERT_NE(banner, std::string::npos) << md;
  EXPECT_LT(banner, md.find("What was run")) << md; // first
  // the first failure that is not the fit's: b, whose job ended without a report
  EXPECT_NE(md.find("2 unit(s) failed, first b: job 42 ended without a report"), std::string::npos)
      << md;
  EXPECT_NE(md.find("1 of 4 units done"), std::string::npos) << md;
  EXPECT_NE(md.find("fit (job 43: the fit needs a/u_2"), std::string::npos) << md;
  EXPECT_NE(md.find("not finished: a/u_2 (job 41_1: stopped by SIGTERM"), std::string::npos) << md;
  EXPECT_NE(md.find("unit `a/u_1` (done): `a1`"), std::string::npos) << md;
  EXPECT_NE(md.find("`" + made + " --resume`"), std::string::npos) << md;

  // done: status refreshes nothing once the final unit is done
  fs::remove(fs::path(dir) / "report.md");
  fs::remove(fs::path(dir) / "report.html");
  for (const char* id : {"a/u_2", "b", "fit"}) {
    UnitStatus ok;
    ok.state = UnitState::done;
    ok.job_id = "50";
    write_status(dir, id, ok);
  }
  r = pnc::test::run_command(status);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_FALSE(fs::exists(fs::path(dir) / "report.md")) << r.out;
  fs::remove_all(d);
}

namespace {
/// Starts `sleep 30` with SLURM_JOB_ID=`job` in its initial environment (what
/// /proc/<pid>/environ shows); returns its pid.
pid_t sleeper_in_job(const char* job) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string var = std::string("SLURM_JOB_ID=") + job;
    char* const argv[] = {const_cast<char*>("sleep"), const_cast<char*>("30"), nullptr};
    char* const envp[] = {const_cast<char*>(var.c_str()), nullptr};
    ::execve("/bin/sleep", argv, envp);
    ::_exit(127);
  }
  return pid;
}
} // namespace

// D244: an srun task is not a descendant of srun; the channel accepts a peer of our own job.
TEST(RveCampaign, SlurmPeerCheckAcceptsOnlyProcessesOfOurJob) {
  const pid_t same = sleeper_in_job("4242"), other = sleeper_in_job("999");
  std::this_thread::sleep_for(std::chrono::milliseconds(300)); // exec done
  ::unsetenv("SLURM_JOB_ID");
  EXPECT_FALSE(in_our_slurm_job(same)); // outside a job nothing is a job peer
  ::setenv("SLURM_JOB_ID", "4242", 1);
  EXPECT_TRUE(in_our_slurm_job(same));
  EXPECT_FALSE(in_our_slurm_job(other));
  EXPECT_FALSE(in_our_slurm_job(999999999)); // no such process
  ::unsetenv("SLURM_JOB_ID");
  for (pid_t p : {same, other}) {
    ::kill(p, SIGKILL);
    ::waitpid(p, nullptr, 0);
  }
}

// D300: `pnc characterize --executor slurm --wait` whose jobs end without the fit (here no job
// ever runs: stand-ins for sbatch and scontrol accept the jobs, squeue shows none) leaves the
// stopped report before its error, with every unit's job and the command with --resume.
TEST(RveCampaign, SlurmWaitThatEndsWithoutTheFitLeavesTheStoppedReport) {
  const auto d = plan_dir("test_campaign_slurm_wait");
  const std::string path = pnc::test::slurm_stand_ins(d);
  std::ofstream(d / "r.json") << R"({"name": "tiny-wait", "seed": 7, "build": {"chains": 8},
    "deform": {"cases": [2], "strain_max": 0.03, "steps": 3}, "phase_check": {"enabled": false},
    "run": {"replicas": 1}})";
  const std::string out = (d / "out").string();
  const std::string cmd = std::string(PNC_EXE) + " characterize " + (d / "r.json").string() +
                          " --no-plots --out " + out + " --executor slurm --wait";
  const auto r = pnc::test::run_command(path + "PNC_SLURM_POLL_SECONDS=1 " + cmd + " 2>&1");
  EXPECT_EQ(r.code, 1) << r.out;
  const auto page = r.out.find("report (stopped early): " + out + "/report.html");
  EXPECT_NE(page, std::string::npos) << r.out;
  EXPECT_LT(page, r.out.find("pnc: error:")) << r.out; // the page, then the run's own error
  const std::string md = slurp(fs::path(out) / "report.md");
  const auto banner = md.find("Did not finish: ");
  ASSERT_NE(banner, std::string::npos) << md;
  EXPECT_LT(banner, md.find("What was run")) << md;
  EXPECT_NE(md.find("with 0 of 3 units done"), std::string::npos) << md;
  EXPECT_NE(md.find("replica_1/case_2: job 77 ended without a report"), std::string::npos) << md;
  EXPECT_NE(md.find("fit: job 77 ended without a report"), std::string::npos) << md;
  EXPECT_NE(md.find("`" + cmd + " --resume`"), std::string::npos) << md;
  fs::remove_all(d);
}

// D332: srun's MPI plugin reaches every job `pnc characterize --executor slurm` submits (the
// sbatch --export of PNC_SRUN_MPI, what a unit's K-rank stages give srun): the recipe's
// slurm.mpi, the option --mpi over it. Stand-ins record the submission; no job runs.
TEST(RveCampaign, SlurmMpiOfTheRecipeAndTheOptionReachEveryJob) {
  const auto d = plan_dir("test_campaign_slurm_mpi");
  const std::string path = pnc::test::slurm_stand_ins(d);
  std::ofstream(d / "r.json") << R"({"name": "tiny-mpi", "seed": 7, "build": {"chains": 8},
    "deform": {"cases": [2], "strain_max": 0.03, "steps": 3}, "phase_check": {"enabled": false},
    "run": {"replicas": 1}, "slurm": {"mpi": "pmi1"}})";
  for (const auto& [option, want] :
       {std::pair<std::string, std::string>{"", "pmi1"}, {" --mpi pmi2", "pmi2"}}) {
    fs::remove(d / "sbatch.args");
    const auto r = pnc::test::run_command(
        path + PNC_EXE + " characterize " + (d / "r.json").string() + " --no-plots --out " +
        (d / ("out" + want)).string() + " --executor slurm" + option + " 2>&1");
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string args = slurp(d / "sbatch.args");
    std::size_t jobs = 0;
    std::istringstream lines(args);
    for (std::string line; std::getline(lines, line); ++jobs)
      EXPECT_NE(line.find(",PNC_SRUN_MPI=" + want + " "), std::string::npos) << line;
    EXPECT_EQ(jobs, 3u) << args; // the equilibration, the case, the fit
  }
  fs::remove_all(d);
}
