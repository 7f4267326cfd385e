// `pnc characterize --executor slurm` on a real one-node Slurm cluster on localhost (the ctest
// fixture tests/rve/slurm/start_cluster.sh; docs/cluster.md, decisions D243-D245):
//  1. the same tiny recipe (2 replicas, 2 cases, phase check) run locally and through Slurm
//     gives bitwise equal cases.h5 datasets and the same card (constants, errors, verdict):
//     the units run the same code on the same inputs with the same seeds and rank counts;
//  2. a case unit cancelled with scancel while it runs is reported (its job id, why), the other
//     units keep going, the fit says which unit is missing, pnc status then writes the stopped
//     report (D300), and --resume submits only what is not done, finishes the campaign and
//     replaces that page with the full report;
//  3. Ctrl-C while --wait follows the jobs ends only the waiting (D306): exit code 130, the
//     stopped report names the live jobs, `scancel` and `pnc status`, and the jobs are still
//     in the queue;
//  4. a case unit that LAMMPS stops inside its job is reported with LAMMPS's own ERROR line
//     and its job id, the other units finish, the fit names the missing unit;
//  5. `pnc thermo ti` through Slurm gives the numbers of a local run;
//  6. --resume --replicas 3 on the run of 2 submits only the third replica's units (D418).
// Without the cluster the tests fail, naming the reason (start_cluster.sh's output).
#include "pnc/campaign/campaign.hpp"
#include "pnc/core/hdf5_io.hpp"

#include "common/run_command.hpp"
#include "common/spawn.hpp"
#include "common/temp_dir.hpp"
#ifdef PNC_HAVE_THERMO
#include "../thermo/tiny_polymer.hpp"
#endif

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

namespace fs = std::filesystem;
using pnc::test::run_command;
using pnc::test::slurp;

namespace {

/// Points SLURM_CONF at the fixture's cluster; "" when it runs, else why not.
std::string use_cluster() {
  std::ifstream h(PNC_SLURM_HANDLE);
  std::string dir;
  if (!std::getline(h, dir) || !fs::exists(fs::path(dir) / "slurm.conf"))
    return std::string("the test cluster is not running (no ") + PNC_SLURM_HANDLE +
           "): see the output of the ctest rve.slurm.start_cluster (tests/rve/slurm/"
           "start_cluster.sh), which needs the Debian packages slurm-wlm and munge";
  setenv("SLURM_CONF", (fs::path(dir) / "slurm.conf").c_str(), 1);
  setenv("PNC_SLURM_POLL_SECONDS", "1", 1);
  // A node that is still ending the jobs an earlier test cancelled reports "completing": the
  // cluster answers and takes jobs (they start once the node is free). Any other state (down,
  // drained, not responding) is given 30 s to clear, then named.
  pnc::test::CommandResult r;
  for (int attempt = 0; attempt < 30; ++attempt) {
    if (attempt > 0) std::this_thread::sleep_for(std::chrono::seconds(1));
    r = run_command("sinfo -h -o %T 2>&1");
    bool up = false;
    for (const char* s : {"idle", "mix", "alloc", "completing"})
      up = up || r.out.find(s) != std::string::npos;
    if (r.code == 0 && up) return "";
  }
  return "the test cluster does not answer within 30 s (sinfo: " + r.out + "); logs in " + dir +
         "/log";
}

// 160 beads, two replicas, cases 2 and 6 of 3 strain steps, a short phase check: seconds each
const char* tiny = R"({
  "name": "tiny-slurm", "seed": 7,
  "build": { "chains": 8 },
  "equilibrate": { "pushoff_steps": 500, "hot_steps": 500, "cool_steps": 500,
                   "langevin_chunk_steps": 200, "langevin_max_chunks": 2,
                   "npt_steps": 500, "final_steps": 200 },
  "deform": { "cases": [2, 6], "strain_max": 0.03, "steps": 3, "timestep_fs": 1.0,
              "hold_steps": 200, "sample_every": 10, "blocks": 4, "reference_holds": 1 },
  "phase_check": { "enabled": true, "steps": 1000, "sample_every": 5, "cavitation_steps": 200 },
  "analysis": { "moving_average": 1 },
  "run": { "jobs": 2, "replicas": 2 }
})";

/// Bitwise equality, NaN equal to NaN (a missing error is NaN in both or in neither).
bool same_bits(const pnc::h5::RowMatrix& a, const pnc::h5::RowMatrix& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    const double x = a.data()[i], y = b.data()[i];
    if (!(x == y || (std::isnan(x) && std::isnan(y)))) return false;
  }
  return true;
}

nlohmann::json status_json(const std::string& dir) {
  const auto r = run_command(std::string(PNC_EXE) + " status " + dir + " --json 2>/dev/null");
  return nlohmann::json::parse(r.out, nullptr, false);
}

nlohmann::json unit_of(const nlohmann::json& st, const std::string& id) {
  for (const auto& u : st["units"])
    if (u["unit"] == id) return u;
  return {};
}

/// Polls until `pred(status)` holds or `seconds` pass.
bool wait_until(const std::string& dir, double seconds,
                const std::function<bool(const nlohmann::json&)>& pred) {
  const auto t0 = std::chrono::steady_clock::now();
  while (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < seconds) {
    const auto st = status_json(dir);
    if (st.is_object() && pred(st)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  return false;
}

} // namespace

TEST(RveSlurm, SameCasesAndCardAsALocalRun) {
  const std::string why = use_cluster();
  ASSERT_EQ(why, "");
  const auto d = pnc::test::fresh_dir("test_rve_slurm_same");
  std::ofstream(d / "tiny.json") << tiny;
  const std::string base = std::string(PNC_EXE) + " characterize " + (d / "tiny.json").string() +
                           " --no-plots --json --equilibrate-ranks 1 --ranks 1";
  const auto local = run_command(base + " --out " + (d / "local").string() + " --jobs 2 2>" +
                                 (d / "local.err").string());
  ASSERT_TRUE(local.code == 0 || local.code == 3 || local.code == 4)
      << local.code << slurp(d / "local.err");
  const std::string sdir = (d / "slurm").string();
  const auto sl = run_command(base + " --out " + sdir + " --executor slurm --wait 2>" +
                              (d / "slurm.err").string());
  ASSERT_EQ(sl.code, local.code) << slurp(d / "slurm.err");

  // cases.h5: every dataset the fit reads, and every replica's raw curves, bit for bit
  pnc::h5::File a((d / "local" / "cases.h5").string(), pnc::h5::File::Mode::read);
  pnc::h5::File b((fs::path(sdir) / "cases.h5").string(), pnc::h5::File::Mode::read);
  int compared = 0;
  for (const int c : {2, 6}) {
    const std::string g = "/case_" + std::to_string(c);
    for (const char* n : {"/strain", "/stress", "/stress_stderr", "/reference_stderr"}) {
      EXPECT_TRUE(same_bits(a.read_matrix(g + n), b.read_matrix(g + n))) << g << n;
      ++compared;
    }
    for (const char* rep : {"/replicas/replica_1", "/replicas/replica_2"})
      for (const char* n : {"/raw_strain", "/raw_stress_total", "/raw_stress_virial",
                            "/raw_stress_total_stderr", "/stress", "/stress_stderr"}) {
        EXPECT_TRUE(same_bits(a.read_matrix(rep + g + n), b.read_matrix(rep + g + n)))
            << rep << g << n;
        ++compared;
      }
  }
  EXPECT_EQ(compared, 32);
  // the card: constants with their errors and status, the verdict (JSON doubles round-trip)
  const auto jl = nlohmann::json::parse(local.out);
  const auto js = nlohmann::json::parse(sl.out);
  EXPECT_EQ(jl["constants"], js["constants"]);
  EXPECT_EQ(jl["verdict"], js["verdict"]);
  EXPECT_EQ(jl["statistics"], js["statistics"]);
  EXPECT_EQ(jl["phase_check"], js["phase_check"]);
  EXPECT_TRUE(fs::exists(fs::path(sdir) / "card.h5"));

  // every unit ran as a Slurm job: the equilibrations as one array, each case array after its
  // replica's equilibration, the fit last; pnc status shows them done with their job ids
  const auto st = status_json(sdir);
  ASSERT_TRUE(st.is_object());
  ASSERT_EQ(st["units"].size(), 8u);
  for (const auto& u : st["units"]) {
    EXPECT_EQ(u["state"], "done") << u.dump();
    EXPECT_FALSE(u["job_id"].get<std::string>().empty()) << u.dump();
  }
  const std::string e1 = unit_of(st, "replica_1/equilibrate")["job_id"];
  const std::string e2 = unit_of(st, "replica_2/equilibrate")["job_id"];
  EXPECT_EQ(e1.substr(0, e1.find('_')), e2.substr(0, e2.find('_'))) << e1 << " " << e2;
  EXPECT_NE(e1, e2);
  for (const char* c : {"replica_1/case_2", "replica_1/case_6"})
    EXPECT_GE(unit_of(st, c)["started_s"].get<double>(),
              unit_of(st, "replica_1/equilibrate")["ended_s"].get<double>())
        << c;
  for (const auto& u : st["units"]) {
    if (u["unit"] == "fit") continue;
    EXPECT_GE(unit_of(st, "fit")["started_s"].get<double>(), u["ended_s"].get<double>())
        << u["unit"];
  }

  // a third replica added (D418): only its units (and the fit) are submitted; the jobs of
  // replicas 1 and 2 stay those of the first run
  const auto more = run_command(base + " --out " + sdir + " --executor slurm --wait --resume " +
                                "--replicas 3 2>" + (d / "more.err").string());
  ASSERT_TRUE(more.code == 0 || more.code == 3 || more.code == 4) << slurp(d / "more.err");
  EXPECT_EQ(nlohmann::json::parse(more.out)["statistics"]["replicas"], 3);
  const auto st3 = status_json(sdir);
  ASSERT_EQ(st3["units"].size(), 11u);
  for (const char* u :
       {"replica_1/equilibrate", "replica_2/equilibrate", "replica_1/case_2", "replica_2/case_6"})
    EXPECT_EQ(unit_of(st3, u)["job_id"], unit_of(st, u)["job_id"]) << u;
  for (const char* u : {"replica_3/equilibrate", "replica_3/case_2", "replica_3/case_6"}) {
    EXPECT_EQ(unit_of(st3, u)["state"], "done") << u;
    EXPECT_FALSE(unit_of(st3, u)["job_id"].get<std::string>().empty()) << u;
  }
  fs::remove_all(d);
}

TEST(RveSlurm, ScancelledUnitIsReportedAndResumeSubmitsOnlyWhatIsMissing) {
  const std::string why = use_cluster();
  ASSERT_EQ(why, "");
  const auto d = pnc::test::fresh_dir("test_rve_slurm_cancel");
  auto recipe = nlohmann::json::parse(tiny);
  recipe["name"] = "tiny-cancel";
  recipe["run"]["replicas"] = 1;
  recipe["phase_check"]["enabled"] = false;
  recipe["deform"]["steps"] = 12; // case 2 runs long enough to be cancelled while it runs
  recipe["deform"]["hold_steps"] = 400;
  std::ofstream(d / "r.json") << recipe.dump();
  // a site template of the user's: its placeholders get the group's values, "$@" the command
  std::ofstream(d / "site.sbatch") << "#!/bin/bash\n#SBATCH --comment={{kind}}\n"
                                      "echo \"site template: {{kind}} unit(s) on {{ranks}} "
                                      "rank(s), job {{job_name}}\"\nexec \"$@\"\n";
  const std::string out = (d / "out").string();
  const std::string cmd = std::string(PNC_EXE) + " characterize " + (d / "r.json").string() +
                          " --no-plots --out " + out + " --executor slurm --sbatch-template " +
                          (d / "site.sbatch").string() + " --job-name cancel-test";
  // submit and return
  const auto sub = run_command(cmd + " --json 2>" + (d / "sub.err").string());
  ASSERT_EQ(sub.code, 0) << slurp(d / "sub.err");
  const auto js = nlohmann::json::parse(sub.out);
  EXPECT_EQ(js["executor"], "slurm");
  EXPECT_EQ(js["units"].size(), 4u);

  // cancel case 2's job while it runs
  std::string job;
  ASSERT_TRUE(wait_until(out, 240, [&](const nlohmann::json& st) {
    const auto u = unit_of(st, "replica_1/case_2");
    if (u["state"] != "running") return false;
    job = u["job_id"];
    return true;
  })) << status_json(out).dump();
  ASSERT_EQ(run_command("scancel " + job).code, 0);
  // the fit (afterany) runs once the others ended, and fails naming what is missing
  ASSERT_TRUE(wait_until(out, 240, [](const nlohmann::json& st) {
    const auto f = unit_of(st, "fit");
    return f["state"] == "failed" || f["state"] == "done";
  })) << status_json(out).dump();
  const auto st = status_json(out);
  const auto c2 = unit_of(st, "replica_1/case_2");
  EXPECT_NE(c2["state"], "done") << c2.dump();
  EXPECT_EQ(c2["job_id"], job);
  const std::string msg = c2["message"];
  EXPECT_TRUE(msg.find("signal 15") != std::string::npos ||
              msg.find("job " + job) != std::string::npos)
      << msg;
  EXPECT_EQ(unit_of(st, "replica_1/case_6")["state"], "done"); // the others keep going
  const auto fit = unit_of(st, "fit");
  EXPECT_EQ(fit["state"], "failed");
  EXPECT_NE(fit["message"].get<std::string>().find("replica_1/case_2"), std::string::npos)
      << fit.dump();
  const auto status = run_command(std::string(PNC_EXE) + " status " + out + " 2>&1");
  EXPECT_EQ(status.code, 1); // a unit failed
  EXPECT_NE(status.out.find(job), std::string::npos) << status.out;
  // every job ended without the fit (submitted without --wait): pnc status wrote the stopped
  // report (D300): the banner first, the cancelled unit with its job id, the resume command
  EXPECT_NE(status.out.find("report (stopped early): " + out + "/report.html"), std::string::npos)
      << status.out;
  EXPECT_TRUE(fs::exists(fs::path(out) / "report.html"));
  const std::string stopped = slurp(fs::path(out) / "report.md");
  const auto banner = stopped.find("Did not finish: ");
  ASSERT_NE(banner, std::string::npos) << stopped;
  EXPECT_LT(banner, stopped.find("What was run")) << stopped;
  EXPECT_NE(stopped.find("with 2 of 4 units done"), std::string::npos)
      << stopped; // the equilibration and case 6
  EXPECT_TRUE(stopped.find("replica_1/case_2 (job " + job) != std::string::npos ||
              stopped.find("replica_1/case_2: job " + job) != std::string::npos)
      << stopped;
  EXPECT_NE(stopped.find("`" + cmd + " --json --resume`"), std::string::npos) << stopped;
  const std::string eq_job = unit_of(st, "replica_1/equilibrate")["job_id"];
  const std::string c6_job = unit_of(st, "replica_1/case_6")["job_id"];

  // --resume: only case 2 and the fit are submitted again; the campaign finishes
  const auto again = run_command(cmd + " --resume --wait 2>" + (d / "resume.err").string());
  EXPECT_TRUE(again.code == 0 || again.code == 3 || again.code == 4)
      << again.code << slurp(d / "resume.err");
  const auto st2 = status_json(out);
  for (const auto& u : st2["units"])
    EXPECT_EQ(u["state"], "done") << u.dump();
  EXPECT_EQ(unit_of(st2, "replica_1/equilibrate")["job_id"], eq_job);
  EXPECT_EQ(unit_of(st2, "replica_1/case_6")["job_id"], c6_job);
  EXPECT_NE(unit_of(st2, "replica_1/case_2")["job_id"], job);
  EXPECT_TRUE(fs::exists(fs::path(out) / "cases.h5"));
  EXPECT_TRUE(fs::exists(fs::path(out) / "card.h5"));
  // the resumed run's full report replaced the stopped one
  const std::string full = slurp(fs::path(out) / "report.md");
  EXPECT_EQ(full.find("Did not finish"), std::string::npos) << full.substr(0, 600);
  EXPECT_NE(full, stopped);
  // every job ran the user's template, rendered per group
  EXPECT_NE(slurp(fs::path(out) / "slurm" / "fit.sbatch").find("#SBATCH --comment=fit"),
            std::string::npos);
  int rendered = 0;
  for (const auto& f : fs::directory_iterator(fs::path(out) / "slurm"))
    if (f.path().extension() == ".out") {
      const std::string text = slurp(f.path());
      const bool c = text.find("site template: case unit(s) on 1 rank(s), job "
                               "cancel-test-cases_replica_1") != std::string::npos;
      const bool e = text.find("site template: equilibrate unit(s) on 1 rank(s), job "
                               "cancel-test-equilibrate") != std::string::npos;
      const bool fi = text.find("site template: fit unit(s)") != std::string::npos;
      EXPECT_TRUE(c || e || fi) << f.path() << ": " << text.substr(0, 300);
      ++rendered;
    }
  EXPECT_GE(rendered, 5); // equilibrate, cases (2 + the resubmitted one), fit twice
  fs::remove_all(d);
}

// A case unit that LAMMPS stops inside its Slurm job (D243): the user's system computes
// electrostatics with PPPM (`kspace_modify ... diff ad`, zero charges: the crystal of the LJ
// example); LAMMPS refuses PPPM on a box made triclinic after the solver was defined ("Must
// redefine kspace_style after changing to triclinic box", and with that lifted "Cannot (yet)
// use PPPM with triclinic box and kspace_modify diff ad"), so only the shear case 6, whose box
// is made triclinic, fails; the stretch case 2 keeps an orthogonal box and finishes. The
// failed unit is reported with the ERROR line LAMMPS wrote to its own log and the unit's job
// id (pnc status, the recorded state, the --wait report); the fit names the missing unit;
// the exit code is the local run's.
TEST(RveSlurm, LammpsErrorInACaseJobIsReportedWithItsMessageAndJobId) {
  const std::string why = use_cluster();
  ASSERT_EQ(why, "");
  const auto d = pnc::test::fresh_dir("test_rve_slurm_lmperr");
  { // 4 x 4 x 4 fcc cells (256 atoms, a0 of examples/rve/lj_fcc), atom style charge, q = 0
    const double a0 = 5.27639965902468, l = 4 * a0;
    const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    std::ofstream f(d / "q.data");
    f << "fcc, zero charges\n\n256 atoms\n1 atom types\n\n";
    f << fmt::format("0 {0:.15g} xlo xhi\n0 {0:.15g} ylo yhi\n0 {0:.15g} zlo zhi\n", l);
    f << "\nMasses\n\n1 39.948\n\nAtoms # charge\n\n";
    int id = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        for (int k = 0; k < 4; ++k)
          for (const auto& b : basis)
            f << fmt::format("{} 1 0.0 {:.15g} {:.15g} {:.15g}\n", ++id, (i + b[0]) * a0,
                             (j + b[1]) * a0, (k + b[2]) * a0);
  }
  const nlohmann::json recipe = {
      {"name", "lammps-error"},
      {"seed", 1},
      {"model", "pp"},
      {"system",
       {{"data_file", "q.data"},
        {"atom_style", "charge"},
        {"units", "real"},
        {"forcefield",
         {"pair_style lj/cut/coul/long 8.5", "pair_coeff * * 0.2381 3.405", "mass 1 39.948",
          "kspace_style pppm 1e-4", "kspace_modify gewald 0.3 mesh 8 8 8 diff ad",
          "neighbor 2.0 bin", "neigh_modify every 1 delay 0 check yes"}}}},
      {"equilibrate", {{"stages", nlohmann::json::array()}}},
      {"deform",
       {{"cases", {2, 6}},
        {"strain_max", 0.0002},
        {"steps", 2},
        {"temperature", 0.0},
        {"minimize", true}}},
      {"analysis", {{"stress", "virial"}, {"moving_average", 1}, {"reference", "subtract"}}},
      {"run", {{"jobs", 2}}}};
  std::ofstream(d / "r.json") << recipe.dump();
  const std::string base = std::string(PNC_EXE) + " characterize " + (d / "r.json").string() +
                           " --no-plots --equilibrate-ranks 1 --ranks 1";
  const auto local =
      run_command(base + " --out " + (d / "local").string() + " 2>" + (d / "local.err").string());
  ASSERT_EQ(local.code, 7) << slurp(d / "local.err"); // a ToolError: LAMMPS stopped a stage
  const std::string out = (d / "out").string(), err = (d / "wait.err").string();
  const auto sl = run_command(base + " --out " + out + " --executor slurm --wait 2>" + err);
  const std::string waited = slurp(err);
  EXPECT_EQ(sl.code, local.code) << waited;

  // LAMMPS's own message: the ERROR line of the unit's LAMMPS log
  std::string lmp_error;
  {
    std::ifstream log(fs::path(out) / "cases" / "case_6" / "lammps.log");
    for (std::string line; std::getline(log, line);)
      if (line.rfind("ERROR: ", 0) == 0) lmp_error = line;
  }
  ASSERT_NE(lmp_error.find("triclinic"), std::string::npos) << lmp_error;
  const auto st = status_json(out);
  ASSERT_TRUE(st.is_object()) << waited;
  ASSERT_EQ(st["units"].size(), 4u) << st.dump();
  const auto c6 = unit_of(st, "replica_1/case_6");
  EXPECT_EQ(c6["state"], "failed") << c6.dump();
  const std::string job = c6.value("job_id", std::string());
  ASSERT_FALSE(job.empty()) << c6.dump();
  const std::string msg = c6.value("message", std::string());
  EXPECT_NE(msg.find("LAMMPS failed while running stage case 6: " + lmp_error), std::string::npos)
      << msg;
  // the others keep going: the equilibration and case 2 ran in their jobs and are done
  for (const char* u : {"replica_1/equilibrate", "replica_1/case_2"}) {
    EXPECT_EQ(unit_of(st, u)["state"], "done") << unit_of(st, u).dump();
    EXPECT_FALSE(unit_of(st, u)["job_id"].get<std::string>().empty()) << u;
  }
  const auto fit = unit_of(st, "fit");
  EXPECT_EQ(fit["state"], "failed") << fit.dump();
  EXPECT_NE(fit["message"].get<std::string>().find("missing: replica_1/case_6"), std::string::npos)
      << fit.dump();
  // the text of pnc status and the --wait report: the unit's line, its job id, LAMMPS's message
  const auto status = run_command(std::string(PNC_EXE) + " status " + out + " 2>&1");
  EXPECT_EQ(status.code, 1) << status.out; // a unit failed
  const auto row = status.out.find("\nreplica_1/case_6 ");
  ASSERT_NE(row, std::string::npos) << status.out;
  const std::string line = status.out.substr(row + 1, status.out.find('\n', row + 1) - row - 1);
  EXPECT_NE(line.find(" failed "), std::string::npos) << line;
  EXPECT_NE(line.find(" " + job + " "), std::string::npos) << line;
  EXPECT_NE(line.find(lmp_error), std::string::npos) << line;
  EXPECT_NE(waited.find("pnc: unit replica_1/case_6: failed (job " + job +
                        "): LAMMPS failed while running stage case 6: " + lmp_error),
            std::string::npos)
      << waited;
  // the fit's failure in the report names the missing unit with its job id
  EXPECT_NE(waited.find("missing: replica_1/case_6 (failed, job " + job + ": "), std::string::npos)
      << waited;
  fs::remove_all(d);
}

TEST(RveSlurm, SigintWhileWaitingLeavesTheJobsAndTheStoppedReport) {
  const std::string why = use_cluster();
  ASSERT_EQ(why, "");
  const auto d = pnc::test::fresh_dir("test_rve_slurm_sigwait");
  auto recipe = nlohmann::json::parse(tiny);
  recipe["name"] = "tiny-sigwait";
  recipe["run"]["replicas"] = 1;
  recipe["phase_check"]["enabled"] = false;
  std::ofstream(d / "r.json") << recipe.dump();
  const std::string out = (d / "out").string(), err = (d / "err.txt").string();
  // the jobs this test leaves running are cancelled at its end, whatever happened
  struct Cancel {
    std::string out;
    ~Cancel() {
      const auto st = status_json(out);
      if (!st.is_object()) return;
      for (const auto& u : st["units"]) {
        const std::string j = u.value("job_id", std::string());
        if (!j.empty()) run_command("scancel " + j.substr(0, j.find('_')) + " 2>/dev/null");
      }
    }
  } cancel{out};
  const pid_t pid = pnc::test::spawn(std::string(PNC_EXE) + " characterize " +
                                     (d / "r.json").string() + " --no-plots --out " + out +
                                     " --executor slurm --wait --job-name sigwait-test 2>" + err);
  // the jobs are submitted and the wait has polled once: the fit (afterany) is queued
  ASSERT_TRUE(pnc::test::wait_for_text(err, "pnc: unit fit: queued (job ", 60)) << slurp(err);
  ::kill(pid, SIGINT);
  const auto e = pnc::test::wait_for(pid, 30);
  ASSERT_TRUE(e.ended) << "still waiting 30 s after SIGINT";
  const std::string msg = slurp(err);
  EXPECT_EQ(e.code, 128 + SIGINT) << msg;
  EXPECT_NE(msg.find("pnc: interrupted by SIGINT: stopped waiting; the Slurm jobs keep running"),
            std::string::npos)
      << msg;
  // nothing was cancelled: the fit's job waits in the queue for the others
  const auto st = status_json(out);
  ASSERT_TRUE(st.is_object());
  const std::string fit_job = unit_of(st, "fit")["job_id"];
  ASSERT_FALSE(fit_job.empty()) << st.dump();
  EXPECT_NE(unit_of(st, "fit")["state"], "failed") << st.dump();
  EXPECT_NE(run_command("squeue -h -j " + fit_job + " -o %i").out.find(fit_job), std::string::npos)
      << "the fit's job left the queue";
  // the page: the banner first, in words, the unit states, the live jobs with scancel, pnc status
  const std::string md = slurp(fs::path(out) / "report.md");
  const auto banner = md.find("Did not finish: interrupted by SIGINT while waiting: only the "
                              "waiting stopped, the Slurm jobs keep running");
  ASSERT_NE(banner, std::string::npos) << md;
  EXPECT_LT(banner, md.find("What was run")) << md;
  EXPECT_NE(md.find("of 4 units done"), std::string::npos) << md;
  EXPECT_NE(md.find("fit (job " + fit_job), std::string::npos) << md;
  const auto sc = md.find("`scancel ");
  ASSERT_NE(sc, std::string::npos) << md;
  const std::string scancel = md.substr(sc, md.find('`', sc + 1) - sc);
  EXPECT_NE((scancel + " ").find(" " + fit_job + " "), std::string::npos) << scancel;
  for (const auto& u : st["units"]) // every live job is named, an array by its id
    if (u["state"] == "queued" || u["state"] == "running") {
      const std::string j = u["job_id"];
      EXPECT_NE((scancel + " ").find(" " + j.substr(0, j.find('_')) + " "), std::string::npos)
          << u.dump() << scancel;
    }
  EXPECT_NE(md.find("`pnc status " + out + "`"), std::string::npos) << md;
  EXPECT_EQ(md.find("--resume"), std::string::npos) << md; // D306: not offered while jobs live
}

// `pnc thermo ti --executor slurm` (decisions D285-D288): the (state, lambda) units as one job
// array, the analysis after it (afterany), on the tiny polymer of the thermo tests; its numbers
// equal a local run of the same input and seed to round-off (relative 1e-12): the units run the
// same code on the same files with the same seeds on one rank each, so only the executor
// differs (a different seed or node would differ by the sampling error, percent level).
// Compiled only in builds with the thermo library (a build without it has no such test,
// rather than a skipped one).
#ifdef PNC_HAVE_THERMO
TEST(RveSlurm, ThermoTiSameAsALocalRun) {
  const std::string why = use_cluster();
  ASSERT_EQ(why, "");
  const auto d = pnc::test::fresh_dir("test_rve_slurm_ti");
  const std::string rs = pnc::test::tiny_polymer_restart(d);
  const std::string base = std::string(PNC_EXE) + " thermo ti --restart " + rs +
                           " --vol 0,0.005 --dev none --points 2 --equil-steps 20 "
                           "--prod-steps 60 --sample-every 10 --blocks 3 --no-plots";
  const auto local = run_command(base + " --jobs 2 --out " + (d / "local").string() + " 2>" +
                                 (d / "local.err").string());
  ASSERT_EQ(local.code, 0) << slurp(d / "local.err");
  const std::string sdir = (d / "slurm").string();
  const auto sl =
      run_command(base + " --out " + sdir + " --executor slurm --wait --job-name ti-test 2>" +
                  (d / "slurm.err").string());
  ASSERT_EQ(sl.code, 0) << slurp(d / "slurm.err");
  // ti.h5: per state dA and its error, <dH/dl> and its error at every node (kcal/mol)
  pnc::h5::File a((d / "local" / "ti.h5").string(), pnc::h5::File::Mode::read);
  pnc::h5::File b((fs::path(sdir) / "ti.h5").string(), pnc::h5::File::Mode::read);
  const auto near = [](double x, double y) { return std::fabs(x - y) <= 1e-12 * std::fabs(y); };
  int compared = 0;
  for (const char* id : {"ref", "vol_0.005"}) {
    const std::string g = std::string("/states/") + id;
    for (const char* n : {"/dA", "/dA_stderr"}) {
      EXPECT_TRUE(near(a.read_scalar(g + n), b.read_scalar(g + n))) << g << n;
      ++compared;
    }
    for (const char* n : {"/dhdl_mean", "/dhdl_stderr"}) {
      const auto x = a.read_vector(g + n), y = b.read_vector(g + n);
      ASSERT_EQ(x.size(), 2u);
      ASSERT_EQ(y.size(), 2u);
      for (std::size_t i = 0; i < 2; ++i, ++compared)
        EXPECT_TRUE(near(x[i], y[i])) << g << n << "[" << i << "]";
    }
  }
  EXPECT_EQ(compared, 12);
  EXPECT_TRUE(fs::exists(fs::path(sdir) / "ti.h5"));
  // every unit ran as a Slurm job: the 4 points as one array, the analysis after all of them
  const auto st = status_json(sdir);
  ASSERT_TRUE(st.is_object());
  ASSERT_EQ(st["units"].size(), 5u);
  const std::string array_job = unit_of(st, "ref/lambda_0")["job_id"];
  for (const auto& u : st["units"]) {
    EXPECT_EQ(u["state"], "done") << u.dump();
    const std::string job = u["job_id"];
    ASSERT_FALSE(job.empty()) << u.dump();
    if (u["unit"] == "analysis") continue;
    EXPECT_EQ(job.substr(0, job.find('_')), array_job.substr(0, array_job.find('_'))) << job;
    EXPECT_GE(unit_of(st, "analysis")["started_s"].get<double>(), u["ended_s"].get<double>())
        << u["unit"];
  }
  fs::remove_all(d);
}

// D324: `pnc thermo ti --ranks 2 --executor slurm`: every point job gets 2 tasks and its LAMMPS
// runs on both (srun inside the job; the point's LAMMPS log says so), the analysis follows.
TEST(RveSlurm, ThermoTiPointsOnTwoRanks) {
  const std::string why = use_cluster();
  ASSERT_EQ(why, "");
  const auto d = pnc::test::fresh_dir("test_rve_slurm_ti2");
  const std::string rs = pnc::test::tiny_polymer_restart(d);
  const std::string sdir = (d / "slurm").string();
  const auto sl = run_command(std::string(PNC_EXE) + " thermo ti --restart " + rs +
                              " --vol 0 --dev none --points 2 --equil-steps 20 --prod-steps 60 "
                              "--sample-every 10 --blocks 3 --no-plots --ranks 2 --out " +
                              sdir + " --executor slurm --wait --job-name ti-test2 2>" +
                              (d / "slurm.err").string());
  ASSERT_EQ(sl.code, 0) << slurp(d / "slurm.err");
  EXPECT_TRUE(fs::exists(fs::path(sdir) / "ti.h5"));
  for (const char* log : {"ref/lambda_0.log", "ref/lambda_1.log"})
    EXPECT_NE(slurp(fs::path(sdir) / log).find("on 2 procs"), std::string::npos) << log;
  const auto st = status_json(sdir);
  ASSERT_TRUE(st.is_object());
  for (const auto& u : st["units"])
    EXPECT_EQ(u["state"], "done") << u.dump();
  fs::remove_all(d);
}
#endif
