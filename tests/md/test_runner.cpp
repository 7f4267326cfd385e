// Stage runner: LAMMPS errors are reported with LAMMPS's own ERROR text and the parent
// survives; pnc errors thrown in the child are reported; stages run concurrently; the
// virial stress of a 2-atom periodic configuration matches the analytic value; every stage
// leaves an input file that plain `lmp -in` reruns.
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/subprocess.hpp"
#include "pnc/md/forcefield.hpp"
#include "pnc/md/runner.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

using namespace pnc::md;
namespace fs = std::filesystem;

namespace {
/// The thermo lines ("step pe ke press" rows) of a LAMMPS log, as printed.
std::vector<std::string> thermo_rows(const std::string& log) {
  std::vector<std::string> rows;
  std::istringstream in(pnc::test::slurp(log));
  bool table = false;
  for (std::string l; std::getline(in, l);) {
    if (l.find("Step") != std::string::npos && l.find("PotEng") != std::string::npos) {
      table = true;
      continue;
    }
    if (l.rfind("Loop time", 0) == 0) table = false;
    if (table) rows.push_back(l);
  }
  return rows;
}

fs::path tmpdir(const std::string& tag) {
  return pnc::test::fresh_dir("test_rve_runner_" + tag);
}
} // namespace

TEST(MdRunner, BadLammpsCommandIsReportedWithLammpsErrorAndParentSurvives) {
  const auto d = tmpdir("bad");
  StageSpec s{"bad stage", (d / "stage.log").string(), {}};
  const auto out = run_stage(s, [](Lammps& l) {
    l.cmd("units real");
    l.cmd("pair_style no_such_pair_style 2.5");
    l.cmd("print 'never reached'");
  });
  EXPECT_FALSE(out.ok);
  EXPECT_NE(out.exit_code, 0);
  EXPECT_EQ(out.error.rfind("ERROR", 0), 0u) << out.error;
  EXPECT_NE(out.error.find("no_such_pair_style"), std::string::npos) << out.error;
  EXPECT_NE(out.error.find("Last command"), std::string::npos) << out.error;
  // the LAMMPS output went to the stage log, which holds the same message
  std::ifstream f(s.log_path);
  std::string text((std::istreambuf_iterator<char>(f)), {});
  EXPECT_NE(text.find("no_such_pair_style"), std::string::npos);
  // the stage's input ends with the command that stopped LAMMPS (in.<stage>, D247)
  const std::string input = pnc::test::slurp(stage_input_path(s));
  EXPECT_EQ(fs::path(stage_input_path(s)).filename(), "in.bad_stage");
  EXPECT_EQ(input.substr(input.rfind('\n', input.size() - 2) + 1),
            "pair_style no_such_pair_style 2.5\n")
      << input;
  // and the parent keeps working: a good stage after the failure
  const auto ok =
      run_stage({"good", (d / "good.log").string(), {}}, [](Lammps& l) { l.cmd("units real"); });
  EXPECT_TRUE(ok.ok) << ok.error;
  fs::remove_all(d);
}

TEST(MdRunner, PncErrorInChildAndParallelStages) {
  const auto d = tmpdir("par");
  std::vector<std::pair<StageSpec, StageBody>> st;
  st.push_back({{"throws", (d / "a.log").string(), {}},
                [](Lammps&) { pnc::fail("recipe.json", "deform.steps", "0", "must be >= 1"); }});
  for (int i = 0; i < 3; ++i)
    st.push_back({{"ok" + std::to_string(i), (d / ("b" + std::to_string(i) + ".log")).string(), {}},
                  [](Lammps& l) { l.cmd("units real"); }});
  st.push_back({{"lmp error", (d / "c.log").string(), {}},
                [](Lammps& l) { l.cmd("run 10"); }}); // no box yet
  const auto out = run_stages(st, 2);
  ASSERT_EQ(out.size(), 5u);
  EXPECT_FALSE(out[0].ok);
  EXPECT_NE(out[0].error.find("deform.steps"), std::string::npos) << out[0].error;
  for (int i = 1; i <= 3; ++i)
    EXPECT_TRUE(out[i].ok) << out[i].error;
  EXPECT_FALSE(out[4].ok);
  EXPECT_EQ(out[4].error.rfind("ERROR", 0), 0u) << out[4].error;
  fs::remove_all(d);
}

namespace {
/// The error throw_stage_failure() throws for `o`, as (exit code, what()).
std::pair<int, std::string> thrown(const StageOutcome& o, const std::string& stage) {
  try {
    throw_stage_failure(o, stage);
  } catch (const std::exception& e) {
    return {pnc::exit_code_of(e), e.what()};
  }
  return {-1, ""};
}
} // namespace

// A failed stage becomes the error of its kind (core/error.hpp, docs/errors.md): LAMMPS ending
// the child is a ToolError (7) naming LAMMPS's message and the log; a pnc error thrown by the
// body in the child crosses the process boundary with its kind and parts; anything else is
// an internal error (2).
TEST(MdRunner, FailedStagesThrowTheErrorOfTheirKind) {
  const auto d = tmpdir("kinds");
  std::vector<std::pair<StageSpec, StageBody>> st;
  st.push_back(
      {{"lmp", (d / "lmp.log").string(), {}}, [](Lammps& l) { l.cmd("no_such_command_xyz 1"); }});
  st.push_back({{"input", (d / "in.log").string(), {}},
                [](Lammps&) { pnc::fail("recipe.json", "deform.steps", "0", "must be >= 1"); }});
  st.push_back({{"sim", (d / "sim.log").string(), {}}, [](Lammps&) {
                  pnc::fail_simulation("RVE box", 4000, 4.0, "ps", "cavitated\nfatal here");
                }});
  st.push_back({{"tool", (d / "tool.log").string(), {}},
                [](Lammps&) { pnc::fail_tool("mpirun", "starting", "exit 1", "m.log"); }});
  st.push_back({{"bug", (d / "bug.log").string(), {}},
                [](Lammps&) { throw std::out_of_range("vector::at"); }});
  const auto out = run_stages(st, 2);
  ASSERT_EQ(out.size(), 5u);
  for (const auto& o : out)
    ASSERT_FALSE(o.ok) << o.name;

  EXPECT_FALSE(out[0].child_error); // LAMMPS ended the child, no pnc error
  auto [code, what] = thrown(out[0], "stage lmp");
  EXPECT_EQ(code, pnc::exit_code::tool_failed);
  EXPECT_EQ(what.rfind("LAMMPS failed while running stage lmp: ERROR", 0), 0u) << what;
  EXPECT_NE(what.find("no_such_command_xyz"), std::string::npos) << what;
  EXPECT_NE(what.find("(log " + (d / "lmp.log").string() + ")"), std::string::npos) << what;
  EXPECT_EQ(out[0].input_path, (d / "in.lmp").string());
  EXPECT_NE(what.find("rerunnable with lmp -in: " + (d / "in.lmp").string()), std::string::npos)
      << what;

  std::tie(code, what) = thrown(out[1], "stage input"); // as before this contract
  EXPECT_EQ(code, pnc::exit_code::bad_input);
  EXPECT_EQ(what, (d / "in.log").string() +
                      ": field 'stage input': recipe.json: field 'deform.steps': value '0': "
                      "must be >= 1");

  try {
    throw_stage_failure(out[2], "stage sim");
    FAIL() << "no error";
  } catch (const pnc::SimulationError& e) {
    EXPECT_EQ(e.exit_code(), pnc::exit_code::simulation_failed);
    EXPECT_EQ(e.context().entity, "stage sim: RVE box");
    EXPECT_EQ(e.context().step, 4000);
    EXPECT_EQ(e.context().time, 4.0); // %.17g through the file: exact
    EXPECT_EQ(e.context().time_unit, "ps");
    EXPECT_EQ(e.context().message, "cavitated fatal here (log " + (d / "sim.log").string() + ")");
  }

  std::tie(code, what) = thrown(out[3], "stage tool");
  EXPECT_EQ(code, pnc::exit_code::tool_failed);
  EXPECT_EQ(what, "mpirun failed while starting (stage tool): exit 1 (log m.log)");

  std::tie(code, what) = thrown(out[4], "stage bug");
  EXPECT_EQ(code, pnc::exit_code::internal_error);
  EXPECT_NE(what.find("vector::at"), std::string::npos) << what;
  fs::remove_all(d);
}

TEST(MdRunner, VirialStressOfTwoAtomsMatchesAnalytic) {
  // Two LJ atoms in a periodic 30 A cube, separated along (1, 2, 2)/3 by r = 3.5 A; the
  // cutoff (10 A) sees only the direct pair. Virial: W_ab = r_a f_b (one pair),
  // P_ab = W_ab / V in atm (nktv2p of real units); LAMMPS's virial-only pressure must match.
  const auto d = tmpdir("virial");
  const double eps = 0.2, sig = 3.4, r = 3.5, L = 30;
  const double n[3] = {1.0 / 3, 2.0 / 3, 2.0 / 3};
  const std::string res = (d / "r.h5").string();
  const auto out = run_stage({"virial", (d / "v.log").string(), {}}, [&](Lammps& l) {
    l.cmds({"units real", "atom_style atomic", "boundary p p p", "region b block 0 30 0 30 0 30",
            "create_box 1 b", "mass 1 39.948", "create_atoms 1 single 10 10 10 units box",
            "create_atoms 1 single " + std::to_string(10 + r * n[0]) + " " +
                std::to_string(10 + r * n[1]) + " " + std::to_string(10 + r * n[2]) + " units box",
            "pair_style lj/cut 10", "pair_coeff 1 1 0.2 3.4", "compute pv all pressure NULL virial",
            "thermo_style custom step pe c_pv[1] c_pv[2] c_pv[3] c_pv[4] c_pv[5] c_pv[6]",
            "run 0"});
    std::vector<double> p;
    for (int i = 0; i < 6; ++i)
      p.push_back(l.compute_value("pv", i));
    // positions as LAMMPS stored them (create_atoms with %f-formatted coordinates)
    const auto x = l.gather("x", 3);
    for (int a = 0; a < 3; ++a)
      p.push_back(x[3 + a] - x[a]);
    pnc::h5::File h(res, pnc::h5::File::Mode::truncate);
    h.write_vector("/p", p);
  });
  ASSERT_TRUE(out.ok) << out.error;
  pnc::h5::File h(res, pnc::h5::File::Mode::read);
  const auto p = h.read_vector("/p");
  const double rr = std::sqrt(p[6] * p[6] + p[7] * p[7] + p[8] * p[8]);
  EXPECT_NEAR(rr, r, 1e-5);
  const double u[3] = {p[6] / rr, p[7] / rr, p[8] / rr};
  const double s6 = std::pow(sig / rr, 6);
  const double F = 24 * eps / rr * (2 * s6 * s6 - s6); // -dU/dr, > 0 repulsive
  const double nktv2p = 68568.415;                     // kcal/mol/A^3 -> atm
  const double W = rr * F;                             // r_ij . f_ij for the one pair
  const int lmp[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}}; // pxx pyy pzz pxy pxz pyz
  for (int k = 0; k < 6; ++k) {
    const double expect = W * u[lmp[k][0]] * u[lmp[k][1]] / (L * L * L) * nktv2p;
    EXPECT_NEAR(p[k], expect, 1e-9 * std::fabs(W / (L * L * L) * nktv2p)) << "component " << k;
  }
  EXPECT_GT(p[0], 0); // repulsive pair at r < 2^(1/6) sigma: positive pressure, sigma = -P < 0
  fs::remove_all(d);
}

// Every stage leaves in.<stage> beside its log; plain `lmp -in` (the Debian lammps binary, the
// same liblammps) reruns it from the directory its header names and prints the same thermo
// rows, digit for digit: serial LAMMPS with the same commands is deterministic. A value pnc
// read back chose the last command; the recorded command is the one that ran.
TEST(MdRunner, EveryStageLeavesAnInputThatPlainLmpRerunsToTheSameNumbers) {
  const auto d = tmpdir("input");
  const StageSpec s{"md run/1", (d / "md.log").string(), {}};
  const auto out = run_stage(s, [](Lammps& l) {
    l.cmds({"units lj", "atom_style atomic", "lattice fcc 0.8442", "region b block 0 4 0 4 0 4",
            "create_box 1 b", "create_atoms 1 box", "mass 1 1.0",
            "velocity all create 1.44 87287 loop geom", "pair_style lj/cut 2.5",
            "pair_coeff 1 1 1.0 1.0 2.5", "fix 1 all nve", "thermo 50",
            "thermo_style custom step pe ke press", "thermo_modify format float %22.16g",
            "run 200"});
    l.cmd(l.thermo("pe") < 0 ? "run 100" : "run 50"); // a dense LJ liquid: pe < 0
  });
  ASSERT_TRUE(out.ok) << out.error;
  const std::string in = stage_input_path(s);
  ASSERT_EQ(fs::path(in).filename(), "in.md_run_1");
  const std::string text = pnc::test::slurp(in);
  EXPECT_NE(text.find("# Rerun from " + fs::current_path().string()), std::string::npos) << text;
  EXPECT_NE(text.find("\nrun 100\n"), std::string::npos) << text;
  const std::string rerun_log = (d / "rerun.log").string();
  const auto r = pnc::run_subprocess({"lmp", "-in", in, "-log", rerun_log, "-screen", "none"});
  ASSERT_TRUE(r.ok()) << r.error << r.output;
  const auto a = thermo_rows(s.log_path), b = thermo_rows(rerun_log);
  EXPECT_EQ(a.size(), 5u + 3u) << "rows at steps 0..200 and 200..300";
  EXPECT_EQ(a, b);
  fs::remove_all(d);
}
