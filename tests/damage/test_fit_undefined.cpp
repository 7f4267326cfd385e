// The fit's path for constants the caller declares undefined by the data (FitOptions::undefined,
// used by pnc characterize when the phase check finds that the RVE relaxes within a hold).
#include "pnc/core/error.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/synth.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace pnc::damage;

namespace {
StressStrainData pp_data() {
  SynthOptions o;
  o.points = 80;
  o.noise_sd = 1e6;
  o.seed = 7;
  o.max_extension = 0.30; // past the pp damage onset (17.1 %)
  o.max_shear = 0.40;
  return synthesize(dissertation_parameters(Model::pp), o);
}
} // namespace

TEST(FitUndefined, DeclaredConstantsAreHeldAtThePriorWithTheReasonAndTheVerdictSaysWhy) {
  const auto data = pp_data();
  FitOptions o;
  o.model = Model::pp;
  // prior C44 different from the truth, so "held at the prior" is visible in its value (C44
  // enters only the shear case; the damage constants and alpha are held at the truth)
  NdmParameters prior = dissertation_parameters(Model::pp);
  prior["C44"] *= 0.5;
  o.prior = prior;
  const std::string why = "synthetic reason: the material flows";
  for (const char* n : {"C44", "B1", "B2", "B4", "alpha"})
    o.undefined.push_back({n, why});
  const FitReport rep = fit_ndm(data, o);
  const auto& names = constant_names(Model::pp);
  const NdmParameters truth = dissertation_parameters(Model::pp);
  for (std::size_t j = 0; j < names.size(); ++j) {
    const bool declared = names[j] != "C11" && names[j] != "C12";
    if (declared) {
      EXPECT_EQ(rep.status[j], "not identified") << names[j];
      EXPECT_FALSE(rep.fitted[j]) << names[j];
      EXPECT_NE(rep.note[j].find(why), std::string::npos) << rep.note[j];
      EXPECT_DOUBLE_EQ(rep.params.k[j], prior.k[j]) << names[j]; // exactly the prior
    } else {
      EXPECT_EQ(rep.status[j], "fitted") << names[j];
    }
  }
  // C11, C12: the extension case defines them; with the damage constants held at the truth
  // the estimate is unbiased: within 4 standard errors of the truth
  for (const char* n : {"C11", "C12"}) {
    const auto j = static_cast<std::size_t>(constant_index(Model::pp, n));
    ASSERT_TRUE(std::isfinite(rep.std_error[j])) << n;
    EXPECT_NEAR(rep.params.k[j], truth.k[j], 4 * rep.std_error[j]) << n;
  }
  bool said = false;
  for (const auto& r : rep.verdict.reasons)
    if (r.find("not defined by these data") != std::string::npos &&
        r.find(why) != std::string::npos)
      said = true;
  EXPECT_TRUE(said);
  EXPECT_NE(rep.verdict.level, VerdictLevel::usable);
  EXPECT_NE(rep.alpha_choice.find(why), std::string::npos) << rep.alpha_choice;
}

TEST(FitUndefined, UnknownNameOrEmptyReasonIsAnInputError) {
  FitOptions o;
  o.model = Model::pp;
  o.undefined = {{"C55", "x"}}; // a pnc constant, not pp
  EXPECT_THROW(o.validate(), pnc::InputError);
  o.undefined = {{"C44", ""}};
  EXPECT_THROW(o.validate(), pnc::InputError);
  o.undefined = {{"C44", "flows"}};
  EXPECT_NO_THROW(o.validate());
}
