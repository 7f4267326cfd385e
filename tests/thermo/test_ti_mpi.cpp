// Lambda points on K = 2 MPI ranks (`pnc thermo ti --ranks`, D324): the set-up checks of a
// point (pair-distance sums, LAMMPS's finite difference, the virial identity) on 2 ranks equal
// those on 1 rank for the same configuration to round-off, and a short TI on 2 ranks gives the
// free-energy difference of a TI on 1 rank within the combined statistical error.
#include "pnc/core/units.hpp"
#include "pnc/thermo/analysis.hpp"
#include "pnc/thermo/ti.hpp"

#include "lj_fluid.hpp"

#include "common/temp_dir.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>

using namespace pnc::thermo;
namespace fs = std::filesystem;
using pnc::test::slurp;

namespace {

fs::path tmpdir(const std::string& tag) {
  return pnc::test::fresh_dir("test_thermo_mpi_" + tag);
}

/// Runs one lambda point of `sys` on `ranks` ranks into dir/<tag>.h5 and reads it back.
PointResult run_point(const SamplingSpec& s, const LambdaSystem& sys, const fs::path& dir,
                      const std::string& tag, int ranks) {
  PointJob j;
  j.lambda = 0.5;
  j.lambda_prev = 0.3;
  j.lambda_next = 0.7;
  j.h5 = (dir / (tag + ".h5")).string();
  j.label = tag;
  j.seed = 11;
  run_points(s, {{j, sys}}, false, 1, nullptr, ranks);
  return read_point(j.h5);
}

} // namespace

// The checks run on the configuration before any dynamics (equil_steps 0; the atoms displaced
// by their positions, the same on both rank counts): the same pairs, summed in another order.
// Round-off: ~5000 pair terms, each sum off by at most n eps sum|t| ~ 1e-12 |U|: 1e-10 |U|
// bounds every sum. LAMMPS's finite difference combines four energies with weights whose
// magnitudes add to 1.5/h, so it may move by 1.5/h x that.
TEST(ThermoTiMpi, ChecksOnTwoRanksEqualOneRankOnTheSameConfiguration) {
  const auto d = tmpdir("checks");
  const LjPath p;
  const LambdaSystem sys = pnc::test::lj_fluid(p, 300, "pairs", 0.4);
  SamplingSpec s;
  s.timestep_fs = 2.0;
  s.equil_steps = 0;
  s.prod_steps = 30;
  s.sample_every = 10;
  s.blocks = 3;
  const PointResult a = run_point(s, sys, d, "one", 1);
  const PointResult b = run_point(s, sys, d, "two", 2);
  EXPECT_NE(slurp(d / "one.log").find("on 1 procs"), std::string::npos);
  EXPECT_NE(slurp(d / "two.log").find("on 2 procs"), std::string::npos);
  const double u = std::fabs(a.checks.at("u_pnc")), tol = 1e-10 * u;
  ASSERT_GT(u, 0);
  EXPECT_EQ(b.checks.at("pairs"), a.checks.at("pairs"));
  EXPECT_GT(a.checks.at("pairs"), 1000);
  EXPECT_EQ(b.checks.at("volume"), a.checks.at("volume"));
  EXPECT_EQ(b.checks.at("fd_h"), a.checks.at("fd_h"));
  for (const char* k : {"u_pnc", "u_lammps", "dhdl_pnc", "du_probe_pnc", "dhdl_virial_identity",
                        "du_probe_virial_identity"})
    EXPECT_NEAR(b.checks.at(k), a.checks.at(k), tol) << k;
  const double fd_tol = 1.5 / a.checks.at("fd_h") * tol;
  for (const char* k : {"fd_dhdl_lammps", "fd_error_estimate"})
    EXPECT_NEAR(b.checks.at(k), a.checks.at(k), fd_tol) << k;
  // and the 2-rank numbers are right, not only alike: the pair sum against LAMMPS's energy
  EXPECT_NEAR(b.checks.at("u_pnc"), b.checks.at("u_lammps"), 1e-9 * u);
  EXPECT_NEAR(b.checks.at("dhdl_pnc"), b.checks.at("fd_dhdl_lammps"),
              b.checks.at("fd_error_estimate"));
  // the pair-distance sampler ran on 2 ranks after the checks (one sample per 10 steps)
  ASSERT_EQ(b.dhdl_s.size(), 3u);
  for (double v : b.dhdl_s)
    EXPECT_TRUE(std::isfinite(v));
  fs::remove_all(d);
}

// The same TI window (Simpson over lambda 0.86..0.90 of the LJ fluid, the virial sampler) on 1
// and on 2 ranks: other trajectories (the thermostat's random numbers are per rank), the same
// ensemble, so Delta A agrees within 4 combined standard errors.
TEST(ThermoTiMpi, TwoRankTiAgreesWithOneRankWithinTheStatisticalError) {
  const auto d = tmpdir("ti");
  const LjPath p;
  const double T = 300;
  const LambdaSystem sys = pnc::test::lj_fluid(p, T);
  SamplingSpec s;
  s.timestep_fs = 2.0;
  s.equil_steps = 1000;
  s.prod_steps = 8000;
  s.sample_every = 10;
  s.blocks = 10;
  s.temperature = T;
  const double a = 0.86, b = 0.90, h = b - a;
  const Quadrature simpson{"simpson", {a, 0.5 * (a + b), b}, {h / 6, 4 * h / 6, h / 6}};
  const double kT = pnc::units::kB_kcal_mol_K * T;
  LambdaIntegral li[2];
  for (int k = 0; k < 2; ++k) {
    const auto jobs = node_jobs(simpson, (d / std::to_string(k + 1)).string(), "lj", 500);
    std::vector<std::pair<PointJob, LambdaSystem>> pj;
    for (const auto& j : jobs)
      pj.push_back({j, sys});
    run_points(s, pj, false, k == 0 ? 2 : 1, nullptr, k + 1); // 2 cores either way
    li[k] = collect(simpson, jobs, kT, s.blocks);
  }
  EXPECT_NE(slurp(d / "2" / "lambda_0.log").find("on 2 procs"), std::string::npos);
  std::cerr << fmt::format("  LJ fluid A({}) - A({}): 1 rank {:.4f} +- {:.4f}, 2 ranks {:.4f} +- "
                           "{:.4f} kcal/mol\n",
                           b, a, li[0].dA.value, li[0].dA.se, li[1].dA.value, li[1].dA.se);
  for (const auto& x : li)
    EXPECT_GT(std::fabs(x.dA.value), 10 * x.dA.se) << "the difference must be resolved";
  EXPECT_NEAR(li[1].dA.value, li[0].dA.value, 4 * std::hypot(li[0].dA.se, li[1].dA.se));
  fs::remove_all(d);
}
