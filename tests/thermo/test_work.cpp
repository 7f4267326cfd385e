// `pnc thermo work` (thermo/work.hpp) on synthetic run directories (recipe.json,
// equilibrate/final.h5, cases.h5 written here): closed forms of the trapezoid, the error
// propagation by Monte Carlo, the two-temperature split, and the input checks. No LAMMPS.
#include "common/page_check.hpp"
#include "common/run_command.hpp"
#include "common/temp_dir.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/thermo/work.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

namespace fs = std::filesystem;
using namespace pnc;
using damage::PathMatrix;

namespace {

const double kV0_A3 = 8000.0; // reference box volume of the synthetic runs

fs::path g_scratch_root; // this process's folder of run directories, made on first use

/// A run directory <root>/<name>, emptied, with its equilibrate/ folder. The root is a fresh_dir
/// (new and private per process) on tmpfs when there is one: the writers fsync, and the Monte
/// Carlo test writes 400 files.
fs::path scratch(const std::string& name) {
  if (g_scratch_root.empty()) {
    const fs::path base =
        fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    g_scratch_root = pnc::test::fresh_dir_in(base, "test_work");
  }
  const fs::path d = g_scratch_root / name;
  fs::remove_all(d);
  fs::create_directories(d / "equilibrate");
  return d;
}

/// Removes the root at the end of a run whose tests all passed (kept for a look otherwise): a new
/// root per run would otherwise pile up in /dev/shm, which is memory.
class ScratchCleanup : public ::testing::Environment {
public:
  void TearDown() override {
    if (g_scratch_root.empty() || !::testing::UnitTest::GetInstance()->Passed()) return;
    std::error_code ec;
    fs::remove_all(g_scratch_root, ec);
  }
};
const ::testing::Environment* const kScratchCleanup =
    ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

/// case 1 path: eps11 = k h, k = 1..n (the zero row is removed, as for a subtracted reference)
PathMatrix uniaxial(int n, double h) {
  PathMatrix e = PathMatrix::Zero(n, 6);
  for (int k = 0; k < n; ++k)
    e(k, 0) = (k + 1) * h;
  return e;
}

/// Writes a run directory: stress = f(strain row) in column 0, error `se` (<0: none).
std::string make_run(const fs::path& d, double t, const std::vector<int>& ids, const PathMatrix& e,
                     const std::function<double(double)>& f, double se,
                     std::mt19937_64* rng = nullptr, double noise_sd = -1) {
  if (noise_sd < 0) noise_sd = se;
  {
    std::ofstream r(d / "recipe.json");
    r << "{\"deform\": {\"temperature\": " << t << "}}\n";
  }
  {
    h5::File h((d / "equilibrate" / "final.h5").string(), h5::File::Mode::truncate);
    h5::RowMatrix tr(2, 6);
    tr << t, 0, 0, 0, 0.8, kV0_A3, t, 0, 0, 0, 0.8, kV0_A3;
    h.write_matrix("/trace", tr);
  }
  damage::StressStrainData data;
  data.stress_definition = "synthetic; relative to the zero-strain hold (sigma - sigma_0)";
  std::normal_distribution<double> g(0, 1);
  for (int id : ids) {
    damage::CaseCurve c;
    c.id = id;
    c.strain = e;
    c.stress = PathMatrix::Zero(e.rows(), 6);
    for (Eigen::Index k = 0; k < e.rows(); ++k)
      c.stress(k, 0) = f(e(k, 0)) + (rng ? noise_sd * g(*rng) : 0.0);
    if (se >= 0) c.stress_stderr = PathMatrix::Constant(e.rows(), 6, se);
    data.cases.push_back(c);
  }
  damage::write_stress_strain_h5((d / "cases.h5").string(), data);
  return d.string();
}

} // namespace

TEST(ThermoWork, LinearElasticIsExactAndVolumeIsTheFinalBox) {
  // sigma = C eps: the trapezoid of a linear integrand is exact, Delta a = C eps^2 / 2
  const double C = 3e9, h = 1e-4;
  const auto d = scratch("linear");
  const thermo::WorkRun run = thermo::read_work_run(make_run(
      d, 300, {1, 2}, uniaxial(50, h), [&](double x) { return C * x; }, 1e5));
  EXPECT_DOUBLE_EQ(run.temperature, 300.0);
  EXPECT_NEAR(run.volume, kV0_A3 * 1e-30, 1e-12 * kV0_A3 * 1e-30);
  const auto r = thermo::stress_work(run);
  ASSERT_EQ(r.cases.size(), 2u);
  for (std::size_t k = 0; k < 50; ++k) {
    const double eps = static_cast<double>(k + 1) * h, exact = C * eps * eps / 2;
    EXPECT_NEAR(r.cases[0].da.value[k], exact, 1e-12 * C * 0.25e-4);
  }
  EXPECT_FALSE(r.cases[0].softening);
}

TEST(ThermoWork, QuadraticHasTheTrapezoidErrorOfItsSecondDerivative) {
  // sigma = C eps + D eps^2: trapezoid error on [0, eps] with step h is
  // -(eps h^2 / 12) sigma'' = -eps h^2 D / 6 exactly (sigma'' constant); Delta a_trap =
  // C eps^2/2 + D eps^3/3 + eps h^2 D/6
  const double C = 2e9, D = -4e11, h = 2e-4;
  const auto d = scratch("quad");
  const auto r = thermo::stress_work(thermo::read_work_run(make_run(
      d, 300, {3}, uniaxial(40, h), [&](double x) { return C * x + D * x * x; }, -1)));
  const auto& w = r.cases[0].da;
  EXPECT_FALSE(w.has_se);
  EXPECT_TRUE(std::isnan(w.se_indep.back()));
  for (std::size_t k = 0; k < 40; ++k) {
    const double eps = static_cast<double>(k + 1) * h;
    const double exact = C * eps * eps / 2 + D * eps * eps * eps / 3;
    const double trap_err = eps * h * h * D / 6;
    EXPECT_NEAR(w.value[k] - exact, trap_err, 1e-10 * std::fabs(exact) + 1e-3);
    // the bound |error| <= eps h^2 max|sigma''| / 12 holds (with equality)
    EXPECT_LE(std::fabs(w.value[k] - exact),
              eps * h * h * 2 * std::fabs(D) / 12 * (1 + 1e-9) + 1e-3);
  }
}

TEST(ThermoWork, PropagatedErrorIsCalibratedByMonteCarlo) {
  // M independent noisy files of sigma = C eps + N(0, se): z = (da - exact)/se_indep is N(0,1).
  // mean z^2 ~ chi2_M / M: 99.9 % band 1 +- 3.29 sqrt(2/M); coverage of |z| < 1.96 is binomial
  // (M, 0.95): band 0.95 +- 3.29 sqrt(0.95 0.05 / M).
  const int M = 400, n = 20;
  const double C = 1e9, h = 5e-4, se = 2e6;
  std::mt19937_64 rng(12345);
  const auto d = scratch("mc");
  double z2 = 0;
  int inside = 0;
  double se_expected = 0;
  {
    // independent computation of the propagated error: weights h/2, h, ..., h, h/2 from the
    // prepended exact origin (weight of the origin irrelevant, its error is 0)
    double v = 0;
    for (int k = 1; k <= n; ++k)
      v += std::pow(k == n ? h / 2 : h, 2) * se * se;
    se_expected = std::sqrt(v);
  }
  for (int m = 0; m < M; ++m) {
    const auto r = thermo::stress_work(thermo::read_work_run(make_run(
        d, 300, {1}, uniaxial(n, h), [&](double x) { return C * x; }, se, &rng)));
    const auto& w = r.cases[0].da;
    const double eps = n * h, z = (w.value.back() - C * eps * eps / 2) / w.se_indep.back();
    ASSERT_NEAR(w.se_indep.back(), se_expected, 1e-12 * se_expected);
    ASSERT_GE(w.se_bound.back(), w.se_indep.back());
    z2 += z * z;
    if (std::fabs(z) < 1.96) ++inside;
  }
  z2 /= M;
  EXPECT_NEAR(z2, 1.0, 3.29 * std::sqrt(2.0 / M));
  EXPECT_NEAR(static_cast<double>(inside) / M, 0.95, 3.29 * std::sqrt(0.95 * 0.05 / M));
}

TEST(ThermoWork, ErrorBoundCoversACommonReferenceError) {
  // Like a reference-subtracted file: every point carries the same sigma_0 error d0 ~ N(0, s0)
  // plus its own N(0, s1); the file's se = (s0^2 + s1^2)^1/2. True variance of da(eps):
  // eps^2 s0^2 + sum w^2 s1^2; stderr_indep^2 = sum w^2 (s0^2 + s1^2) understates it by the
  // known ratio q, so mean z_indep^2 must sit in the chi2 band around q (> 1), and the bound
  // (sum |w| se >= true sd here) gives mean z_bound^2 <= 1 + 3.29 (2/M)^1/2.
  const int M = 300, n = 20;
  const double C = 1e9, h = 5e-4, s0 = 2e6, s1 = 1e6, se = std::hypot(s0, s1), eps = n * h;
  double sw2 = 0;
  for (int k = 1; k <= n; ++k)
    sw2 += std::pow(k == n ? h / 2 : h, 2);
  const double q = (eps * eps * s0 * s0 + sw2 * s1 * s1) / (sw2 * se * se);
  std::mt19937_64 rng(777);
  std::normal_distribution<double> g(0, 1);
  const auto d = scratch("mc_common");
  double zi = 0, zb = 0;
  for (int m = 0; m < M; ++m) {
    const double d0 = s0 * g(rng);
    const auto r = thermo::stress_work(thermo::read_work_run(make_run(
        d, 300, {1}, uniaxial(n, h), [&](double x) { return C * x + d0; }, se, &rng, s1)));
    const auto& w = r.cases[0].da;
    const double err = w.value.back() - C * eps * eps / 2;
    zi += std::pow(err / w.se_indep.back(), 2);
    zb += std::pow(err / w.se_bound.back(), 2);
  }
  zi /= M;
  zb /= M;
  ASSERT_GT(q, 2.0); // the design makes the understatement visible
  EXPECT_NEAR(zi, q, 3.29 * std::sqrt(2.0 / M) * q);
  EXPECT_LE(zb, 1.0 + 3.29 * std::sqrt(2.0 / M));
}

TEST(ThermoWork, TwoTemperaturesSplitAKnownFreeEnergy) {
  // A(eps, T)/V0 = (C0 + C1 T) eps^2 / 2: sigma = (C0 + C1 T) eps, T dsigma/dT = T C1 eps
  // (linear in T: the finite difference is exact), sigma_U = C0 eps; integrated with the
  // trapezoid (exact for linear integrands): entropic T_m C1 eps^2/2, energetic C0 eps^2/2.
  const double C0 = 4e9, C1 = -5e6, T1 = 250, T2 = 350, Tm = 300, h = 1e-4, se = 1e5;
  const auto d1 = scratch("t1"), d2 = scratch("t2");
  const auto e = uniaxial(30, h);
  const auto w1 = thermo::read_work_run(make_run(
      d1, T1, {1, 4}, e, [&](double x) { return (C0 + C1 * T1) * x; }, se));
  const auto w2 = thermo::read_work_run(make_run(
      d2, T2, {1, 4}, e, [&](double x) { return (C0 + C1 * T2) * x; }, se));
  const auto r = thermo::stress_work(w1, &w2);
  EXPECT_DOUBLE_EQ(r.temperature, Tm);
  ASSERT_EQ(r.cases.size(), 2u);
  const auto& c = r.cases[0];
  for (Eigen::Index k = 0; k < 30; ++k) {
    const double eps = static_cast<double>(k + 1) * h;
    EXPECT_NEAR(c.sigma_s(k, 0), Tm * C1 * eps, 1e-9 * std::fabs(C0 * eps));
    EXPECT_NEAR(c.sigma_u(k, 0), C0 * eps, 1e-9 * std::fabs(C0 * eps));
    // point errors: r = Tm/(T2-T1) = 3; sigma_S se = r sqrt(2) se, sigma_U se =
    // sqrt((1/2+r)^2 + (1/2-r)^2) se
    EXPECT_NEAR(c.sigma_s_se(k, 0), 3 * std::sqrt(2.0) * se, 1e-9 * se);
    EXPECT_NEAR(c.sigma_u_se(k, 0), std::sqrt(3.5 * 3.5 + 2.5 * 2.5) * se, 1e-9 * se);
    const auto i = static_cast<std::size_t>(k);
    const double scale = C0 * eps * eps;
    EXPECT_NEAR(c.da_s.value[i], Tm * C1 * eps * eps / 2, 1e-9 * scale);
    EXPECT_NEAR(c.da_u.value[i], C0 * eps * eps / 2, 1e-9 * scale);
    EXPECT_NEAR(c.da.value[i], (C0 + C1 * Tm) * eps * eps / 2, 1e-9 * scale);
    EXPECT_NEAR(c.da.value[i], c.da_s.value[i] + c.da_u.value[i], 1e-9 * scale);
  }
}

namespace {
void expect_input_error(const std::function<void()>& f, const std::vector<std::string>& words) {
  try {
    f();
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    for (const auto& w : words)
      EXPECT_NE(m.find(w), std::string::npos) << "message lacks '" << w << "': " << m;
  }
}
} // namespace

TEST(ThermoWork, MismatchedRunsAreClearErrors) {
  const auto lin = [](double x) { return 1e9 * x; };
  const auto a =
      thermo::read_work_run(make_run(scratch("ma"), 300, {1, 2}, uniaxial(10, 1e-4), lin, 1e5));
  // same temperature
  const auto same_t =
      thermo::read_work_run(make_run(scratch("mb"), 300, {1, 2}, uniaxial(10, 1e-4), lin, 1e5));
  expect_input_error([&] { thermo::stress_work(a, &same_t); },
                     {"recipe.json", "deform.temperature", "different temperatures"});
  // other cases
  const auto other =
      thermo::read_work_run(make_run(scratch("mc2"), 350, {1, 3}, uniaxial(10, 1e-4), lin, 1e5));
  expect_input_error([&] { thermo::stress_work(a, &other); },
                     {"cases.h5", "/case_2", "same cases"});
  // other strains
  const auto strains =
      thermo::read_work_run(make_run(scratch("md"), 350, {1, 2}, uniaxial(10, 2e-4), lin, 1e5));
  expect_input_error([&] { thermo::stress_work(a, &strains); },
                     {"cases.h5", "/case_1/strain", "must equal the strain"});
  const auto rows =
      thermo::read_work_run(make_run(scratch("me"), 350, {1, 2}, uniaxial(12, 1e-4), lin, 1e5));
  expect_input_error([&] { thermo::stress_work(a, &rows); },
                     {"cases.h5", "/case_1/strain", "same strain points"});
  // not a run directory
  expect_input_error([&] { thermo::read_work_run(scratch("empty").string()); },
                     {"--from", "recipe.json"});
}

namespace {
/// The declared default of the recipe key `name` (pnc recipe parameters --format json).
double declared_default(const std::string& name) {
  const auto r =
      pnc::test::run_command(std::string(PNC_EXE) + " recipe parameters --format json 2>/dev/null");
  EXPECT_EQ(r.code, 0) << r.out;
  std::function<const nlohmann::json*(const nlohmann::json&)> find =
      [&](const nlohmann::json& j) -> const nlohmann::json* {
    if (j.is_object() && j.value("name", "") == name && j.contains("default")) return &j;
    if (j.is_structured())
      for (const auto& x : j)
        if (const auto* hit = find(x)) return hit;
    return nullptr;
  };
  const nlohmann::json all = nlohmann::json::parse(r.out);
  const nlohmann::json* entry = find(all);
  EXPECT_NE(entry, nullptr) << name << " is not declared";
  return entry ? entry->at("default").get<double>() : -1;
}
} // namespace

// D349: thermo work reads deform.temperature (K) of recipe.json itself, not through rve/. The
// expanded recipe pnc characterize writes (here: pnc recipe show --expanded of two presets)
// carries the temperature the preset gives (demo_glass: 80 K), else the declared default (demo),
// bit for bit; a recipe.json without it, with a string or a negative value, or not JSON at all,
// is refused naming the file, key and rule.
TEST(ThermoWork, RecipeTemperatureIsReadAndBadOnesAreRefused) {
  const auto lin = [](double x) { return 1e9 * x; };
  for (const std::string preset : {"demo", "demo_glass"}) {
    const auto given = pnc::test::run_command(std::string(PNC_EXE) + " recipe show " + preset);
    ASSERT_EQ(given.code, 0) << given.out;
    const nlohmann::json deform = nlohmann::json::parse(given.out).at("deform");
    const double t = deform.contains("temperature") ? deform.at("temperature").get<double>()
                                                    : declared_default("deform.temperature");
    const auto d = make_run(scratch("rt_" + preset), 1, {1}, uniaxial(4, 1e-4), lin, 1e5);
    const auto expanded = pnc::test::run_command(std::string(PNC_EXE) + " recipe show " + preset +
                                                 " --expanded > " + d + "/recipe.json");
    ASSERT_EQ(expanded.code, 0) << expanded.out;
    EXPECT_EQ(thermo::read_work_run(d).temperature, t) << preset;
  }
  const auto d = make_run(scratch("rt_bad"), 300, {1}, uniaxial(4, 1e-4), lin, 1e5);
  const auto with = [&](const std::string& text) {
    std::ofstream(fs::path(d) / "recipe.json") << text;
    return d;
  };
  expect_input_error([&] { thermo::read_work_run(with(R"({"deform": {"steps": 4}})")); },
                     {"recipe.json", "deform.temperature", "is missing"});
  expect_input_error([&] { thermo::read_work_run(with(R"({"deform": {"temperature": "hot"}})")); },
                     {"recipe.json", "deform.temperature", "hot", "must be a number"});
  expect_input_error([&] { thermo::read_work_run(with(R"({"deform": {"temperature": -1}})")); },
                     {"recipe.json", "deform.temperature", "-1", ">= 0 K"});
  expect_input_error([&] { thermo::read_work_run(with("{\"deform\": ")); }, {"recipe.json"});
}

TEST(ThermoWork, SofteningIsFlagged) {
  // rises to a peak at eps = 0.01 and falls by 40 %: yield/damage, work is not free energy
  const auto r = thermo::stress_work(thermo::read_work_run(make_run(
      scratch("soft"), 300, {1}, uniaxial(40, 5e-4),
      [](double x) { return x < 0.01 ? 1e9 * x : 1e7 * (1 - 40 * (x - 0.01)); }, 1e5)));
  EXPECT_TRUE(r.cases[0].softening);
}

// `pnc thermo work` end to end: two runs, --json keys with units, work.h5 units attributes,
// work.csv columns, the run report, and the CLI's error for a missing run directory.
TEST(ThermoWork, CliTwoRunsJsonH5CsvAndReport) {
  const double C0 = 4e9, C1 = -5e6, h = 1e-4;
  const auto e = uniaxial(20, h);
  const auto d1 = make_run(
      scratch("cli1"), 250, {1}, e, [&](double x) { return (C0 + C1 * 250) * x; }, 1e5);
  const auto d2 = make_run(
      scratch("cli2"), 350, {1}, e, [&](double x) { return (C0 + C1 * 350) * x; }, 1e5);
  const fs::path out = scratch("cliout");
  const auto r =
      pnc::test::run_command(std::string(PNC_EXE) + " thermo work --from " + d1 + " --from " + d2 +
                             " --json --out " + out.string() + " 2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("runs"), 2);
  EXPECT_DOUBLE_EQ(j.at("temperature_K").get<double>(), 300.0);
  const auto& c = j.at("cases").at(0);
  const double eps = 20 * h;
  EXPECT_NEAR(c.at("entropic").at("da_J_per_m3").get<double>(), 300 * C1 * eps * eps / 2,
              1e-6 * C0 * eps * eps);
  EXPECT_NEAR(c.at("energetic").at("da_J_per_m3").get<double>(), C0 * eps * eps / 2,
              1e-6 * C0 * eps * eps);
  const double dA = c.at("total").at("dA_J").get<double>();
  EXPECT_NEAR(dA, (C0 + C1 * 300) * eps * eps / 2 * kV0_A3 * 1e-30, 1e-6 * std::fabs(dA));
  // the errors of dA are those of da times the box volume (SI only in --json, D280)
  EXPECT_NEAR(c.at("total").at("dA_stderr_bound_J").get<double>(),
              c.at("total").at("da_stderr_bound_J_per_m3").get<double>() * kV0_A3 * 1e-30,
              1e-12 * c.at("total").at("dA_stderr_bound_J").get<double>());
  EXPECT_FALSE(c.at("total").contains("dA_kcal_mol"));
  // every dataset of work.h5 that carries a quantity has units
  const h5::File f((out / "work.h5").string(), h5::File::Mode::read);
  for (const char* ds : {"/temperature", "/volume", "/case_1/strain", "/case_1/stress",
                         "/case_1/work/density", "/case_1/work/energy_kcal_mol",
                         "/case_1/work/density_stderr_indep", "/case_1/work/density_stderr_bound",
                         "/case_1/sigma_entropic", "/case_1/sigma_energetic_stderr",
                         "/case_1/work_entropic/density", "/case_1/work_T2/energy"})
    EXPECT_TRUE(f.attr_string(ds, "units").has_value()) << ds;
  std::ifstream csv(out / "work.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("case,point,e11_1,", 0), 0u) << header;
  EXPECT_NE(header.find("da_energetic_stderr_bound_J_per_m3"), std::string::npos) << header;
  // report.html: the verdict follows D143 from the --json numbers (resolved when |da| > 2 x its
  // any-correlation bound, for the total and, with two runs, for one of the split parts), each
  // case's da is on the page as printed, work.png is embedded and the page renders in Chromium
  ASSERT_EQ(j.at("report"), (out / "report.html").string());
  const std::string html = pnc::test::slurp((out / "report.html").string());
  const auto resolved = [](const nlohmann::json& w) {
    return std::fabs(w.at("da_J_per_m3").get<double>()) >
           2 * w.at("da_stderr_bound_J_per_m3").get<double>();
  };
  const bool ok =
      resolved(c.at("total")) && (resolved(c.at("entropic")) || resolved(c.at("energetic")));
  EXPECT_NE(html.find(ok ? "Resolved: every case (1)" : "No result"), std::string::npos);
  EXPECT_NE(html.find(fmt::format("{:.4g} ± ", c.at("total").at("da_J_per_m3").get<double>())),
            std::string::npos);
  ASSERT_EQ(j.at("plots").size(), 1u) << "python3-matplotlib is a test dependency";
  const auto b = pnc::test::render_in_chromium((out / "report.html").string(), out.string());
  ASSERT_EQ(b.error, "");
  EXPECT_EQ(b.images, std::vector<std::string>{"ok"}) << "work.png decodes";
  EXPECT_EQ(b.console, std::vector<std::string>{});
  EXPECT_GT(b.ink, 0.02); // a page with a table and a figure, not a blank one
  const auto bad =
      pnc::test::run_command(std::string(PNC_EXE) + " thermo work --from " +
                             (out / "nope").string() + " --out " + out.string() + " 2>&1");
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.out.find("recipe.json"), std::string::npos) << bad.out;
}

// D322: `pnc thermo work --input FILE` whose `from` names the runs relative to the file's
// folder prints the same --json numbers as --from with their paths (the same computation on
// the same files: bit for bit); --from on the command line replaces the file's `from` (D301).
TEST(ThermoWork, AnInputFileGivesTheSameRunAsTheOptionsAndFromOverridesIt) {
  const auto e = uniaxial(10, 1e-4);
  const auto d1 = make_run(
      scratch("in1"), 250, {1}, e, [](double x) { return 4e9 * x; }, 1e5);
  const auto d2 = make_run(
      scratch("in2"), 350, {1}, e, [](double x) { return 3e9 * x; }, 1e5);
  const fs::path folder = fs::path(d1).parent_path();
  const fs::path f = scratch("infile") / "w.toml"; // from its folder, the runs are ../<name>
  std::ofstream(f) << "from = [\"../" << fs::path(d1).filename().string() << "\", \"../"
                   << fs::path(d2).filename().string() << "\"]\n";
  const auto work = [](const std::string& args, const fs::path& out) {
    const auto r =
        pnc::test::run_command(std::string(PNC_EXE) + " thermo work " + args +
                               " --no-plots --json --out " + out.string() + " 2>/dev/null");
    EXPECT_EQ(r.code, 0) << args;
    auto j = nlohmann::json::parse(r.out, nullptr, false);
    for (const char* k : {"h5", "csv", "report", "wall_s"})
      j.erase(k);
    return j;
  };
  const auto a = work("--from " + d1 + " --from " + d2, scratch("outa"));
  const auto b = work("--input " + f.string(), scratch("outb"));
  ASSERT_TRUE(a.is_object());
  EXPECT_EQ(a.at("runs"), 2);
  EXPECT_EQ(a, b);
  const auto c = work("--input " + f.string() + " --from " + d1, scratch("outc"));
  EXPECT_EQ(c.at("runs"), 1);
  EXPECT_EQ(c.at("temperature_K"), 250.0);
  EXPECT_EQ(folder, fs::path(d2).parent_path());
}
