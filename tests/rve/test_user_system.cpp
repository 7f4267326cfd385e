// "Characterize your own system": recipe parsing and validation (JSON and TOML), the shipped
// examples, and the LJ FCC crystal through the CLI against lattice sums computed here.
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/rve/deform.hpp"
#include "pnc/rve/equilibrate.hpp"
#include "pnc/rve/recipe.hpp"

#include "common/run_command.hpp"
#include "common/temp_dir.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

namespace fs = std::filesystem;
using nlohmann::json;
using pnc::test::slurp;
using namespace pnc::rve;
using namespace pnc::md;

namespace {

const fs::path kExamples = fs::path(PNC_SOURCE_DIR) / "examples" / "rve";

fs::path scratch(const std::string& name) {
  return pnc::test::fresh_dir(name);
}

/// A minimal valid user-system recipe whose data file lies in `dir`.
json user_recipe(const fs::path& dir) {
  std::ofstream(dir / "tiny.data") << "x\n\n1 atoms\n1 atom types\n\n0 10 xlo xhi\n0 10 ylo yhi\n"
                                      "0 10 zlo zhi\n\nMasses\n\n1 39.948\n\nAtoms\n\n1 1 0 0 0\n";
  return json::parse(R"({
    "name": "user", "model": "pp",
    "system": { "data_file": "tiny.data", "atom_style": "atomic", "units": "real",
                "forcefield": ["pair_style lj/cut 8.5", "pair_coeff * * 0.2381 3.405"] },
    "deform": { "temperature": 0.0, "strain_max": 0.001, "steps": 3 }
  })");
}

/// The InputError text of parsing `j` as if it were the file `dir`/recipe.json ("" if none).
std::string error_of(const json& j, const fs::path& dir) {
  try {
    parse_recipe(j, (dir / "recipe.json").string());
  } catch (const pnc::InputError& e) {
    return e.what();
  }
  return "";
}

// ---- lattice sums for the LJ FCC crystal of examples/rve/lj_fcc (independent of LAMMPS) ----
constexpr double kEps = 0.2381, kSig = 3.405, kRc = 8.5; // kcal/mol, A, A (recipe.toml)
constexpr double kPaPerKcalMolA3 = 4184.0 / 6.02214076e23 * 1e30;

double dphi(double r) { // d/dr of 4 eps ((s/r)^12 - (s/r)^6), kcal/mol/A
  const double s6 = std::pow(kSig / r, 6);
  return 4 * kEps * (-12 * s6 * s6 + 6 * s6) / r;
}

/// Cauchy stress (Pa, tension positive, Voigt 11 22 33 23 13 12) of the perfect FCC lattice of
/// constant `a` deformed affinely by F: sigma = (1/(2 Omega)) sum_n phi'(r_n) r_n (x) r_n / r_n
/// over the neighbours within the cutoff, Omega = det F a^3 / 4 (the pair virial per atom).
Eigen::Matrix<double, 6, 1> lattice_stress(double a, const Eigen::Matrix3d& F) {
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  const int n = 4;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k)
        for (const auto& b : basis) {
          const Eigen::Vector3d r0(a * (i + b[0]), a * (j + b[1]), a * (k + b[2]));
          const Eigen::Vector3d r = F * r0;
          const double d = r.norm();
          if (d == 0 || d >= kRc) continue;
          s += dphi(d) / d * r * r.transpose();
        }
  s /= 2 * F.determinant() * a * a * a / 4;
  Eigen::Matrix<double, 6, 1> v;
  v << s(0, 0), s(1, 1), s(2, 2), s(1, 2), s(0, 2), s(0, 1);
  return v * kPaPerKcalMolA3;
}

/// The edge of the shipped cubic box (4 x 4 x 4 FCC cells), Angstrom.
double shipped_box_length() {
  std::istringstream data(slurp(kExamples / "lj_fcc" / "fcc.data"));
  std::string line;
  double L = 0;
  while (std::getline(data, line))
    if (line.find("xlo xhi") != std::string::npos) {
      std::istringstream(line) >> L >> L;
      break;
    }
  return L;
}

struct LatticeSums {
  double p0, C11, C12, C44; ///< Pa: sigma11 of the undeformed lattice, the cubic constants
};
/// The cubic constants of the lattice in the shipped box of edge L (a = L / 4), by central
/// differences of lattice_stress at +-1e-6.
LatticeSums lattice_sums(double L) {
  const double a0 = L / 4;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double h = 1e-6;
  auto at = [&](int i, int j, double e) {
    Eigen::Matrix3d F = I;
    F(i, j) += e;
    return lattice_stress(a0, F);
  };
  return {lattice_stress(a0, I)[0], (at(1, 1, h)[1] - at(1, 1, -h)[1]) / (2 * h),
          (at(1, 1, h)[0] - at(1, 1, -h)[0]) / (2 * h),
          (at(0, 1, h)[5] - at(0, 1, -h)[5]) / (2 * h)};
}

} // namespace

TEST(RveUserSystem, ShippedExamplesParse) {
  for (const char* ex : {"lj_fcc", "bead_spring_glass"}) {
    const Recipe r = read_recipe((kExamples / ex / "recipe.toml").string());
    EXPECT_TRUE(r.system.enabled) << ex;
    EXPECT_TRUE(fs::exists(r.system.input_file)) << ex;
    EXPECT_EQ(r.system.fnv1a64.size(), 16u);
    // the expanded form (absolute path + hash) reads back to the same recipe
    EXPECT_EQ(expanded_json(parse_recipe(expanded_json(r), "x")), expanded_json(r)) << ex;
  }
  const Recipe lj = read_recipe((kExamples / "lj_fcc" / "recipe.toml").string());
  EXPECT_EQ(lj.system.atom_style, "atomic");
  EXPECT_TRUE(lj.system.stages.empty());
  EXPECT_EQ(lj.deform.temperature, 0.0);
  EXPECT_TRUE(lj.deform.minimize);
  const Recipe bs = read_recipe((kExamples / "bead_spring_glass" / "recipe.toml").string());
  ASSERT_EQ(bs.system.stages.size(), 4u);
  EXPECT_EQ(bs.system.stages[0].kind, "minimize");
  EXPECT_EQ(bs.system.stages[2].t_end(), 10.0);
  EXPECT_EQ(bs.system.stages[3].kind, "npt");
  EXPECT_GT(bs.deform.temperature, 0.0);
}

TEST(RveUserSystem, JsonAndTomlAgree) {
  const auto d = scratch("test_user_sys_formats");
  const json j = user_recipe(d);
  std::ofstream(d / "r.json") << j.dump(2);
  std::ofstream(d / "r.toml") << recipe_toml(j);
  EXPECT_EQ(expanded_json(read_recipe((d / "r.json").string())),
            expanded_json(read_recipe((d / "r.toml").string())));
  fs::remove_all(d);
}

TEST(RveUserSystem, ValidationErrorsNameFieldValueRule) {
  const auto d = scratch("test_user_sys_errors");
  const json ok = user_recipe(d);
  EXPECT_EQ(error_of(ok, d), "");
  auto with = [&](const std::string& ptr, const json& v) {
    json j = ok;
    j[json::json_pointer(ptr)] = v;
    return error_of(j, d);
  };
  std::string e = with("/system/units", "metal");
  EXPECT_NE(e.find("system.units"), std::string::npos) << e;
  EXPECT_NE(e.find("metal"), std::string::npos) << e;
  EXPECT_NE(e.find("real"), std::string::npos) << e;
  for (const char* bad :
       {"shell rm -rf x", "include other.in", "python f input 1 x", "run 100", "write_data x.data",
        "log x.log", "print hi file x", "pair_style python 2.5", "pair_coeff * * ${e} 3.4",
        "pair_coeff * * 0.2 3.4 &", "fix 1 all nve"}) {
    json j = ok;
    j["system"]["forcefield"].push_back(bad);
    e = error_of(j, d);
    EXPECT_NE(e.find("system.forcefield[2]"), std::string::npos) << bad << ": " << e;
  }
  e = with("/system/data_file", "missing.data");
  EXPECT_NE(e.find("system.data_file"), std::string::npos) << e;
  EXPECT_NE(e.find("no such file"), std::string::npos) << e;
  e = with("/system/restart_file", "tiny.data");
  EXPECT_NE(e.find("exactly one"), std::string::npos) << e;
  e = with("/system/atom_style", "hybrid atomic");
  EXPECT_NE(e.find("system.atom_style"), std::string::npos) << e;
  e = with("/system/colour", "red");
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
  e = with("/system/fnv1a64", "0000000000000000");
  EXPECT_NE(e.find("changed"), std::string::npos) << e;
  e = with("/build", json::object());
  EXPECT_NE(e.find("builder"), std::string::npos) << e;
  e = with("/equilibrate", json::parse(R"({"stages": [{"kind": "nose"}]})"));
  EXPECT_NE(e.find("equilibrate.stages[0].kind"), std::string::npos) << e;
  e = with("/equilibrate", json::parse(R"({"stages": [{"kind": "langevin", "steps": 1000}]})"));
  EXPECT_NE(e.find("equilibrate.stages[0].temperature"), std::string::npos) << e;
  e = with("/equilibrate", json::parse(R"({"hot_steps": 10})"));
  EXPECT_NE(e.find("equilibrate.hot_steps"), std::string::npos) << e;
  json nounits = ok;
  nounits["system"].erase("units");
  e = error_of(nounits, d);
  EXPECT_NE(e.find("system.units"), std::string::npos) << e;
  fs::remove_all(d);
}

// The LJ crystal through `pnc characterize`: C11, C12, C44 of the fit against lattice sums.
// Why 1 %: the lattice sums are exact derivatives at zero strain (central differences at
// +-1e-6, truncation error ~1e-12 relative); the MD side fits sigma over 0 < eps <= 2e-4, where
// the quadratic term of sigma(eps) (third-order constants of LJ crystals are ~10 C11 in
// magnitude) shifts a secant/least-squares slope by ~10 x 1e-4 = 0.1 %; the minimiser stops on a
// force norm of 1e-10 kcal/mol/A (in a Bravais lattice the affine positions are already the
// minimum by symmetry), and LAMMPS's stress is exact to round-off. 1 % leaves a margin of ~10 on
// the nonlinearity while still catching any unit, sign, volume or factor-2 error.
TEST(RveUserSystem, LjCrystalStaticElasticConstantsMatchLatticeSums) {
  const auto d = scratch("test_user_sys_lj");
  fs::copy(kExamples / "lj_fcc" / "recipe.toml", d / "recipe.toml");
  fs::copy(kExamples / "lj_fcc" / "fcc.data", d / "fcc.data");
  // the shipped data file is at the zero-pressure lattice constant: its virial vanishes
  const LatticeSums sums = lattice_sums(shipped_box_length());
  const double C11 = sums.C11, C12 = sums.C12, C44 = sums.C44;
  EXPECT_LT(std::fabs(sums.p0), 1e-9 * C11) << "data file not at zero pressure: " << sums.p0;
  EXPECT_GT(C11, 1e9); // a few GPa for argon-like LJ
  EXPECT_GT(C44, 1e9);

  const std::string out = (d / "out").string();
  const auto r = pnc::test::run_command(std::string(PNC_EXE) + " characterize " +
                                        (d / "recipe.toml").string() + " --out " + out +
                                        " --json --no-plots 2>" + (d / "err.txt").string());
  ASSERT_TRUE(r.code == 0 || r.code == 3 || r.code == 4) << r.code << slurp(d / "err.txt");
  const auto j = json::parse(r.out);
  const auto& c = j["constants"];
  EXPECT_NEAR(c["C11"]["value"].get<double>(), C11, 0.01 * C11);
  EXPECT_NEAR(c["C12"]["value"].get<double>(), C12, 0.01 * C12);
  EXPECT_NEAR(c["C44"]["value"].get<double>(), C44, 0.01 * C44);
  // static rows carry no standard errors, so none reach cases.h5 (the fit's no-errors path)
  const auto cases = pnc::damage::read_stress_strain_h5((fs::path(out) / "cases.h5").string());
  ASSERT_EQ(cases.cases.size(), 2u);
  for (const auto& cc : cases.cases)
    EXPECT_EQ(cc.stress_stderr.rows(), 0) << cc.id;
  EXPECT_NE(cases.stress_definition.find("static"), std::string::npos);
  // at 0 K with zero velocities the total stress equals the virial stress
  const CaseResult c2 = read_case((fs::path(out) / "cases" / "case_2").string());
  EXPECT_LT((c2.stress_total - c2.stress_virial).cwiseAbs().maxCoeff(), 1e-6 * C11 * 2e-4);
  EXPECT_TRUE(std::isnan(c2.stress_virial_se(1, 1)));
  EXPECT_NEAR(j["equilibrated"]["pressure_Pa"].get<double>(), 0.0, 1e-6 * 101325); // 1e-6 atm
  EXPECT_TRUE(fs::exists(fs::path(out) / "build" / "system.data"));
  EXPECT_EQ(slurp(fs::path(out) / "build" / "system.data"), slurp(d / "fcc.data"));
  EXPECT_EQ(j["fit"]["error_model"], "sandwich (HC3)"); // the fit's no-data-errors path
  EXPECT_NE(slurp(fs::path(out) / "report.md").find("User system: data file"), std::string::npos);

  // the same crystal from a restart file (the measured start state of the run above), without
  // the per-row minimisation (the affine positions of a Bravais lattice are already relaxed),
  // sheared in the negative sense (case 9, D424): the box tilts the other way, the same C44
  fs::copy(fs::path(out) / "equilibrate" / "final.restart", d / "fcc.restart");
  std::string toml = slurp(d / "recipe.toml");
  toml.replace(toml.find("data_file = \"fcc.data\""), 22, "restart_file = \"fcc.restart\"");
  toml.replace(toml.find("minimize = true"), 15, "minimize = false");
  toml.replace(toml.find("cases = [2, 6]"), 14, "cases = [2, 9]");
  std::ofstream(d / "restart.toml") << toml;
  const std::string out2 = (d / "out2").string();
  const auto r2 = pnc::test::run_command(std::string(PNC_EXE) + " characterize " +
                                         (d / "restart.toml").string() + " --out " + out2 +
                                         " --json --no-plots 2>" + (d / "err2.txt").string());
  ASSERT_TRUE(r2.code == 0 || r2.code == 3 || r2.code == 4) << r2.code << slurp(d / "err2.txt");
  const auto j2 = json::parse(r2.out);
  for (const auto& [k, ref] : {std::pair{"C11", C11}, {"C12", C12}, {"C44", C44}})
    EXPECT_NEAR(j2["constants"][k]["value"].get<double>(), ref, 0.01 * ref) << k;
  const auto neg = pnc::damage::read_stress_strain_h5((fs::path(out2) / "cases.h5").string());
  ASSERT_NE(neg.find(9), nullptr);
  EXPECT_LE(neg.find(9)->strain.col(5).maxCoeff(), 0.0); // gamma12 <= 0 on every row
  EXPECT_LT(neg.find(9)->strain.col(5).minCoeff(), 0.0);
  EXPECT_TRUE(fs::exists(fs::path(out2) / "build" / "system.restart"));

  // --resume of the finished run with the same input: accepted, nothing recomputed
  const auto again = pnc::test::run_command(std::string(PNC_EXE) + " characterize " +
                                            (d / "recipe.toml").string() + " --out " + out +
                                            " --resume --no-plots 2>/dev/null");
  EXPECT_EQ(again.code, r.code);
  // a changed data file is detected on --resume, naming the file and the rule
  std::ofstream(d / "fcc.data", std::ios::app) << "\n";
  const auto changed = pnc::test::run_command(std::string(PNC_EXE) + " characterize " +
                                              (d / "recipe.toml").string() + " --out " + out +
                                              " --resume --no-plots 2>&1");
  EXPECT_EQ(changed.code, 1);
  EXPECT_NE(changed.out.find("system.data_file"), std::string::npos) << changed.out;
  EXPECT_NE(changed.out.find("changed since this run was made"), std::string::npos) << changed.out;
  fs::remove_all(d);
}

// The user stages on the bead-spring example's data file, shortened: every stage writes its
// record, the NPT stage hands on its mean volume (decision D123), the final measurement
// reports the last dynamic stage's temperature, and --resume re-runs nothing.
TEST(RveUserSystem, UserStagesRunMeasureAndResume) {
  const auto d = scratch("test_user_sys_stages");
  Recipe r = read_recipe((kExamples / "bead_spring_glass" / "recipe.toml").string());
  UserSystem u = r.system;
  u.stages.clear();
  UserStage m;
  m.kind = "minimize";
  m.ftol = 2.0;
  UserStage npt;
  npt.kind = "npt";
  npt.temperature = 30;
  npt.steps = 400;
  npt.timestep_fs = 10;
  npt.damp_fs = 1000;
  npt.pdamp_fs = 10000;
  UserStage lan;
  lan.kind = "langevin";
  lan.temperature = 30;
  lan.steps = 600;
  lan.timestep_fs = 10;
  lan.damp_fs = 100; // 60 damping times: the kinetic temperature is relaxed to 30 K
  u.stages = {m, npt, lan};
  const std::string eq = (d / "eq").string();
  const auto e = equilibrate_user(u, u.input_file, eq, false, "{}", 3, 1);
  ASSERT_EQ(e.criteria.size(), 4u);
  EXPECT_NE(e.criteria[1].find("NPT"), std::string::npos) << e.criteria[1];
  for (const char* f : {"stage_1_minimize", "stage_2_npt", "stage_3_langevin", "final"})
    for (const char* ext : {".h5", ".restart", ".log"})
      EXPECT_TRUE(fs::exists(fs::path(eq) / (std::string(f) + ext))) << f << ext;
  // the box after NPT has the mean volume of its second half: the density of the start state
  // equals that mean (the Langevin stage keeps the box)
  const auto tr =
      pnc::h5::File((fs::path(eq) / "stage_2_npt.h5").string(), pnc::h5::File::Mode::read)
          .read_matrix("/trace");
  const Eigen::Index k = tr.rows() - tr.rows() / 2;
  const double vmean = tr.col(5).tail(k).mean(); // A^3
  // 600 beads of 50 g/mol; 1e-6: LAMMPS's g/mol/A^3 -> g/cm^3 factor uses an older N_A
  EXPECT_NEAR(e.density, 600 * 50.0 / (0.602214076 * vmean), 1e-6 * e.density);
  // equilibrium chunk means of T for 600 beads fluctuate by a few % (sd of the instantaneous
  // kinetic T is sqrt(2/(3N)) = 3.3 %); 15 % catches missing velocities or unit errors
  EXPECT_NEAR(e.temperature, 30.0, 4.5);
  EXPECT_GT(e.min_distance, 2.0); // A; no overlap (sigma = 4 A)
  EXPECT_TRUE(std::isnan(e.void_fraction));
  const auto t1 = fs::last_write_time(fs::path(eq) / "stage_2_npt.h5");
  const auto again = equilibrate_user(u, u.input_file, eq, true, "{}", 3, 1);
  EXPECT_EQ(fs::last_write_time(fs::path(eq) / "stage_2_npt.h5"), t1);
  EXPECT_EQ(again.density, e.density);
  fs::remove_all(d);
}

// The committed data files are what the committed generator scripts write.
TEST(RveUserSystem, GeneratorsReproduceTheShippedDataFiles) {
  // python3 is a dependency of pnc (scripts/common.sh installs it): its absence is a failure
  ASSERT_EQ(pnc::test::run_command("python3 -c 0 >/dev/null 2>&1").code, 0) << "no python3";
  const auto d = scratch("test_user_sys_gen");
  for (const auto& [ex, file] :
       {std::pair{"lj_fcc", "fcc.data"}, std::pair{"bead_spring_glass", "chains.data"}}) {
    const auto r = pnc::test::run_command("python3 " + (kExamples / ex / "make_data.py").string() +
                                          " " + (d / file).string());
    ASSERT_EQ(r.code, 0) << ex << r.out;
    EXPECT_EQ(slurp(d / file), slurp(kExamples / ex / file)) << ex;
  }
  fs::remove_all(d);
}

// The bead-spring example through the CLI, shortened (finite temperature, atom_style molecular,
// bonds): the cases re-issue the user's force field, the holds carry standard errors.
TEST(RveUserSystem, BeadSpringShortRunThroughCli) {
  const auto d = scratch("test_user_sys_bs");
  Recipe full = read_recipe((kExamples / "bead_spring_glass" / "recipe.toml").string());
  json j = expanded_json(full); // absolute data path + hash
  for (auto& st : j["equilibrate"]["stages"])
    if (st.contains("steps")) st["steps"] = 600;
  j["deform"]["steps"] = 3;
  j["deform"]["hold_steps"] = 200;
  std::ofstream(d / "short.json") << j.dump(2);
  const std::string out = (d / "out").string();
  const auto r = pnc::test::run_command(
      std::string(PNC_EXE) + " characterize " + (d / "short.json").string() + " --out " + out +
      " --json --no-plots --equilibrate-ranks 1 2>" + (d / "err.txt").string());
  ASSERT_TRUE(r.code == 0 || r.code == 3 || r.code == 4) << r.code << slurp(d / "err.txt");
  const auto o = json::parse(r.out);
  EXPECT_EQ(o["equilibrated"]["ensemble"], "user stages");
  // the reported T and P are the means of the second half of the last (NPT) stage's chunks
  // (decision D123; 600 steps are too short for T to have relaxed to 10 K)
  const auto tr = pnc::h5::File((fs::path(out) / "equilibrate" / "stage_4_npt.h5").string(),
                                pnc::h5::File::Mode::read)
                      .read_matrix("/trace");
  const Eigen::Index k = tr.rows() - tr.rows() / 2;
  EXPECT_NEAR(o["equilibrated"]["temperature_K"].get<double>(), tr.col(0).tail(k).mean(), 1e-9);
  // --json in SI (D284): the trace's atm in Pa
  EXPECT_NEAR(o["equilibrated"]["pressure_Pa"].get<double>(), tr.col(2).tail(k).mean() * 101325.0,
              1e-9 * 101325.0);
  for (const char* f : {"build/system.data", "build/system.json", "equilibrate/stage_4_npt.h5",
                        "equilibrate/final.restart", "cases/case_6/checkpoint.h5", "card.h5"})
    EXPECT_TRUE(fs::exists(fs::path(out) / f)) << f;
  const auto cases = pnc::damage::read_stress_strain_h5((fs::path(out) / "cases.h5").string());
  ASSERT_EQ(cases.cases.size(), 2u);
  EXPECT_EQ(cases.cases[0].stress_stderr.rows(), 3);
  EXPECT_GT(cases.cases[0].stress_stderr(0, 1), 0.0);
  fs::remove_all(d);
}

// The same crystal in a user's tilted cell (xy = a, a lattice vector, so the crystal is
// unchanged) with atoms on the cell's faces, at 0 K, sheared both ways (cases 6 and 9, D424;
// the start state off the faces, D425): C11, C12, C44 match the lattice sums within the 1 % of
// the test above (the cell's shape does not enter the constants of the crystal in the x frame).
TEST(RveUserSystem, LjCrystalInATiltedCellShearedBothWaysMatchesLatticeSums) {
  const auto d = scratch("test_user_sys_lj_tilted");
  const double L = shipped_box_length(), a = L / 4;
  std::istringstream in(slurp(kExamples / "lj_fcc" / "fcc.data"));
  std::ostringstream out;
  std::string line;
  bool atoms = false;
  while (std::getline(in, line)) {
    if (line.find("zlo zhi") != std::string::npos) {
      out << line << "\n" << fmt::format("{:.17g} 0 0 xy xz yz\n", a);
      continue;
    }
    if (line.rfind("Atoms", 0) == 0) atoms = true;
    std::istringstream f(line);
    int id = 0, type = 0;
    double x = 0, y = 0, z = 0;
    if (atoms && (f >> id >> type >> x >> y >> z)) { // wrap into the tilted cell: x - y a / L
      double lam = (x - a * y / L) / L;
      lam -= std::floor(lam);
      out << fmt::format("{} {} {:.17g} {:.17g} {:.17g}\n", id, type, lam * L + a * y / L, y, z);
      continue;
    }
    out << line << "\n";
  }
  std::ofstream(d / "fcc.data") << out.str();
  std::string toml = slurp(kExamples / "lj_fcc" / "recipe.toml");
  toml.replace(toml.find("cases = [2, 6]"), 14, "cases = [2, 6, 9]");
  std::ofstream(d / "recipe.toml") << toml;
  const auto r = pnc::test::run_command(
      std::string(PNC_EXE) + " characterize " + (d / "recipe.toml").string() + " --out " +
      (d / "out").string() + " --json --no-plots 2>" + (d / "err.txt").string());
  ASSERT_TRUE(r.code == 0 || r.code == 3 || r.code == 4) << r.code << slurp(d / "err.txt");
  const auto j = json::parse(r.out);
  const LatticeSums sums = lattice_sums(L);
  for (const auto& [k, ref] : {std::pair{"C11", sums.C11}, {"C12", sums.C12}, {"C44", sums.C44}})
    EXPECT_NEAR(j["constants"][k]["value"].get<double>(), ref, 0.01 * ref) << k;
  fs::remove_all(d);
}
