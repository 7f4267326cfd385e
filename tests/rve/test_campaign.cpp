// The plan of units, its state files, the local executor and the Slurm executor's inputs
// (rve/campaign.hpp, rve/executor.hpp, rve/slurm.hpp; decisions D240-D245, D332), without LAMMPS:
// the units here sleep, fail or stop on purpose. The runs through a real Slurm cluster are in
// test_slurm_cli.cpp.
#include "pnc/core/error.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/md/private_channel.hpp"
#include "pnc/rve/campaign.hpp"
#include "pnc/rve/executor.hpp"
#include "pnc/rve/recipe.hpp"
#include "pnc/rve/slurm.hpp"

#include "common/run_command.hpp"
#include "common/slurm_stand_ins.hpp"

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
using namespace pnc::rve;
using namespace pnc::md;

namespace {

fs::path scratch(const std::string& name) {
  const auto d = fs::temp_directory_path() / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string what_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const pnc::InputError& e) {
    return e.what();
  }
  return "";
}

/// a1, a2 (one group), b needs a1, fit (join) needs a2 and b.
Plan toy_plan() {
  Plan p;
  p.command = "toy";
  p.parameters = {{"x", 1}};
  p.units = {{"a/u_1", "a", "a", {}, false, 1, {}, {"a1"}},
             {"a/u_2", "a", "a", {}, false, 1, {}, {"a2"}},
             {"b", "b", "b", {"a/u_1"}, false, 2, {"a1"}, {"b"}},
             {"fit", "fit", "fit", {"a/u_2", "b"}, true, 1, {}, {}}};
  return p;
}

} // namespace

TEST(RveCampaign, PlanRoundTripsAndBadPlansNameTheRule) {
  const Plan p = toy_plan();
  const Plan q = plan_from_json(plan_json(p), "test");
  ASSERT_EQ(q.units.size(), p.units.size());
  for (std::size_t i = 0; i < p.units.size(); ++i) {
    EXPECT_EQ(q.units[i].id, p.units[i].id);
    EXPECT_EQ(q.units[i].needs, p.units[i].needs);
    EXPECT_EQ(q.units[i].join, p.units[i].join);
    EXPECT_EQ(q.units[i].ranks, p.units[i].ranks);
  }
  EXPECT_EQ(q.parameters, p.parameters);
  EXPECT_TRUE(q.has("b"));
  EXPECT_NE(what_of([&] { q.unit("nope"); }).find("no such unit"), std::string::npos);

  Plan bad = p;
  bad.units[0].id = "A/../x";
  EXPECT_NE(what_of([&] { check_plan(bad, "plan.json"); }).find("lower-case letters"),
            std::string::npos);
  bad = p;
  std::swap(bad.units[0], bad.units[2]); // b before the unit it needs
  EXPECT_NE(what_of([&] { check_plan(bad, "plan.json"); }).find("listed before it"),
            std::string::npos);
  bad = p;
  bad.units[1].kind = "other"; // two kinds in group "a"
  EXPECT_NE(what_of([&] { check_plan(bad, "plan.json"); }).find("one kind"), std::string::npos);
  for (const char* id : {"", "/a", "a/", "a//b", "a b", "a;b", "a/./b"})
    EXPECT_NE(what_of([&] { check_unit_id(id, "x"); }), "") << id;
}

TEST(RveCampaign, StateFilesArePendingWithoutAFileAndRoundTrip) {
  const auto d = scratch("pnc_test_campaign_state");
  EXPECT_EQ(read_status(d.string(), "a/u_1").state, UnitState::pending);
  UnitStatus s;
  s.state = UnitState::failed;
  s.job_id = "12_3";
  s.message = "ERROR: Lost atoms | Last command: run 100";
  s.log_path = "x.log";
  s.detail = {{"seconds", 1.5}};
  write_status(d.string(), "a/u_1", s);
  EXPECT_TRUE(fs::exists(d / "state" / "a" / "u_1.json"));
  const UnitStatus r = read_status(d.string(), "a/u_1");
  EXPECT_EQ(r.state, UnitState::failed);
  EXPECT_EQ(r.job_id, "12_3");
  EXPECT_EQ(r.message, s.message);
  EXPECT_EQ(r.detail["seconds"], 1.5);
  std::ofstream(d / "state" / "b.json") << "{\"state\": \"exploded\"}";
  const std::string w = what_of([&] { read_status(d.string(), "b"); });
  EXPECT_NE(w.find("b.json"), std::string::npos) << w;
  EXPECT_NE(w.find("exploded"), std::string::npos) << w;
  clear_status(d.string(), "a/u_1");
  EXPECT_EQ(read_status(d.string(), "a/u_1").state, UnitState::pending);
  fs::remove_all(d);
}

TEST(RveCampaign, RunUnitRecordedRecordsDoneFailedAndStopped) {
  const auto d = scratch("pnc_test_campaign_record").string();
  const Plan p = toy_plan();
  run_unit_recorded(d, p.unit("b"), [] { return nlohmann::json{{"n", 3}}; });
  UnitStatus s = read_status(d, "b");
  EXPECT_EQ(s.state, UnitState::done);
  EXPECT_EQ(s.detail["n"], 3);
  EXPECT_GE(s.detail["seconds"].get<double>(), 0.0);
  EXPECT_GE(s.ended_s, s.started_s);
  EXPECT_THROW(run_unit_recorded(d, p.unit("a/u_1"),
                                 []() -> nlohmann::json {
                                   throw UnitFailure("case 2: ERROR: Lost atoms", "c2.log");
                                 }),
               UnitFailure);
  s = read_status(d, "a/u_1");
  EXPECT_EQ(s.state, UnitState::failed);
  EXPECT_EQ(s.message, "case 2: ERROR: Lost atoms");
  EXPECT_EQ(s.log_path, "c2.log");
  EXPECT_THROW(run_unit_recorded(d, p.unit("a/u_2"),
                                 []() -> nlohmann::json { throw pnc::Interrupted(15, "here"); }),
               pnc::Interrupted);
  s = read_status(d, "a/u_2");
  EXPECT_EQ(s.state, UnitState::pending); // stopped: run again by --resume
  EXPECT_NE(s.message.find("signal 15"), std::string::npos) << s.message;
  // one process per unit: a second run of the same unit while it runs is refused
  const std::string w = what_of([&] {
    run_unit_recorded(d, p.unit("fit"), [&] {
      run_unit_recorded(d, p.unit("fit"), [] { return nlohmann::json::object(); });
      return nlohmann::json::object();
    });
  });
  EXPECT_NE(w.find("another process"), std::string::npos) << w;
  fs::remove_all(d);
}

namespace {
/// Each unit sleeps `sleep_s` and records itself; unit "a/u_1" fails when `fail_a1`.
LocalRun run_toy(const std::string& d, int jobs, double sleep_s, bool fail_a1) {
  const Plan p = toy_plan();
  return run_local(d, p, jobs, [&](const Unit& u) {
    try {
      run_unit_recorded(d, u, [&]() -> nlohmann::json {
        std::this_thread::sleep_for(std::chrono::duration<double>(sleep_s));
        if (fail_a1 && u.id == "a/u_1") throw UnitFailure("a1 broke", "a1.log");
        return nlohmann::json::object();
      });
      return 0;
    } catch (...) {
      return 1;
    }
  });
}
} // namespace

TEST(RveCampaign, LocalExecutorRunsIndependentUnitsAtOnceAndNeedsInOrder) {
  for (int jobs : {1, 2}) {
    const auto d = scratch("pnc_test_campaign_local").string();
    const LocalRun lr = run_toy(d, jobs, 1.0, false);
    EXPECT_TRUE(lr.failed.empty());
    EXPECT_TRUE(lr.not_run.empty());
    ASSERT_EQ(lr.ran.size(), 4u);
    std::map<std::string, UnitStatus> s;
    for (const char* id : {"a/u_1", "a/u_2", "b", "fit"}) {
      s[id] = read_status(d, id);
      EXPECT_EQ(s[id].state, UnitState::done) << id;
    }
    // needs first: b after a/u_1, the join after a/u_2 and b
    EXPECT_GE(s["b"].started_s, s["a/u_1"].ended_s);
    EXPECT_GE(s["fit"].started_s, std::max(s["a/u_2"].ended_s, s["b"].ended_s));
    // the two independent units of group a: together with 2 jobs, one after the other with 1
    const bool overlap =
        s["a/u_2"].started_s < s["a/u_1"].ended_s && s["a/u_1"].started_s < s["a/u_2"].ended_s;
    EXPECT_EQ(overlap, jobs == 2) << "jobs " << jobs;
    // a second run finds everything done and runs nothing
    EXPECT_TRUE(run_toy(d, jobs, 0.0, false).ran.empty());
    fs::remove_all(d);
  }
}

TEST(RveCampaign, AFailedUnitStopsItsDependentsButNotTheOthers) {
  const auto d = scratch("pnc_test_campaign_fail").string();
  const LocalRun lr = run_toy(d, 2, 0.1, true);
  ASSERT_EQ(lr.failed.size(), 1u);
  EXPECT_NE(lr.failed[0].find("a/u_1: a1 broke (log a1.log)"), std::string::npos) << lr.failed[0];
  ASSERT_EQ(lr.not_run.size(), 1u);
  EXPECT_NE(lr.not_run[0].find("b (needs a/u_1"), std::string::npos) << lr.not_run[0];
  EXPECT_EQ(read_status(d, "a/u_2").state, UnitState::done); // the other keeps going
  EXPECT_EQ(read_status(d, "b").state, UnitState::pending);  // never started
  EXPECT_EQ(read_status(d, "fit").state, UnitState::done);   // a join runs and judges
  // --resume: only what is not done runs again
  const LocalRun again = run_toy(d, 2, 0.0, false);
  EXPECT_EQ(again.ran, (std::vector<std::string>{"a/u_1", "b"}));
  fs::remove_all(d);
}

TEST(RveCampaign, SlurmTemplateAndOptionsTakeValidatedValuesOnly) {
  const std::map<std::string, std::string> v = {{"kind", "case"}, {"ranks", "2"}};
  EXPECT_EQ(render_template("#SBATCH --ntasks={{ranks}} # {{kind}}\n", v, "t"),
            "#SBATCH --ntasks=2 # case\n");
  std::string w = what_of([&] { render_template("x {{partion}} y", v, "my.sbatch"); });
  EXPECT_NE(w.find("my.sbatch"), std::string::npos) << w;
  EXPECT_NE(w.find("{{partion}}"), std::string::npos) << w;
  EXPECT_NE(w.find("unknown placeholder"), std::string::npos) << w;
  EXPECT_NE(what_of([&] { render_template("x {{kind", v, "t"); }).find("without its"),
            std::string::npos);
  // the built-in template runs the command it is given as its arguments, nothing else
  const std::string t = render_template(default_sbatch_template(),
                                        {{"job_name", "j"}, {"kind", "case"}, {"ranks", "1"}}, "b");
  EXPECT_NE(t.find("exec \"$@\""), std::string::npos);

  SlurmSpec s;
  s.partition = "gpu;rm -rf";
  w = what_of([&] { s.validate("recipe.json"); });
  EXPECT_NE(w.find("slurm.partition"), std::string::npos) << w;
  s.partition = "compute-1";
  s.time = "1h";
  EXPECT_NE(what_of([&] { s.validate("r"); }).find("slurm.time"), std::string::npos);
  for (const char* ok : {"30", "30:00", "2:00:00", "1-12", "1-12:30", "1-12:30:00"}) {
    s.time = ok;
    EXPECT_EQ(what_of([&] { s.validate("r"); }), "") << ok;
  }
  w = what_of([&] { parse_slurm_spec({{"queue", "x"}}, "r.json"); });
  EXPECT_NE(w.find("slurm.queue"), std::string::npos) << w;
  EXPECT_NE(what_of([&] {
              parse_slurm_spec({{"ranks", 0}}, "r.json");
            }).find("1 to 4096"),
            std::string::npos);
  // a recipe's slurm section is kept in the expanded recipe; without one nothing is added
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
  const auto d = scratch("pnc_test_campaign_cli");
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

namespace {
std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  return std::string(std::istreambuf_iterator<char>(f), {});
}
} // namespace

// D300: `pnc status` on a Slurm plan whose jobs ended without its final unit (a unit cancelled,
// the join unit failed naming what it missed) writes the stopped report: the units done, failed
// (job id, message) and not finished, the plan's command with --resume; while a unit is still
// queued it writes nothing. The state files are written as the Slurm units write them; a
// stand-in squeue on PATH says which jobs are alive.
TEST(RveCampaign, StatusOfAnEndedSlurmPlanWritesTheStoppedReport) {
  const auto d = scratch("pnc_test_campaign_slurm_report");
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
  const auto d = scratch("pnc_test_campaign_slurm_wait");
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
  const auto d = scratch("pnc_test_campaign_slurm_mpi");
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
