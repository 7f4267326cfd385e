// Stages on K = 2 MPI ranks (runner.hpp StageSpec::ranks, lammps_server.hpp): the same
// calls give the same numbers as on one rank (a local compute's rows and a global too, D324),
// a LAMMPS error on 2 ranks is reported with LAMMPS's own message, and a stage killed mid-run
// takes its MPI server down with it.
#include "pnc/core/error.hpp"
#include "pnc/core/units.hpp"
#include "pnc/md/runner.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

using namespace pnc::md;
namespace fs = std::filesystem;
using pnc::test::slurp;

namespace {

fs::path tmpdir(const std::string& tag) {
  return pnc::test::fresh_dir("test_rve_mpi_" + tag);
}

// A 500-atom LJ FCC crystal with random displacements (no symmetry hides a wrong sum),
// then a short NVE run. Writes natoms, pe, press, positions and forces at step 0, pe, box
// length and positions at step 20 to `out`. create_atoms numbers the atoms per rank, so
// the same site has different ids on 1 and 2 ranks: the test matches atoms by position.
StageBody lj_body(const std::string& out) {
  return [out](Lammps& l) {
    l.cmds({"units lj", "lattice fcc 0.8442", "region box block 0 5 0 5 0 5", "create_box 1 box",
            "create_atoms 1 box", "mass 1 1.0", "displace_atoms all random 0.05 0.05 0.05 4821",
            "pair_style lj/cut 2.5", "pair_coeff 1 1 1.0 1.0 2.5", "pair_modify shift yes",
            "velocity all create 0.5 87287 loop geom", "fix 1 all nve",
            "thermo_style custom step pe press", "run 0"});
    std::ofstream f(out);
    f.precision(17);
    f << l.natoms() << " " << l.thermo("pe") << " " << l.thermo("press") << "\n";
    for (double v : l.gather("x", 3))
      f << v << "\n";
    for (double v : l.gather("f", 3))
      f << v << "\n";
    l.cmd("run 20");
    f << l.thermo("pe") << "\n";
    f << l.box().length(0) << "\n";
    for (double v : l.gather("x", 3))
      f << v << "\n";
  };
}

std::vector<double> read_numbers(const std::string& path) {
  std::ifstream f(path);
  std::vector<double> v;
  double x;
  while (f >> x)
    v.push_back(x);
  return v;
}

int count_servers(const std::string& tag) {
  // processes whose command line names this test's log directory (the server's -log FILE)
  int n = 0;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const auto name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmd = slurp((e.path() / "cmdline").string());
    for (auto& c : cmd)
      if (c == '\0') c = ' ';
    if (cmd.find("pnc_lammps_server") != std::string::npos && cmd.find(tag) != std::string::npos)
      ++n;
  }
  return n;
}

} // namespace

TEST(MdMpiStage, TwoRanksGiveTheSameNumbersAsOne) {
  const auto d = tmpdir("same");
  StageSpec one{"one rank", (d / "one.log").string(), {}, 1};
  StageSpec two{"two ranks", (d / "two.log").string(), {}, 2};
  const auto o1 = run_stage(one, lj_body((d / "one.txt").string()));
  const auto o2 = run_stage(two, lj_body((d / "two.txt").string()));
  ASSERT_TRUE(o1.ok) << o1.error;
  ASSERT_TRUE(o2.ok) << o2.error;
  // the second stage really ran on 2 ranks
  EXPECT_NE(slurp(two.log_path).find("on 2 procs"), std::string::npos);
  EXPECT_NE(slurp(one.log_path).find("on 1 procs"), std::string::npos);
  const auto a = read_numbers((d / "one.txt").string());
  const auto b = read_numbers((d / "two.txt").string());
  const std::size_t n = 500;
  ASSERT_EQ(a.size(), 3 + 6 * n + 2 + 3 * n);
  ASSERT_EQ(b.size(), a.size());
  ASSERT_EQ(a[0], 500.0);
  // atoms sorted by their step-0 position: the same site in both runs
  auto order = [n](const std::vector<double>& v) {
    std::vector<std::size_t> idx(n);
    for (std::size_t i = 0; i < n; ++i)
      idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&v](std::size_t p, std::size_t q) {
      for (int c = 0; c < 3; ++c)
        if (std::abs(v[3 + 3 * p + c] - v[3 + 3 * q + c]) > 1e-9)
          return v[3 + 3 * p + c] < v[3 + 3 * q + c];
      return false;
    });
    return idx;
  };
  const auto ia = order(a), ib = order(b);
  const std::size_t f0 = 3 + 3 * n, k = 3 + 6 * n, x1 = k + 2;
  // Same configuration, different summation order over the domain decomposition: energies
  // and forces agree to round-off, bounded by (pairs per atom ~ 75) x eps x |term| ~ 1e-12.
  EXPECT_NEAR(b[1], a[1], 1e-11 * std::abs(a[1]));       // pe
  EXPECT_NEAR(b[2], a[2], 1e-10 * (1 + std::abs(a[2]))); // press
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(b[3 + 3 * ib[i] + c], a[3 + 3 * ia[i] + c], 1e-12) << "site " << i;
      EXPECT_NEAR(b[f0 + 3 * ib[i] + c], a[f0 + 3 * ia[i] + c], 1e-10) << "force, site " << i;
    }
  // 20 NVE steps from the same velocities (loop geom: by site): round-off grows by the
  // Lyapunov factor (~e^(20 x 0.005 x ~5) < 2), far below 1e-8 in energy and positions
  EXPECT_NEAR(b[k], a[k], 1e-8 * std::abs(a[k]));
  EXPECT_DOUBLE_EQ(b[k + 1], a[k + 1]); // box length, untouched by NVE
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(b[x1 + 3 * ib[i] + c], a[x1 + 3 * ia[i] + c], 1e-8) << "x, site " << i;
  fs::remove_all(d);
}

// Writes what Lammps::compute_local_vector and extract_global_double (D324) give on an FCC
// crystal (a = 5 A, 4 x 4 x 4 cells, N = 256, cut-off 4.5 A between the first shell at a/sqrt 2
// and the second at a): the pair count and the sorted pair distances, again after a random
// displacement (which moves each atom by its position, the same on any rank count), the sum of
// the distances, nktv2p, and 1 for each bad request refused with an InputError.
StageBody local_body(const std::string& out) {
  return [out](Lammps& l) {
    l.cmds({"units real", "atom_style atomic", "lattice fcc 5.0", "region box block 0 4 0 4 0 4",
            "create_box 1 box", "create_atoms 1 box", "mass 1 39.9", "pair_style lj/cut 4.5",
            "pair_coeff 1 1 0.2 3.4", "compute pnc_pl all pair/local dist", "run 0"});
    std::ofstream f(out);
    f.precision(17);
    auto rows = [&] {
      std::vector<double> d = l.compute_local_vector("pnc_pl");
      std::sort(d.begin(), d.end());
      double sum = 0;
      for (double v : d)
        sum += v;
      f << d.size() << "\n" << sum << "\n";
      for (double v : d)
        f << v << "\n";
    };
    rows();
    // a new step: LAMMPS rebuilds pair/local's occasional neighbour list at most once per step
    l.cmds({"displace_atoms all random 0.2 0.2 0.2 4821 units box", "reset_timestep 1", "run 0"});
    rows();
    f << l.extract_global_double("nktv2p") << "\n";
    auto refused = [&f](const std::function<void()>& call) {
      try {
        call();
        f << 0 << "\n";
      } catch (const pnc::InputError&) {
        f << 1 << "\n";
      }
    };
    refused([&l] { l.compute_local_vector("no_such_compute"); });
    refused([&l] { l.compute_local_vector("thermo_pe"); }); // a global compute
    refused([&l] { l.extract_global_double("no_such_global"); });
  };
}

// D324: the rows of a local compute from the server's 2 ranks are one rank's rows (in another
// order), and a global double reads the same through the server as in-process.
TEST(MdMpiStage, LocalComputeRowsAndGlobalsFromTwoRanksEqualOneRanks) {
  const auto d = tmpdir("local");
  StageSpec one{"one rank", (d / "one.log").string(), {}, 1};
  StageSpec two{"two ranks", (d / "two.log").string(), {}, 2};
  const auto o1 = run_stage(one, local_body((d / "one.txt").string()));
  const auto o2 = run_stage(two, local_body((d / "two.txt").string()));
  ASSERT_TRUE(o1.ok) << o1.error;
  ASSERT_TRUE(o2.ok) << o2.error;
  EXPECT_NE(slurp(two.log_path).find("on 2 procs"), std::string::npos);
  const auto a = read_numbers((d / "one.txt").string());
  const auto b = read_numbers((d / "two.txt").string());
  // perfect crystal: 12 nearest neighbours per atom, each pair once: 6 N at a / sqrt 2
  const std::size_t n = 6 * 256;
  ASSERT_GT(a.size(), 2 + n + 2 + 4);
  ASSERT_EQ(b.size(), a.size());
  ASSERT_EQ(a[0], static_cast<double>(n));
  ASSERT_EQ(b[0], static_cast<double>(n));
  // positions are lattice products (a few ulp of the 20 A box): distances to 1e-12 relative
  const double nn = 5.0 / std::sqrt(2.0);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_NEAR(a[2 + i], nn, 1e-12 * nn) << i;
    ASSERT_NEAR(b[2 + i], nn, 1e-12 * nn) << i;
  }
  // displaced: the same pairs on both rank counts; a distance is a difference of positions
  // that may carry a periodic shift on one count and not the other (an ulp of the box length,
  // 4e-15 A), so sorted distances agree to 1e-12 relative, their sums to n x that
  const std::size_t k = 2 + n;
  ASSERT_EQ(b[k], a[k]);
  const std::size_t m = static_cast<std::size_t>(a[k]);
  ASSERT_GT(m, 0u);
  ASSERT_EQ(a.size(), k + 2 + m + 4);
  EXPECT_NEAR(b[k + 1], a[k + 1], 1e-12 * a[k + 1]);
  for (std::size_t i = 0; i < m; ++i)
    ASSERT_NEAR(b[k + 2 + i], a[k + 2 + i], 1e-12 * a[k + 2 + i]) << i;
  const std::size_t g = k + 2 + m;
  EXPECT_EQ(b[g], a[g]); // nktv2p: the same double
  // units real: atm per (kcal/mol)/A^3 from SI (LAMMPS keeps 8 digits of it: 1e-6 relative)
  const double atm = pnc::units::pa_per_kcal_mol_A3 / pnc::units::pa_per_atm;
  EXPECT_NEAR(a[g], atm, 1e-6 * atm);
  for (int r = 1; r <= 3; ++r) {
    EXPECT_EQ(a[g + r], 1.0) << "bad request " << r << " in-process";
    EXPECT_EQ(b[g + r], 1.0) << "bad request " << r << " on the server";
  }
  fs::remove_all(d);
}

TEST(MdMpiStage, LammpsErrorOnTwoRanksIsReportedWithLammpsMessage) {
  const auto d = tmpdir("err");
  StageSpec s{"bad on 2", (d / "bad.log").string(), {}, 2};
  const auto o = run_stage(s, [](Lammps& l) {
    l.cmd("units real");
    l.cmd("pair_style no_such_pair_style 2.5");
    l.cmd("print 'never reached'");
  });
  EXPECT_FALSE(o.ok);
  EXPECT_NE(o.error.find("ERROR"), std::string::npos) << o.error;
  EXPECT_NE(o.error.find("no_such_pair_style"), std::string::npos) << o.error;
  try { // the server's LAMMPS ended: a tool failure naming the command, the stage and the log
    throw_stage_failure(o, "stage bad on 2");
    ADD_FAILURE() << "no error";
  } catch (const pnc::ToolError& e) {
    const std::string m = e.what();
    EXPECT_EQ(e.context().tool, "LAMMPS");
    EXPECT_EQ(e.context().log_path, s.log_path);
    EXPECT_EQ(m.rfind("LAMMPS failed while running 'pair_style no_such_pair_style 2.5' on the "
                      "LAMMPS server (stage bad on 2): ERROR",
                      0),
              0u)
        << m;
  }
  // the parent goes on, and so does a following 2-rank stage
  const auto ok =
      run_stage({"good", (d / "good.log").string(), {}, 2}, [](Lammps& l) { l.cmd("units real"); });
  EXPECT_TRUE(ok.ok) << ok.error;
  fs::remove_all(d);
}

TEST(MdMpiStage, KilledStageTakesItsServerDown) {
  const auto d = tmpdir("kill");
  StageSpec s{"killed", (d / "killed.log").string(), {}, 2};
  const auto o = run_stage(s, [](Lammps& l) {
    l.cmds({"units lj", "lattice fcc 0.8442", "region box block 0 4 0 4 0 4", "create_box 1 box",
            "create_atoms 1 box", "mass 1 1.0", "pair_style lj/cut 2.5", "pair_coeff 1 1 1.0 1.0",
            "run 0"});
    std::raise(SIGKILL); // the stage child dies while its server waits for the next request
  });
  EXPECT_FALSE(o.ok);
  EXPECT_EQ(o.signal, SIGKILL);
  // every rank of that server ends (socket closed -> MPI_Abort; mpirun also gets SIGTERM)
  int left = -1;
  for (int i = 0; i < 100 && left != 0; ++i) {
    left = count_servers(d.string());
    if (left) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_EQ(left, 0) << "server processes outlived their stage";
  fs::remove_all(d);
}

// `mpirun -np 2 pnc rve lammps IN`: rank 0 supervises and runs the input on both ranks in a
// stage of its own; rank 1 leaves at once. One report line, and LAMMPS ran on 2 procs.
TEST(MdMpiStage, PncUnderMpirunRunsTheStageOnAllRanks) {
  const auto d = tmpdir("cli");
  {
    std::ofstream in(d / "lj.in");
    in << "units lj\nlattice fcc 0.8442\nregion box block 0 4 0 4 0 4\ncreate_box 1 box\n"
          "create_atoms 1 box\nmass 1 1.0\npair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0\n"
          "velocity all create 1.0 5 loop geom\nfix 1 all nve\nrun 50\n";
  }
  const std::string cmd = "cd " + d.string() +
                          " && OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                          "mpirun -np 2 --bind-to none " PNC_EXE
                          " rve lammps lj.in --log run.log 2> err.txt";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp((d / "err.txt").string());
  const std::string err = slurp((d / "err.txt").string());
  std::size_t lines = 0;
  for (std::size_t p = err.find("pnc rve lammps:"); p != std::string::npos;
       p = err.find("pnc rve lammps:", p + 1))
    ++lines;
  EXPECT_EQ(lines, 1u) << err;
  EXPECT_NE(err.find("on 2 rank(s)"), std::string::npos) << err;
  EXPECT_NE(slurp((d / "run.log").string()).find("on 2 procs"), std::string::npos);
  fs::remove_all(d);
}
