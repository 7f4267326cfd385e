// How many MPI ranks per lambda point and points at a time `pnc thermo ti` plans (D333), as
// `pnc characterize` does (app/campaign_driver.hpp plan_parallelism): a warning when ranks x
// jobs exceeds the machine's cores; started as `mpirun -np K pnc thermo ti`, rank 0 supervises
// with K ranks per point and one point at a time unless --ranks / --jobs (or the input file's
// keys) say otherwise, and the other ranks leave at once. No LAMMPS runs: the start state is
// missing (the run stops right after planning), or the plan goes to stand-ins of Slurm's
// commands (tests/common/slurm_stand_ins.hpp) whose jobs never run.
#include "common/run_command.hpp"
#include "common/slurm_stand_ins.hpp"
#include "common/temp_dir.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

namespace fs = std::filesystem;

namespace {

/// Number of (non-overlapping) occurrences of `what` in `text`.
std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + what.size()))
    ++n;
  return n;
}

nlohmann::json plan_of(const fs::path& out) {
  return nlohmann::json::parse(pnc::test::slurp(out / "plan.json"), nullptr, false);
}

/// A fresh directory `d` with the stand-ins of Slurm's commands and an empty start restart, and
/// the shell command of `pnc thermo ti` over 2 points of the volume path through the slurm
/// executor, started by `launcher` (environment assignments, or mpirun and its options).
struct SlurmTi {
  fs::path d;
  std::string path; // the PATH assignment that puts the stand-ins first
  explicit SlurmTi(const std::string& name)
      : d(pnc::test::fresh_dir(name)), path(pnc::test::slurm_stand_ins(d)) {
    std::ofstream(d / "rs.restart") << "";
  }
  /// Output into d/`out`, stderr into d/err; `args` appended to the command line.
  std::string command(const std::string& launcher, const std::string& out,
                      const std::string& args = "") const {
    return fmt::format("{}{} {} thermo ti --restart {} --vol 0 --dev none --points 2 --executor "
                       "slurm --out {} {} 2>{}",
                       path, launcher, PNC_EXE, (d / "rs.restart").string(), (d / out).string(),
                       args, (d / "err").string());
  }
  std::string err() const { return pnc::test::slurp(d / "err"); }
};

} // namespace

// More processes than cores (ranks x jobs > std::thread::hardware_concurrency, which pnc
// compares with) is a warning with the numbers, before the run goes on (here to the error of
// its missing restart); 1 x 1 is not.
TEST(ThermoTiParallel, WarnsWhenRanksTimesJobsExceedTheCores) {
  const unsigned cores = std::thread::hardware_concurrency();
  const fs::path d = pnc::test::fresh_dir("test_ti_parallel_warn");
  const int jobs = 8, ranks = std::max(2, static_cast<int>(cores) / jobs + 1);
  const auto run = [&](int k, int j) {
    const auto r = pnc::test::run_command(
        fmt::format("{} thermo ti --restart {} --out {} --ranks {} --jobs {} 2>{}", PNC_EXE,
                    (d / "missing.restart").string(), (d / fmt::format("o{}x{}", k, j)).string(), k,
                    j, (d / "err").string()));
    EXPECT_EQ(r.code, 1); // the missing restart, after the warning
    return pnc::test::slurp(d / "err");
  };
  std::string err = run(ranks, jobs);
  if (cores == 0) { // the machine does not say how many cores it has: pnc does not guess
    EXPECT_EQ(err.find("processes on"), std::string::npos) << err;
  } else {
    ASSERT_GT(static_cast<unsigned>(ranks * jobs), cores);
    EXPECT_NE(err.find(fmt::format("pnc: warning: {} ranks x {} jobs = {} processes on {} cores\n",
                                   ranks, jobs, ranks * jobs, cores)),
              std::string::npos)
        << err;
  }
  EXPECT_NE(err.find("no such LAMMPS restart file"), std::string::npos) << err;
  err = run(1, 1);
  EXPECT_EQ(err.find("processes on"), std::string::npos) << err;
  EXPECT_NE(err.find("no such LAMMPS restart file"), std::string::npos) << err;
  fs::remove_all(d);
}

// As Open MPI's mpirun starts it (OMPI_COMM_WORLD_SIZE/RANK, what md::launcher_from_environment
// reads): a follower rank leaves at once, silently, touching nothing; rank 0 says it supervises
// and plans every point on K ranks, one at a time; --ranks/--jobs given, or the input file's
// `ranks`, win over K (D301's precedence).
TEST(ThermoTiParallel, UnderMpirunRankZeroPlansKRanksOneJobAndTheOthersLeave) {
  const SlurmTi ti("test_ti_parallel_env");
  const fs::path& d = ti.d;
  std::ofstream(d / "ti.toml") << "ranks = 2\n";
  const auto run = [&](int rank, const std::string& out, const std::string& args) {
    const auto r = pnc::test::run_command(
        ti.command(fmt::format("OMPI_COMM_WORLD_SIZE=3 OMPI_COMM_WORLD_RANK={}", rank), out, args));
    EXPECT_EQ(r.code, 0) << ti.err();
    return ti.err();
  };
  EXPECT_EQ(run(1, "f", ""), "");
  EXPECT_FALSE(fs::exists(d / "f"));
  EXPECT_FALSE(fs::exists(d / "sbatch.args"));
  struct Case {
    std::string out, args;
    int ranks, jobs;
  };
  for (const Case& c : {Case{"k", "", 3, 1}, Case{"o", "--ranks 1 --jobs 2", 1, 2},
                        Case{"i", "--input " + (d / "ti.toml").string(), 2, 1}}) {
    const std::string err = run(0, c.out, c.args);
    EXPECT_EQ(count_of(err, fmt::format("pnc: started by mpirun with 3 ranks: each LAMMPS stage "
                                        "runs on {} rank(s), {} unit(s) at a time\n",
                                        c.ranks, c.jobs)),
              1u)
        << c.out << ": " << err;
    const auto p = plan_of(d / c.out);
    ASSERT_TRUE(p.is_object()) << c.out;
    EXPECT_EQ(p["parameters"]["ranks"], c.ranks) << c.out;
    EXPECT_EQ(p["parameters"]["jobs"], c.jobs) << c.out;
    for (const auto& u : p["units"])
      EXPECT_EQ(u["ranks"], u["kind"] == "lambda_point" ? c.ranks : 1) << c.out << u["id"];
  }
  // the point jobs ask Slurm for K tasks each (the job array of run "k" is the first sbatch)
  const std::string args = pnc::test::slurp(d / "sbatch.args");
  const std::string first = args.substr(0, args.find('\n'));
  EXPECT_NE(first.find("--ntasks=3 "), std::string::npos) << args;
  EXPECT_NE(first.find("--array=0-1 "), std::string::npos) << args;
  fs::remove_all(d);
}

// The same under a real `mpirun -np 2`: one supervisor plans and submits (one message, one
// submission of 2 jobs), the follower adds nothing.
TEST(ThermoTiParallel, MpirunNp2SubmitsOncePlannedOnTwoRanks) {
  const SlurmTi ti("test_ti_parallel_mpirun");
  const fs::path& d = ti.d;
  const auto r = pnc::test::run_command(ti.command(
      "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -np 2 --bind-to none",
      "o"));
  const std::string err = ti.err();
  ASSERT_EQ(r.code, 0) << err;
  EXPECT_EQ(count_of(err, "pnc: started by mpirun with 2 ranks: each LAMMPS stage runs on 2 "
                          "rank(s), 1 unit(s) at a time\n"),
            1u)
      << err;
  EXPECT_EQ(count_of(err, "pnc thermo ti: submitted 2 job(s)"), 1u) << err;
  EXPECT_EQ(count_of(pnc::test::slurp(d / "sbatch.args"), "\n"), 2u);
  const auto p = plan_of(d / "o");
  ASSERT_TRUE(p.is_object());
  EXPECT_EQ(p["parameters"]["ranks"], 2);
  EXPECT_EQ(p["parameters"]["jobs"], 1);
  fs::remove_all(d);
}
