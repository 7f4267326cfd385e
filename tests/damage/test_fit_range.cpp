// The fit range (decision D12h) and the onset-below-zero-strain warning (D12i), on synthetic
// pure-polymer curves of the kernel itself with known constants.
#include "pnc/core/error.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/synth.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

using namespace pnc::damage;

namespace {

StressStrainData pp_curves(const NdmParameters& truth, double noise_pa, int points) {
  SynthOptions o;
  o.cases = {2, 6};
  o.points = points;
  o.max_extension = 0.3;
  o.max_shear = 0.4;
  o.noise_sd = noise_pa;
  o.seed = 17;
  return synthesize(truth, o);
}

bool has_reason(const Verdict& v, const std::string& text) {
  for (const auto& r : v.reasons)
    if (r.find(text) != std::string::npos) return true;
  return false;
}

double max_abs_z(const FitReport& r, const NdmParameters& truth) {
  double z = 0;
  for (std::size_t i = 0; i < truth.size(); ++i)
    if (r.fitted[i]) z = std::max(z, std::abs(r.params.k[i] - truth.k[i]) / r.std_error[i]);
  return z;
}

} // namespace

TEST(FitRange, OnlyTheRowsWithinStrainMaxAreFittedAndTheCardSaysSo) {
  NdmParameters truth = dissertation_parameters(Model::pp);
  truth["alpha"] = 0.85; // onset at extension 0.058 and shear 0.117: both inside 0.15
  StressStrainData d = pp_curves(truth, 0.2e6, 120);
  // a regime the law has no term for beyond 0.15 (e.g. cavitation): the stress halves
  int beyond = 0;
  for (auto& c : d.cases)
    for (Eigen::Index k = 0; k < c.strain.rows(); ++k)
      if (c.strain.row(k).cwiseAbs().maxCoeff() > 0.15) {
        c.stress.row(k) *= 0.5;
        ++beyond;
      }
  ASSERT_GT(beyond, 20);
  FitOptions o;
  o.model = Model::pp;
  o.strain_max = 0.15;
  // the tables' start alpha (0.941: onset at 0.171) lies beyond the range, where its column
  // vanishes: a start inside the range, as a user gives it with --alpha
  o.alpha_mode = AlphaMode::fit;
  o.alpha = 0.9;
  const FitReport r = fit_ndm(d, o);
  EXPECT_EQ(r.rows_beyond_strain_max, beyond);
  EXPECT_DOUBLE_EQ(r.strain_max, 0.15);
  for (std::size_t j = 0; j < r.fitted.size(); ++j)
    EXPECT_TRUE(r.fitted[j]) << r.note[j];
  // 7 constants: all |z| < 4 by chance with probability 0.9996
  EXPECT_LT(max_abs_z(r, truth), 4.0);
  EXPECT_FALSE(has_reason(r.verdict, "does not fit")) << r.chi2 / r.dof;
  // the card carries the range
  const auto dir = pnc::test::fresh_dir("test_fit_range");
  const std::string path = (dir / "card.h5").string();
  write_card(path, card_from_fit(r, d, "none"), "test");
  const Card c = read_card(path);
  EXPECT_DOUBLE_EQ(c.fit.strain_max, 0.15);
  EXPECT_EQ(c.fit.rows_beyond_strain_max, beyond);
  std::filesystem::remove_all(dir);
  // without the range the corrupted rows are fitted too, and the misfit is flagged
  FitOptions all = o;
  all.strain_max = 0;
  const FitReport a = fit_ndm(d, all);
  EXPECT_EQ(a.rows_beyond_strain_max, 0);
  EXPECT_TRUE(has_reason(a.verdict, "does not fit the data within their standard errors"));
}

TEST(FitRange, ARangeThatLeavesTooFewRowsIsRefusedWithTheCaseNamed) {
  const StressStrainData d = pp_curves(dissertation_parameters(Model::pp), 1e6, 40);
  FitOptions o;
  o.model = Model::pp;
  o.strain_max = 0.01; // rows at 0.0075, 0.015, ...: one row of case 2
  try {
    fit_ndm(d, o);
    FAIL() << "expected an input error";
  } catch (const pnc::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("case 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("strain_max"), std::string::npos) << e.what();
  }
  o.strain_max = -1;
  EXPECT_THROW(fit_ndm(d, o), pnc::InputError);
}

TEST(FitVerdict, AnOnsetBelowZeroStrainIsAWarningAndAFittedAlphaStopsAtZeroStrain) {
  const double bound = 1.0 / critical_stretch(); // 0.8035
  for (double alpha : {0.78, 0.85}) {
    NdmParameters truth = dissertation_parameters(Model::pp);
    truth["alpha"] = alpha;
    const StressStrainData d = pp_curves(truth, 0.5e6, 80);
    FitOptions o;
    o.model = Model::pp;
    o.alpha_mode = AlphaMode::fit;
    o.alpha = alpha; // below the bound: the fit starts on it
    const FitReport r = fit_ndm(d, o);
    if (alpha < bound) {
      // the data want an onset below zero strain; the fit stops on the bound and says so
      EXPECT_EQ(r.status.back(), "at bound") << r.alpha_choice;
      EXPECT_FALSE(r.fitted.back());
      EXPECT_NEAR(r.params.alpha(), bound, 1e-9);
      EXPECT_FALSE(has_reason(r.verdict, "puts the damage onset at the stretch"));
      // held there by the user instead: the verdict warns
      FitOptions h = o;
      h.alpha_mode = AlphaMode::hold;
      const FitReport rh = fit_ndm(d, h);
      EXPECT_TRUE(has_reason(rh.verdict, "puts the damage onset at the stretch"));
    } else {
      ASSERT_TRUE(r.fitted.back());
      EXPECT_LT(std::abs(r.params.alpha() - alpha), 5 * r.std_error.back());
      EXPECT_FALSE(has_reason(r.verdict, "puts the damage onset at the stretch"));
    }
  }
}

TEST(FitRange, AStretchRangeAdmitsTheSameLargestPrincipalStretchInExtensionAndShear) {
  // Decision D12m. Extension e: lambda_max - 1 = e. Simple shear gamma (F = I + gamma e1 (x) e2):
  // lambda_max = gamma/2 + sqrt(1 + gamma^2/4), and lambda_max = 1 + s exactly when
  // gamma = (1 + s) - 1 / (1 + s) (lambda - 1/lambda = gamma for the principal stretches).
  const double s = 0.08;
  const double gamma_s = (1 + s) - 1 / (1 + s);
  PathMatrix ext = PathMatrix::Zero(41, 6), shear = PathMatrix::Zero(41, 6);
  for (int k = 0; k <= 40; ++k) {
    ext(k, 1) = 0.005 * k;   // 0 .. 0.2
    shear(k, 5) = 0.005 * k; // 0 .. 0.2
  }
  auto expected = [](double limit) {
    return static_cast<Eigen::Index>(std::floor(limit / 0.005 + 1e-9)) + 1;
  };
  EXPECT_EQ(rows_in_fit_range(ext, 0, s), expected(s));
  EXPECT_EQ(rows_in_fit_range(shear, 0, s), expected(gamma_s));
  EXPECT_GT(gamma_s, 1.9 * s); // a shear reaches the same stretch at about twice the strain
  // the strain range cuts both at the same component value; no range keeps every row
  EXPECT_EQ(rows_in_fit_range(shear, s, 0), expected(s));
  EXPECT_EQ(rows_in_fit_range(shear, 0, 0), 41);
}

TEST(FitRange, TheStretchRangeIsFittedRecordedOnTheCardAndExcludesTheStrainRange) {
  NdmParameters truth = dissertation_parameters(Model::pp);
  truth["alpha"] = 0.85;
  StressStrainData d = pp_curves(truth, 0.2e6, 120);
  FitOptions o;
  o.model = Model::pp;
  o.stretch_max = 0.15;
  o.alpha_mode = AlphaMode::fit;
  o.alpha = 0.9;
  const FitReport r = fit_ndm(d, o);
  int beyond = 0;
  for (const auto& c : d.cases)
    beyond += static_cast<int>(c.strain.rows() - rows_in_fit_range(c.strain, 0, 0.15));
  EXPECT_GT(beyond, 0);
  EXPECT_EQ(r.rows_beyond_strain_max, beyond);
  EXPECT_DOUBLE_EQ(r.stretch_max, 0.15);
  EXPECT_LT(max_abs_z(r, truth), 4.0);
  const auto dir = pnc::test::fresh_dir("test_fit_stretch_range");
  const std::string path = (dir / "card.h5").string();
  write_card(path, card_from_fit(r, d, "none"), "test");
  const Card c = read_card(path);
  EXPECT_DOUBLE_EQ(c.fit.stretch_max, 0.15);
  EXPECT_DOUBLE_EQ(c.fit.strain_max, 0.0);
  std::filesystem::remove_all(dir);
  o.strain_max = 0.1; // both ranges at once: refused, naming the option
  try {
    fit_ndm(d, o);
    FAIL() << "expected an input error";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().field, "stretch_max");
  }
}
