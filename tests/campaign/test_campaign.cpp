// The plan of units, its state files, the local executor and the Slurm executor's inputs
// (pnc/campaign/campaign.hpp, executor.hpp, slurm.hpp; decisions D240-D245, D332), without
// LAMMPS and without the pnc executable: the units here sleep, fail or stop on purpose. The
// commands on a plan (pnc run-unit, pnc status, pnc characterize --executor slurm) are tested in
// tests/rve/test_campaign_cli.cpp, the runs through a real Slurm cluster in
// tests/rve/test_slurm_cli.cpp.
#include "pnc/campaign/campaign.hpp"
#include "pnc/campaign/executor.hpp"
#include "pnc/campaign/slurm.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/stop.hpp"

#include "common/toy_plan.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using namespace pnc::campaign;
using pnc::test::plan_dir;
using pnc::test::toy_plan;

namespace {

std::string what_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const pnc::InputError& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(Campaign, PlanRoundTripsAndBadPlansNameTheRule) {
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

TEST(Campaign, StateFilesArePendingWithoutAFileAndRoundTrip) {
  const auto d = plan_dir("test_campaign_state");
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

TEST(Campaign, RunUnitRecordedRecordsDoneFailedAndStopped) {
  const auto d = plan_dir("test_campaign_record").string();
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

TEST(Campaign, LocalExecutorRunsIndependentUnitsAtOnceAndNeedsInOrder) {
  for (int jobs : {1, 2}) {
    const auto d = plan_dir("test_campaign_local").string();
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

// The ETA of a run (D429): every unit left takes the mean of the finished units of its kind (of
// all finished ones for a kind not yet seen), less what it has run; jobs share the sum.
TEST(Campaign, RemainingSecondsTakesEachKindsMeanOverTheJobs) {
  const std::vector<UnitSeconds> done = {{"case", 30}, {"case", 40}, {"equilibrate", 100}};
  // two cases (35 s each), an equilibration that has run 40 of its 100 s, a fit (mean of all: 56.67
  // s)
  const std::vector<UnitSeconds> left = {{"case", 0}, {"case", 0}, {"equilibrate", 40}, {"fit", 0}};
  EXPECT_NEAR(remaining_seconds(done, left, 1), 35 + 35 + 60 + 170.0 / 3, 1e-12);
  EXPECT_NEAR(remaining_seconds(done, left, 2), (35 + 35 + 60 + 170.0 / 3) / 2, 1e-12);
  // more jobs than units left: the units left run at once
  EXPECT_NEAR(remaining_seconds(done, {{"case", 0}}, 8), 35.0, 1e-12);
  EXPECT_EQ(remaining_seconds(done, {{"case", 50}}, 1), 0.0) << "a unit past its mean: 0, not < 0";
  EXPECT_EQ(remaining_seconds(done, {}, 2), 0.0);
  EXPECT_TRUE(std::isnan(remaining_seconds({}, left, 2))) << "no unit finished: unknown";
  // the last 8 of a kind: ten cases of 100 s on a busy machine, then eight of 30 s
  std::vector<UnitSeconds> busy_then_idle(10, {"case", 100});
  busy_then_idle.insert(busy_then_idle.end(), 8, {"case", 30});
  EXPECT_NEAR(remaining_seconds(busy_then_idle, {{"case", 0}}, 1), 30.0, 1e-12);
  busy_then_idle.push_back({"case", 110}); // one slow one among the last eight: 7 x 30 + 110
  EXPECT_NEAR(remaining_seconds(busy_then_idle, {{"case", 0}}, 1), (7 * 30 + 110) / 8.0, 1e-12);
}

// One progress line of the whole run per unit that ends (D344, D429), in the order they end,
// its ETA from the first unit's time: the three left are each expected to take as long.
TEST(Campaign, LocalExecutorPrintsTheRunsProgressWithItsEta) {
  const auto d = plan_dir("test_campaign_progress").string();
  testing::internal::CaptureStderr();
  run_toy(d, 1, 0.5, false);
  const std::string err = testing::internal::GetCapturedStderr();
  std::vector<std::string> lines;
  std::istringstream in(err);
  for (std::string l; std::getline(in, l);)
    if (l.rfind("pnc toy: ", 0) == 0) lines.push_back(l);
  ASSERT_EQ(lines.size(), 4u) << err;
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_EQ(lines[k].rfind(fmt::format("pnc toy: {}/4 units", k + 1), 0), 0u) << lines[k];
  EXPECT_NE(lines[0].find("; unit a/u_1 done in "), std::string::npos) << lines[0];
  EXPECT_NE(lines[3].find("ETA 0"), std::string::npos) << lines[3];
  // "ETA 1.6 s; unit a/u_1 done in 0.5 s": ETA = 3 x the first unit's time, each rounded to 0.05 s
  double eta = 0, first = 0;
  ASSERT_EQ(std::sscanf(lines[0].c_str() + lines[0].find("ETA "), "ETA %lf s", &eta), 1)
      << lines[0];
  ASSERT_EQ(std::sscanf(lines[0].c_str() + lines[0].find("done in "), "done in %lf s", &first), 1);
  EXPECT_GE(first, 0.5);
  EXPECT_NEAR(eta, 3 * first, 3 * 0.05 + 0.05) << lines[0];
  fs::remove_all(d);
}

TEST(Campaign, AFailedUnitStopsItsDependentsButNotTheOthers) {
  const auto d = plan_dir("test_campaign_fail").string();
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

TEST(Campaign, SlurmTemplateAndOptionsTakeValidatedValuesOnly) {
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
}
