// `pnc material drive` (docs/drive.md) against independent references: the compliance of
// C0 for uniaxial stress, direct plugin calls for strain control, the secant C0 + C1(D) of
// theory.md (1.2) for unloading, the energy balance to the trapezoidal rule's order, and the
// rotation of strain and stress for a turned platelet frame.
#include "material_cli.hpp"

#include "common/temp_dir.hpp"

#include "pnc/core/hdf5_io.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/fe_material/material.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

using pnc::test::CliResult;
using pnc::test::slurp;

using pnc::test::Mat6;
using pnc::test::MaterialCli;
using pnc::test::Vec6;
namespace fs = std::filesystem;

namespace {

std::map<std::string, double> constants_of(const std::string& card) {
  const auto m = pnc::fe_material::Material::from_card(card);
  std::map<std::string, double> k;
  const auto names = m.constant_names();
  const auto values = m.constants();
  for (std::size_t i = 0; i < names.size(); ++i)
    k[names[i]] = values[i];
  return k;
}

const char* kE[6] = {"e11", "e22", "e33", "g23", "g13", "g12"};
const char* kS[6] = {"s11_Pa", "s22_Pa", "s33_Pa", "s23_Pa", "s13_Pa", "s12_Pa"};

Vec6 row(const std::map<std::string, std::vector<double>>& c, const char* const* names,
         std::size_t k) {
  Vec6 v;
  for (int i = 0; i < 6; ++i)
    v[i] = c.at(names[i])[k];
  return v;
}

// Engineering Voigt strain <-> tensor (gamma = 2 eps), stress Voigt <-> tensor.
Eigen::Matrix3d strain_tensor(const Vec6& e) {
  Eigen::Matrix3d t;
  t << e[0], e[5] / 2, e[4] / 2, e[5] / 2, e[1], e[3] / 2, e[4] / 2, e[3] / 2, e[2];
  return t;
}
Vec6 strain_voigt(const Eigen::Matrix3d& t) {
  Vec6 v;
  v << t(0, 0), t(1, 1), t(2, 2), 2 * t(1, 2), 2 * t(0, 2), 2 * t(0, 1);
  return v;
}
Eigen::Matrix3d stress_tensor(const Vec6& s) {
  Eigen::Matrix3d t;
  t << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
  return t;
}
Vec6 stress_voigt(const Eigen::Matrix3d& t) {
  Vec6 v;
  v << t(0, 0), t(1, 1), t(2, 2), t(1, 2), t(0, 2), t(0, 1);
  return v;
}

} // namespace

TEST_F(MaterialCli, UniaxialStressInTheElasticRangeFollowsTheComplianceOfC0) {
  const std::string card = tables_card();
  write("uni.toml", "[[segment]]\nsteps = 10\ne11 = 1e-3\ns22 = 0.0\ns33 = 0.0\n");
  const CliResult r =
      run("material drive '" + card + "' --path uni.toml --out uni.csv --no-plot --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto c = columns(p("uni.csv"));
  const auto k = constants_of(card);
  const Mat6 C0 = pnc::test::stiffness(k, {0, 0, 0});
  const Mat6 S = C0.inverse();
  const double E1 = 1 / S(0, 0), nu12 = -S(1, 0) / S(0, 0), nu13 = -S(2, 0) / S(0, 0);
  const double tol_pa = 1e-12 * C0.cwiseAbs().maxCoeff(); // the documented Newton tolerance
  ASSERT_EQ(c.at("step").size(), 11u);
  for (std::size_t i = 1; i < 11; ++i) {
    const double e = c.at("e11")[i];
    EXPECT_NEAR(e, 1e-4 * static_cast<double>(i), 1e-18);
    EXPECT_NEAR(c.at("s11_Pa")[i], E1 * e, 1e-9 * E1 * e);
    EXPECT_NEAR(c.at("e22")[i], -nu12 * e, 1e-9 * e);
    EXPECT_NEAR(c.at("e33")[i], -nu13 * e, 1e-9 * e);
    EXPECT_LE(std::abs(c.at("s22_Pa")[i]), tol_pa);
    EXPECT_LE(std::abs(c.at("s33_Pa")[i]), tol_pa);
    EXPECT_EQ(c.at("D1")[i], 0.0); // elastic: below the damage onset
  }
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["newton"]["mixed_control"].get<bool>());
  EXPECT_TRUE(j["converged"].get<bool>());
  EXPECT_LE(j["newton"]["max_iterations"].get<int>(), 1); // linear: the predictor is exact
  EXPECT_NEAR(j["newton"]["residual_tolerance_Pa"].get<double>(), tol_pa, 1e-6 * tol_pa);
}

TEST_F(MaterialCli, MixedControlPastTheDamageOnsetConvergesAndIsReported) {
  const std::string card = tables_card();
  // uniaxial stress into damage (onset at eps11 ~ 0.07), then back to zero stress
  write("uni.json", R"({"segment": [{"steps": 40, "e11": 0.1, "s22": 0, "s33": 0},
                                     {"steps": 10, "s11": 0}]})");
  const CliResult r =
      run("material drive '" + card + "' --path uni.json --out uni.csv --no-plot --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto c = columns(p("uni.csv"));
  const double tol_pa = nlohmann::json::parse(r.out)["newton"]["residual_tolerance_Pa"];
  EXPECT_GT(c.at("D1")[40], 0.0); // damaged
  int most = 0;
  for (std::size_t i = 1; i < c.at("step").size(); ++i) {
    EXPECT_LE(std::abs(c.at("s22_Pa")[i]), tol_pa) << i;
    EXPECT_LE(std::abs(c.at("s33_Pa")[i]), tol_pa) << i;
    EXPECT_LE(c.at("newton_residual_Pa")[i], tol_pa) << i;
    most = std::max(most, static_cast<int>(c.at("newton_iterations")[i]));
  }
  EXPECT_GE(most, 1); // the damaging steps need Newton corrections ...
  EXPECT_LE(most, 8); // ... and the consistent tangent makes them few
  EXPECT_LE(std::abs(c.at("s11_Pa").back()), tol_pa); // unloaded to zero stress
  EXPECT_NE(r.err.find("Newton (stress control)"), std::string::npos) << r.err;

  // a stress far beyond the strength has no solution: exit 3 naming the segment and step
  write("beyond.toml", "[[segment]]\nsteps = 5\nlabel = \"too far\"\ns11 = 5e10\n");
  const CliResult b = run("material drive '" + card + "' --path beyond.toml --out b.csv --no-plot");
  EXPECT_EQ(b.code, 3) << b.err;
  EXPECT_NE(b.err.find("beyond.toml: segment[1] 'too far' step"), std::string::npos) << b.err;
  EXPECT_TRUE(fs::exists(p("b.csv"))); // the steps before it are kept
  // the report says first, in words, that the run did not finish, why, where, and what is valid
  const std::string md = slurp(p("b_report.md"));
  const auto banner = md.find("Did not finish: ");
  ASSERT_NE(banner, std::string::npos) << md;
  EXPECT_EQ(md.find("beyond.toml: segment[1] 'too far' step"), md.find(":", banner) + 2) << md;
  EXPECT_LT(banner, md.find("What was run")) << md;
  EXPECT_NE(md.find("of 5 steps (the next step did not converge)"), std::string::npos) << md;
  EXPECT_NE(md.find("b.csv`: steps 0 to"), std::string::npos) << md;
  EXPECT_NE(md.find("nothing to resume"), std::string::npos) << md;
  const std::string html = slurp(p("b_report.html"));
  EXPECT_NE(html.find("Did not finish: "), std::string::npos);
}

TEST_F(MaterialCli, StrainControlEqualsDirectPluginCalls) {
  const std::string card = tables_card();
  write("path.toml", "[[segment]]\nsteps = 30\ne11 = 0.15\ng12 = 0.05\n"
                     "[[segment]]\nsteps = 10\ne11 = 0.05\ne22 = -0.01\n"
                     "[[segment]]\nsteps = 20\ne11 = 0.2\ng23 = 0.03\n");
  const auto c = drive(card, "path.toml");
  const pnc::fe_material::Plugin plugin(PNC_PLUGIN);
  const auto m = plugin.from_card(card);
  std::vector<double> s0 = m.initial_state(), s1;
  pnc::fe_material::Voigt6 e0{}, de{}, sig{};
  pnc::fe_material::Tangent36 K{};
  const auto names = m.state_names();
  ASSERT_EQ(c.at("step").size(), 61u);
  for (std::size_t k = 1; k < 61; ++k) {
    const Vec6 e = row(c, kE, k);
    for (int i = 0; i < 6; ++i)
      de[static_cast<std::size_t>(i)] = e[i] - e0[static_cast<std::size_t>(i)];
    m.integrate(s0, s1, e0, de, sig, &K);
    for (int i = 0; i < 6; ++i) {
      const double ref = sig[static_cast<std::size_t>(i)];
      EXPECT_NEAR(c.at(kS[i])[k], ref, 1e-14 * std::abs(ref) + 1e-9) << k << " " << kS[i];
      for (int j = 0; j < 6; ++j) {
        // ds11_de11_Pa: the tangent's name, its unit last (D336)
        const std::string col = "d" + std::string(kS[i]).substr(0, 3) + "_d" + kE[j] + "_Pa";
        EXPECT_NEAR(c.at(col)[k], K[static_cast<std::size_t>(6 * i + j)],
                    1e-14 * std::abs(K[static_cast<std::size_t>(6 * i + j)]) + 1e-9)
            << k << " " << col;
      }
    }
    for (std::size_t i = 0; i < names.size(); ++i)
      EXPECT_EQ(c.at(names[i])[k], s1[i]) << k << " " << names[i];
    s0 = s1;
    for (int i = 0; i < 6; ++i)
      e0[static_cast<std::size_t>(i)] = e[i];
  }
  EXPECT_GT(c.at("D1")[30], 0.0);
}

TEST_F(MaterialCli, LoadUnloadReloadIsSecantAndConservesEnergy) {
  const std::string card = tables_card();
  const auto k = constants_of(card);
  std::array<double, 2> balance_error{};
  double work_end = 0;
  for (int refine = 0; refine < 2; ++refine) {
    const int n = 20 << refine; // steps of the first ramp: 20, then 40
    const std::string file = "lur" + std::to_string(n) + ".toml";
    write(file, "[[segment]]\nsteps = " + std::to_string(n) + "\ne11 = 0.14\ng12 = 0.02\n" +
                    "[[segment]]\nsteps = " + std::to_string(n) + "\ne11 = 0.0\ng12 = 0.0\n" +
                    "[[segment]]\nsteps = " + std::to_string(2 * n) + "\ne11 = 0.2\ng12 = 0.03\n");
    const auto c = drive(card, file, "lur" + std::to_string(n) + ".csv");
    const std::size_t rows = c.at("step").size();
    ASSERT_EQ(rows, static_cast<std::size_t>(4 * n + 1));
    const std::size_t top = static_cast<std::size_t>(n); // end of the first ramp
    ASSERT_GT(c.at("D1")[top], 0.0);
    const std::array<double, 3> D = {c.at("D1")[top], c.at("D2")[top], c.at("D3")[top]};
    const Mat6 Csec = pnc::test::stiffness(k, D);
    for (std::size_t i = top; i <= 2 * top; ++i) { // unloading: on the secant through 0
      EXPECT_EQ(c.at("D1")[i], D[0]) << i;
      const Vec6 s = row(c, kS, i), e = row(c, kE, i);
      EXPECT_LE((s - Csec * e).cwiseAbs().maxCoeff(), 1e-10 * (Csec * row(c, kE, top)).norm()) << i;
    }
    // reloading stays on the same secant until the previous maximum strain is passed
    for (std::size_t i = 2 * top; i < rows && c.at("e11")[i] <= 0.14 - 1e-12; ++i)
      EXPECT_EQ(c.at("D1")[i], D[0]) << i;
    EXPECT_GT(c.at("D1").back(), D[0]);
    // dissipation never negative, never decreasing (-1/2 eps.dC.eps >= 0 for growing damage)
    for (std::size_t i = 1; i < rows; ++i) {
      EXPECT_GE(c.at("dissipated_J_per_m3")[i], 0.0) << i;
      EXPECT_GE(c.at("dissipated_J_per_m3")[i], c.at("dissipated_J_per_m3")[i - 1] - 1e-9) << i;
    }
    // external work = stored + dissipated, to the trapezoidal rule's accuracy
    double worst = 0;
    for (std::size_t i = 0; i < rows; ++i)
      worst = std::max(worst, std::abs(c.at("work_J_per_m3")[i] - c.at("stored_J_per_m3")[i] -
                                       c.at("dissipated_J_per_m3")[i]));
    balance_error[static_cast<std::size_t>(refine)] = worst;
    work_end = c.at("work_J_per_m3").back();
    // stored energy is 1/2 sigma.eps independently of the driver
    const std::size_t last = rows - 1;
    EXPECT_NEAR(c.at("stored_J_per_m3")[last], 0.5 * row(c, kS, last).dot(row(c, kE, last)),
                1e-12 * work_end);
  }
  EXPECT_GT(work_end, 0.0);
  EXPECT_LT(balance_error[0], 1e-2 * work_end);
  // second order: halving the step divides the error by about 4 (at least 3 here)
  EXPECT_LE(balance_error[1], balance_error[0] / 3 + 1e-12 * work_end)
      << balance_error[0] << " " << balance_error[1];
}

TEST_F(MaterialCli, DrivingATurnedFrameEqualsRotatingStrainAndStress) {
  const std::string card = tables_card();
  // the platelet turned by 30 degrees about x3 (active): Q = P^T, x_local = Q x_driver
  write("turned.toml", "[rotation]\naxis = [0, 0, 1]\nangle_deg = 30\n"
                       "[[segment]]\nsteps = 25\ne11 = 0.12\ne22 = 0.03\ng12 = 0.05\n"
                       "[[segment]]\nsteps = 10\ne11 = 0.02\n");
  const auto a = drive(card, "turned.toml", "turned.csv");
  const double t = std::acos(-1.0) / 6;
  Eigen::Matrix3d P;
  P << std::cos(t), -std::sin(t), 0, std::sin(t), std::cos(t), 0, 0, 0, 1;
  const Eigen::Matrix3d Q = P.transpose();
  // the same history in the card's own frame: eps_local = Q eps Q^T, one CSV row per step
  std::string csv = "steps,e11,e22,e33,g23,g13,g12\n";
  const std::size_t rows = a.at("step").size();
  char line[512];
  for (std::size_t k = 1; k < rows; ++k) {
    const Vec6 el = strain_voigt(Q * strain_tensor(row(a, kE, k)) * Q.transpose());
    std::snprintf(line, sizeof line, "1,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", el[0], el[1], el[2],
                  el[3], el[4], el[5]);
    csv += line;
  }
  write("local.csv", csv);
  const auto b = drive(card, "local.csv", "local_out.csv");
  ASSERT_EQ(b.at("step").size(), rows);
  double scale = 0;
  for (std::size_t k = 0; k < rows; ++k)
    scale = std::max(scale, row(a, kS, k).cwiseAbs().maxCoeff());
  for (std::size_t k = 1; k < rows; ++k) {
    const Vec6 back = stress_voigt(Q.transpose() * stress_tensor(row(b, kS, k)) * Q);
    EXPECT_LE((row(a, kS, k) - back).cwiseAbs().maxCoeff(), 1e-9 * scale) << k;
    EXPECT_NEAR(a.at("D1")[k], b.at("D1")[k], 1e-12) << k;
    EXPECT_NEAR(a.at("D2")[k], b.at("D2")[k], 1e-12) << k;
  }
  EXPECT_GT(a.at("D1")[25], 0.0);
  // and the energies are frame-independent
  EXPECT_NEAR(a.at("work_J_per_m3").back(), b.at("work_J_per_m3").back(),
              1e-9 * a.at("work_J_per_m3").back());
}

TEST_F(MaterialCli, ReferenceFileWithTolerances) {
  const std::string card = tables_card();
  write("p.toml", "[[segment]]\nsteps = 12\ne11 = 0.1\ns22 = 0\ns33 = 0\n");
  ASSERT_EQ(run("material drive '" + card + "' --path p.toml --out ref.csv --no-plot").code, 0);
  const CliResult same =
      run("material drive '" + card + "' --path p.toml --out a.csv --no-plot --reference ref.csv");
  EXPECT_EQ(same.code, 0) << same.err;
  EXPECT_NE(same.err.find("within tolerances"), std::string::npos) << same.err;
  // a reference of two columns, s11 at step 5 moved by 1 kPa (tolerance 1 Pa + 1e-6 |ref|)
  const auto c = columns(p("ref.csv"));
  std::string ref = "step,s11_Pa\n";
  char line[128];
  for (std::size_t k = 0; k < c.at("step").size(); ++k) {
    std::snprintf(line, sizeof line, "%g,%.17g\n", c.at("step")[k],
                  c.at("s11_Pa")[k] + (k == 5 ? 1e3 : 0.0));
    ref += line;
  }
  write("moved.csv", ref);
  const CliResult bad = run("material drive '" + card +
                            "' --path p.toml --out b.csv --no-plot --reference moved.csv");
  EXPECT_EQ(bad.code, 5) << bad.err;
  EXPECT_NE(bad.err.find("reference moved.csv: step 5, column s11_Pa: value "), std::string::npos)
      << bad.err;
  EXPECT_NE(bad.err.find("> tolerance"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("1 values outside the tolerances"), std::string::npos) << bad.err;
  // a reference with the names of before D336 (no unit suffix): refused, naming the new one
  write("old.csv", "step,s11\n0,0\n");
  const CliResult old =
      run("material drive '" + card + "' --path p.toml --out o.csv --no-plot --reference old.csv");
  EXPECT_NE(old.code, 0);
  EXPECT_NE(old.err.find("old.csv"), std::string::npos) << old.err;
  EXPECT_NE(old.err.find("the column is now named s11_Pa"), std::string::npos) << old.err;
  // a wider stress tolerance accepts it
  EXPECT_EQ(run("material drive '" + card +
                "' --path p.toml --out b.csv --no-plot "
                "--reference moved.csv --tol-stress 2e3")
                .code,
            0);
  // a reference that cannot be compared is an input error naming the column
  write("unknown.csv", "step,s99\n0,0\n");
  const CliResult u = run("material drive '" + card +
                          "' --path p.toml --out u.csv --no-plot --reference unknown.csv");
  EXPECT_EQ(u.code, 1);
  EXPECT_NE(u.err.find("unknown.csv: field 's99'"), std::string::npos) << u.err;
}

TEST_F(MaterialCli, BadPathFilesAreNamedAndLeaveNoOutput) {
  const std::string card = tables_card();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[[segment]]\nsteps = 0\ne11 = 0.1\n",
       "bad.toml: field 'segment[1].steps': value '0': must be an integer in [1, 100000]"},
      {"[[segment]]\nsteps = 3\ne11 = \"x\"\n", "bad.toml: field 'segment[1].e11': value '\"x\"'"},
      {"[[segment]]\nsteps = 3\ne12 = 0.1\n",
       "field 'segment[1].e12': value '0.1': shear strains are engineering shear: name them g12"},
      {"[[segment]]\nsteps = 3\ne11 = 0.1\ns11 = 0\n",
       "a component is driven in strain or in stress, not both"},
      {"[[segment]]\nsteps = 3\ne11 = 5.0\n",
       "field 'segment[1].e11': value '5.0': must be a finite number in [-1, 1]"},
      {"stepz = 3\n[[segment]]\nsteps = 1\n", "field 'stepz': value '3': unknown key"},
      {"[rotation]\naxis = [0, 0, 0]\nangle_deg = 3\n[[segment]]\nsteps = 1\n",
       "field 'rotation.axis': value '[0,0,0]': must not be the zero vector"},
      {"[[segment]]\nsteps = 3\ne11 = [1\n", "bad.toml: not valid TOML"},
  };
  for (const auto& [text, want] : cases) {
    write("bad.toml", text);
    const CliResult r = run("material drive '" + card + "' --path bad.toml --out o.csv");
    EXPECT_EQ(r.code, 1) << text;
    EXPECT_NE(r.err.find(want), std::string::npos) << text << "\n" << r.err;
    EXPECT_FALSE(fs::exists(p("o.csv"))) << text;
    EXPECT_FALSE(fs::exists(p("o.png"))) << text;
  }
  write("bad.csv", "steps,e11\n2.5,0.1\n");
  const CliResult c = run("material drive '" + card + "' --path bad.csv --out o.csv");
  EXPECT_EQ(c.code, 1);
  EXPECT_NE(c.err.find("bad.csv: field 'segment[1].steps': value '2.5'"), std::string::npos)
      << c.err;
  write("bad.yaml", "x");
  EXPECT_NE(run("material drive '" + card + "' --path bad.yaml --out o.csv")
                .err.find("a path file ends in .toml, .json or .csv"),
            std::string::npos);
}

TEST_F(MaterialCli, Hdf5OutputStatesItsUnitsAndThePngIsDrawn) {
  const std::string card = tables_card();
  write("p.toml", "[[segment]]\nsteps = 8\ne11 = 0.1\n");
  const CliResult r = run("material drive '" + card + "' --path p.toml --out r.h5");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto c = drive(card, "p.toml", "r.csv");
  std::ifstream png(p("r.png"), std::ios::binary);
  char sig[8] = {};
  png.read(sig, 8);
  EXPECT_EQ(std::string(sig + 1, 3), "PNG");
  EXPECT_FALSE(fs::exists(p("r.png.csv"))); // the plot data were private
  // the plotting phase (seconds: matplotlib starts) is announced before it runs, then its
  // end, and both come before the summary lines: no silent seconds
  const auto plotting = r.err.find("pnc material drive: plotting r.png ...");
  const auto plotted = r.err.find("pnc material drive: plotted r.png in ");
  ASSERT_NE(plotting, std::string::npos) << r.err;
  ASSERT_NE(plotted, std::string::npos) << r.err;
  EXPECT_LT(plotting, plotted) << r.err;
  EXPECT_LT(plotted, r.err.find("pnc material drive: " + card)) << r.err;
  // units in the column names (D336): the header line, every unit-bearing column suffixed
  std::ifstream f(p("r.csv"));
  std::string head;
  while (std::getline(f, head) && head.rfind('#', 0) == 0) {
  }
  EXPECT_EQ(head.rfind("step,segment,e11,e22,e33,g23,g13,g12,s11_Pa,s22_Pa,s33_Pa,s23_Pa,s13_Pa,"
                       "s12_Pa,",
                       0),
            0u)
      << head;
  EXPECT_NE(head.find(",ds11_de11_Pa,"), std::string::npos) << head;
  EXPECT_NE(head.find(",ds12_dg12_Pa,work_J_per_m3,stored_J_per_m3,dissipated_J_per_m3,"
                      "newton_iterations,newton_residual_Pa"),
            std::string::npos)
      << head;
  // the HDF5 file: the same numbers, units on every dataset
  const pnc::h5::File h(p("r.h5"), pnc::h5::File::Mode::read);
  const auto stress = h.read_matrix("/stress");
  const auto energy = h.read_matrix("/energy");
  ASSERT_EQ(stress.rows(), 9);
  for (Eigen::Index k = 0; k < 9; ++k) {
    EXPECT_EQ(stress(k, 0), c.at("s11_Pa")[static_cast<std::size_t>(k)]);
    EXPECT_EQ(energy(k, 2), c.at("dissipated_J_per_m3")[static_cast<std::size_t>(k)]);
  }
  EXPECT_EQ(h.attr_string("/stress", "units").value_or(""), "Pa");
  EXPECT_EQ(h.attr_string("/strain", "units").value_or(""), "1");
  EXPECT_EQ(h.attr_string("/tangent", "units").value_or(""), "Pa");
  EXPECT_EQ(h.attr_string("/energy", "units").value_or(""), "J/m^3");
  EXPECT_NE(h.attr_string("/", "units").value_or("").find("stress Pa"), std::string::npos);
}

TEST_F(MaterialCli, PluginLookupIsNamedWhenItFails) {
  const std::string card = tables_card();
  write("p.toml", "[[segment]]\nsteps = 1\ne11 = 0.01\n");
  const CliResult a = run("material drive '" + card +
                          "' --path p.toml --out o.csv --no-plot --plugin /nonexistent/lib.so");
  EXPECT_EQ(a.code, 1);
  EXPECT_NE(a.err.find("field '--plugin': value '/nonexistent/lib.so'"), std::string::npos)
      << a.err;
  const CliResult b = run("material drive '" + card + "' --path p.toml --out o.csv --no-plot",
                          "PNC_MATERIAL_PLUGIN=libm.so.6");
  EXPECT_EQ(b.code, 1);
  const CliResult c = run("material drive '" + card + "' --path p.toml --out o.csv --no-plot",
                          "PNC_MATERIAL_PLUGIN=/nonexistent.so");
  EXPECT_EQ(c.code, 1);
  EXPECT_NE(c.err.find("PNC_MATERIAL_PLUGIN"), std::string::npos) << c.err;
  // without any override the build tree's plugin is found next to the executable
  const CliResult d =
      run("material drive '" + card + "' --path p.toml --out o.csv --no-plot --json",
          "-u PNC_MATERIAL_PLUGIN");
  ASSERT_EQ(d.code, 0) << d.err;
  EXPECT_NE(nlohmann::json::parse(d.out)["plugin"].get<std::string>().find("libpnc_material.so"),
            std::string::npos);
}

TEST_F(MaterialCli, HelpOfTheNewSubcommands) {
  for (const char* sub : {"material", "material drive", "card export"}) {
    const CliResult r = run(std::string(sub) + " --help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
  EXPECT_NE(run("material drive --help").out.find("--reference"), std::string::npos);
  EXPECT_NE(run("card export --help").out.find("--format"), std::string::npos);
  EXPECT_NE(run("material").code, 0); // a subcommand is required
}

TEST_F(MaterialCli, ThePathRotationComposesWithTheCardsOwn) {
  // card A turned by R_A; the path turns it further by Q (matrix form); card B has R_A Q
  pnc::damage::NdmParameters a = pnc::damage::dissertation_parameters(pnc::damage::Model::pnc);
  a.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  const Eigen::Matrix3d Q =
      Eigen::AngleAxisd(-0.7, Eigen::Vector3d(0, 1, 2).normalized()).toRotationMatrix();
  pnc::damage::NdmParameters b = a;
  b.R = a.R * Q;
  pnc::damage::write_card(p("a.h5"), pnc::damage::card_from_parameters(a, "test"), "test");
  pnc::damage::write_card(p("b.h5"), pnc::damage::card_from_parameters(b, "test"), "test");
  char m[512];
  std::snprintf(m, sizeof m,
                "[rotation]\nmatrix = [[%.17g, %.17g, %.17g], [%.17g, %.17g, %.17g], "
                "[%.17g, %.17g, %.17g]]\n",
                Q(0, 0), Q(0, 1), Q(0, 2), Q(1, 0), Q(1, 1), Q(1, 2), Q(2, 0), Q(2, 1), Q(2, 2));
  const std::string seg = "[[segment]]\nsteps = 20\ne11 = 0.15\ng23 = 0.04\ns22 = 0\n";
  write("qa.toml", std::string(m) + seg);
  write("qb.toml", seg);
  const auto ra = drive(p("a.h5"), "qa.toml", "qa.csv");
  const auto rb = drive(p("b.h5"), "qb.toml", "qb.csv");
  ASSERT_EQ(ra.at("step").size(), 21u);
  double scale = 0;
  for (std::size_t k = 0; k < 21; ++k)
    scale = std::max(scale, row(rb, kS, k).cwiseAbs().maxCoeff());
  for (std::size_t k = 1; k < 21; ++k) {
    EXPECT_LE((row(ra, kS, k) - row(rb, kS, k)).cwiseAbs().maxCoeff(), 1e-9 * scale) << k;
    EXPECT_LE((row(ra, kE, k) - row(rb, kE, k)).cwiseAbs().maxCoeff(), 1e-12) << k;
  }
  EXPECT_GT(rb.at("D1").back() + rb.at("D2").back() + rb.at("D3").back(), 0.0);
}
