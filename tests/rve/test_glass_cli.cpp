// The glassy bead-spring polymer (model kg) through `pnc characterize` on a tiny recipe: the
// outputs of every stage, the glass state (denser than the built melt, less dense than the
// T = 0 crystal, at the thermostat's temperature), and that it is a solid on the time scale of
// a strain hold while its melt is not: after a small shear step the shear stress of a Maxwell
// body with relaxation time tau_M falls by exp(-dt / tau_M) between two windows dt apart; a
// solid on the hold time scale (tau_M >= the hold t_h) keeps at least exp(-dt / t_h) of it,
// while the melt (T* = 1, chains of 15 beads: Rouse time ~ 20-100 tau, ~ the hold)
// carries no shear stress at the end of the hold.
// `pnc recipe show demo_glass` (JSON and TOML) reads back as the preset.
#include "pnc/core/hdf5_io.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/md/lammps_path.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/rve/bead_spring.hpp"
#include "pnc/rve/recipe.hpp"

#include "common/run_command.hpp"
#include "common/temp_dir.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace pnc::rve;
using namespace pnc::md;

namespace {

pnc::test::CommandResult run(const std::string& args) {
  return pnc::test::run_command(std::string(PNC_EXE) + " " + args);
}

// 600 beads; 20 fs steps (0.008 tau); melt 16 tau, quench 82 tau, glass hold 25 tau; one MPI
// rank per stage (a small system on 2 ranks of a busy machine is slower than on 1)
const char* tiny_glass = R"({
  "name": "tiny_glass", "seed": 5, "model": "kg",
  "build": { "chains": 40, "beads_per_chain": 15, "density": 0.9, "min_distance": 3.5 },
  "equilibrate": { "timestep_fs": 20.0, "temperature": 80.0, "hot_temperature": 400.0,
                   "damp_fs": 2000.0, "pushoff_steps": 1000, "hot_steps": 2000,
                   "cool_steps": 10000, "pdamp_fs": 20000.0, "npt_steps": 3000,
                   "final_steps": 1000 },
  "deform": { "cases": [2, 6, 9], "strain_max": 0.03, "steps": 3, "timestep_fs": 20.0,
              "hold_steps": 1000, "sample_every": 10, "blocks": 5, "temperature": 80.0,
              "damp_fs": 2000.0 },
  "analysis": { "stress": "total", "moving_average": 1 },
  "run": { "jobs": 2 }
})";

struct Relaxation {
  double early = 0, early_se = 0, late = 0, late_se = 0; ///< atm, shear stress minus reference
};

/// From `restart`: 1000 steps at zero strain (reference shear stress), then shear xy by
/// `gamma` (affine remap) and 40 chunks of 100 steps (20 fs; the hold t_h = 80 ps = 33 tau) under
/// NVE + Langevin at T; the means of chunks 10..19 (t_h/4..t_h/2) and 30..39 (3t_h/4..t_h), s.e.
/// from the chunk means.
Relaxation shear_relaxation(const std::string& restart, double T, double gamma, const fs::path& dir,
                            const std::string& tag) {
  const std::string res = (dir / (tag + ".h5")).string();
  const auto out = run_stage({"shear " + tag, (dir / (tag + ".log")).string(), {}}, [&](Lammps& l) {
    l.cmd("units real");
    l.cmd("atom_style molecular");
    l.cmd("read_restart " + lammps_path(restart, "restart"));
    l.cmds(bead_spring_commands(BeadSpringForceField{}));
    l.cmd("change_box all triclinic");
    l.cmd("timestep 20");
    l.cmd("fix nve all nve");
    l.cmd(fmt::format("fix lan all langevin {0} {0} 2000 {1}", T, 4242));
    l.cmd("variable sxy equal -pxy");
    l.cmd("fix avg all ave/time 10 10 100 v_sxy c_thermo_temp");
    l.cmd("run 1000");
    double s0 = 0;
    for (int k = 0; k < 10; ++k) {
      l.cmd("run 100");
      s0 += l.fix_value("avg", 0) / 10;
    }
    l.cmd(
        fmt::format("change_box all xy final {:.12g} remap units box", gamma * l.box().length(1)));
    std::vector<double> c;
    for (int k = 0; k < 40; ++k) {
      l.cmd("run 100");
      c.push_back(l.fix_value("avg", 0) - s0);
    }
    pnc::h5::File h(res, pnc::h5::File::Mode::truncate);
    h.write_vector("/chunks", c);
  });
  EXPECT_TRUE(out.ok) << out.error;
  const auto c = pnc::h5::File(res, pnc::h5::File::Mode::read).read_vector("/chunks");
  auto window = [&](int a, double& m, double& se) {
    m = 0;
    for (int k = a; k < a + 10; ++k)
      m += c[k] / 10;
    double v = 0;
    for (int k = a; k < a + 10; ++k)
      v += (c[k] - m) * (c[k] - m) / 9;
    se = std::sqrt(v / 10);
  };
  std::string trace;
  for (double v : c)
    trace += fmt::format(" {:.0f}", v);
  std::cerr << tag << " shear stress minus reference, 40 chunks (atm):" << trace << "\n";
  Relaxation r;
  window(0, r.early, r.early_se);
  window(30, r.late, r.late_se);
  return r;
}

} // namespace

TEST(RveGlassCli, TinyGlassIsASolidOnTheHoldTimeScaleAndItsMeltIsNot) {
  const auto d = pnc::test::fresh_dir("test_rve_glass");
  std::ofstream(d / "tiny.json") << tiny_glass;
  const std::string out = (d / "out").string();
  const auto r = run("characterize " + (d / "tiny.json").string() + " --out " + out +
                     " --equilibrate-ranks 1 --json 2>" + (d / "err.txt").string());
  // 3 strain points a case: the fit may be "not usable" (4) or not converge (3)
  ASSERT_TRUE(r.code == 0 || r.code == 3 || r.code == 4) << r.code << " " << r.out;
  for (const char* f :
       {"build/rve.data", "build/build.h5", "equilibrate/pushoff.h5", "equilibrate/melt.h5",
        "equilibrate/quench.h5", "equilibrate/final.h5", "cases/case_2/checkpoint.h5",
        "cases/case_6/checkpoint.h5", "cases.h5", "card.h5", "report.md"})
    EXPECT_TRUE(fs::exists(fs::path(out) / f)) << f;
  // the shear both ways (case 9, D424): the same structure sheared to -gamma answers with a
  // stress of the other sign, each resolved (a solid: about G gamma = 15 MPa against a few MPa)
  const auto cases = pnc::damage::read_stress_strain_h5((fs::path(out) / "cases.h5").string());
  ASSERT_NE(cases.find(6), nullptr);
  ASSERT_NE(cases.find(9), nullptr);
  for (int id : {6, 9}) {
    const auto& c = *cases.find(id);
    const Eigen::Index k = c.strain.rows() - 1;
    const double sense = id == 6 ? 1.0 : -1.0;
    EXPECT_DOUBLE_EQ(c.strain(k, 5), sense * 0.03) << "case " << id;
    EXPECT_GT(sense * c.stress(k, 5), 3 * c.stress_stderr(k, 5))
        << "case " << id << ": sigma12 " << c.stress(k, 5) << " +- " << c.stress_stderr(k, 5);
  }
  // ... and the report sets them side by side (D428): a table row and a figure of the pair
  EXPECT_NE(pnc::test::slurp(fs::path(out) / "report.md").find("| 1-2 | 6, 9 | 1 |"),
            std::string::npos);
  const std::string err = pnc::test::slurp(d / "err.txt"); // and the summary on stderr
  EXPECT_NE(err.find("shear 1-2 both ways (cases 6, 9; 1 replica)"), std::string::npos) << err;
  const auto jobs = nlohmann::json::parse(pnc::test::slurp(fs::path(out) / "plots/figures.json"));
  const nlohmann::json* senses = nullptr;
  for (const auto& f : jobs["figures"])
    if (f["png"].get<std::string>().find("senses.png") != std::string::npos) senses = &f;
  ASSERT_NE(senses, nullptr) << jobs.dump();
  ASSERT_EQ((*senses)["panels"].size(), 1u);
  const auto& series = (*senses)["panels"][0]["series"];
  ASSERT_EQ(series.size(), 3u);
  const auto& neg = *cases.find(9);
  for (std::size_t k = 0; k < 3; ++k) // the negative sense with its sign turned, in MPa
    EXPECT_NEAR(series[1]["y"][k].get<double>(), -neg.stress(static_cast<Eigen::Index>(k), 5) / 1e6,
                1e-9);
  // resume of the finished run re-runs no stage of the glass protocol and no case
  std::vector<fs::file_time_type> stamps;
  const char* stages[] = {"equilibrate/pushoff.h5", "equilibrate/melt.h5", "equilibrate/quench.h5",
                          "equilibrate/final.h5", "cases/case_6/checkpoint.h5"};
  for (const char* f : stages)
    stamps.push_back(fs::last_write_time(fs::path(out) / f));
  const auto again =
      run("characterize " + (d / "tiny.json").string() + " --out " + out +
          " --resume --equilibrate-ranks 1 --no-plots 2>" + (d / "err2.txt").string());
  EXPECT_EQ(again.code, r.code);
  for (std::size_t k = 0; k < stamps.size(); ++k)
    EXPECT_EQ(fs::last_write_time(fs::path(out) / stages[k]), stamps[k]) << stages[k];
  const auto j = nlohmann::json::parse(r.out);
  const BeadSpringForceField ff;
  // --json in SI (D284): kg/m^3, the reduced density takes g/cm^3
  const double rho =
      ff.reduced_density(j["equilibrated"]["density_kg_per_m3"].get<double>() / 1000);
  // quenched at P = 0: denser than the built melt (rho* 0.847), below the LJ crystal at T = 0
  // (fcc at zero pressure, rho* 1.09 with the full potential; the cut one binds less)
  EXPECT_GT(rho, ff.reduced_density(0.9));
  EXPECT_LT(rho, 1.09);
  const double T = j["equilibrated"]["temperature_K"].get<double>();
  EXPECT_NEAR(T, 80.0, 0.05 * 80.0); // Langevin target; 200 beads: sd(T)/T ~ 0.06 per sample
  // The standard errors come from 10 chunk means each: a deviation is judged against Student's
  // t with 9 dof at two-sided 0.1 % (4.78), not 3 (1.5 % per check with 9 dof; four such checks
  // made a run fail by chance a few times in a hundred).
  const double t_crit = 4.78;
  // solid on the hold time scale: the window centres are dt = 3 t_h / 4 apart, so a solid keeps
  // >= exp(-3/4) of the early shear stress (t_crit standard errors of the difference allowed)
  const auto g = shear_relaxation((fs::path(out) / "equilibrate/final.restart").string(), 80.0,
                                  0.02, d, "glass");
  EXPECT_GT(g.late, 5 * g.late_se) << "glass: no shear stress left at the end of the hold";
  const double se_g = std::hypot(g.late_se, std::exp(-0.75) * g.early_se);
  EXPECT_GE(g.late, std::exp(-0.75) * g.early - t_crit * se_g)
      << "glass: early " << g.early << " late " << g.late << " atm";
  // the melt (T* = 1, build density) has relaxed by the end of the hold: zero within t_crit s.e.
  const auto m = shear_relaxation((fs::path(out) / "equilibrate/melt.restart").string(), 400.0,
                                  0.02, d, "melt");
  EXPECT_LT(std::fabs(m.late), t_crit * m.late_se)
      << "melt: early " << m.early << " late " << m.late << " +- " << m.late_se << " atm";
  // and the glass's late stress is above the melt's by more than 3 s.e. of the difference
  EXPECT_GT(g.late - m.late, 3 * std::hypot(g.late_se, m.late_se));
  fs::remove_all(d);
}

TEST(RveGlassCli, RecipeShowDemoGlassRoundTrips) {
  const auto d = pnc::test::fresh_dir("test_rve_glass_show");
  const Recipe ref = parse_recipe(preset_json("demo_glass"), "demo_glass");
  const auto show = run("recipe show demo_glass");
  ASSERT_EQ(show.code, 0);
  EXPECT_EQ(nlohmann::json::parse(show.out), preset_json("demo_glass"));
  EXPECT_EQ(nlohmann::json::parse(show.out)["model"], "kg");
  const auto toml = run("recipe show demo_glass --expanded --toml");
  ASSERT_EQ(toml.code, 0);
  std::ofstream(d / "g.toml") << toml.out;
  EXPECT_EQ(expanded_json(read_recipe((d / "g.toml").string())), expanded_json(ref));
  std::ofstream(d / "g.json") << show.out;
  EXPECT_EQ(expanded_json(read_recipe((d / "g.json").string())), expanded_json(ref));
  fs::remove_all(d);
}
