// The MD gates of the card verdict (MdCardGates, decision D12f): each gate warns exactly when
// its condition fails, on synthetic curves whose statistics are known by construction.
#include "pnc/damage/data.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/synth.hpp"
#include "pnc/damage/verdict.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace pnc::damage;

namespace {

// Curves of the pure-polymer law with Gaussian noise of a known sd, recorded as the point
// errors: chi^2/dof is ~1 (sd sqrt(2/dof) ~ 0.08 for 160 points), far inside [0.5, 2].
StressStrainData pp_data(int points, double noise_pa, std::uint64_t seed = 7) {
  SynthOptions o;
  o.points = points;
  o.noise_sd = noise_pa;
  o.seed = seed;
  o.max_extension = 0.30; // past the pp damage onset (17.1 %)
  o.max_shear = 0.40;
  return synthesize(dissertation_parameters(Model::pp), o);
}

FitReport fit(const StressStrainData& d) {
  FitOptions o;
  o.model = Model::pp;
  return fit_ndm(d, o);
}

std::vector<std::string> gate_warnings(const FitReport& rep, const StressStrainData& d,
                                       const MdCardGates& g) {
  Verdict v;
  judge_md_card(rep, d, g, v);
  return v.reasons;
}

bool any_has(const std::vector<std::string>& r, const std::string& what) {
  for (const auto& s : r)
    if (s.find(what) != std::string::npos) return true;
  return false;
}

} // namespace

TEST(VerdictMd, AWellResolvedCardFromFourReplicasPassesEveryGate) {
  // 80 points a case, 1 MPa noise: about 45 points before the extension onset, standard errors
  // of every constant far below 10 % of its scale
  const auto d = pp_data(80, 1e6);
  const FitReport rep = fit(d);
  MdCardGates g;
  g.replicas = 4;
  const auto w = gate_warnings(rep, d, g);
  EXPECT_TRUE(w.empty()) << w.front();
}

TEST(VerdictMd, EachGateWarnsWhenItFails) {
  const auto d = pp_data(80, 1e6);
  const FitReport rep = fit(d);
  MdCardGates g;
  g.replicas = 2; // errors from two structures only
  auto w = gate_warnings(rep, d, g);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_TRUE(any_has(w, "2 independent replica(s)")) << w[0];

  // errors stated 3x too large: chi^2/dof ~ 1/9
  StressStrainData wide = d;
  for (auto& c : wide.cases)
    c.stress_stderr *= 3.0;
  g.replicas = 4;
  w = gate_warnings(fit(wide), wide, g);
  EXPECT_TRUE(any_has(w, "chi^2/dof")) << (w.empty() ? "" : w[0]);
  EXPECT_TRUE(any_has(w, "point errors are larger")) << (w.empty() ? "" : w[0]);

  // errors stated 3x too small: chi^2/dof ~ 9
  StressStrainData narrow = d;
  for (auto& c : narrow.cases)
    c.stress_stderr /= 3.0;
  w = gate_warnings(fit(narrow), narrow, g);
  EXPECT_TRUE(any_has(w, "scatter about the fit is larger")) << (w.empty() ? "" : w[0]);

  // 12 points to 30 % extension: 6 of them before the 17.1 % onset and one just past it where
  // the damage term is still below the 1 MPa point error (case 2: 7 < 8, D12j); the shear
  // case (onset at gamma ~ 0.33 of 0.40) keeps 9 and is not flagged
  const auto sparse = pp_data(12, 1e6);
  w = gate_warnings(fit(sparse), sparse, g);
  EXPECT_TRUE(any_has(w, "case 2: ")) << (w.empty() ? "" : w[0]);
  EXPECT_FALSE(any_has(w, "case 6: ")) << (w.empty() ? "" : w[0]);

  // 40 MPa noise: the damage constants are no longer resolved to 10 %
  const auto noisy = pp_data(80, 4e7);
  w = gate_warnings(fit(noisy), noisy, g);
  EXPECT_TRUE(any_has(w, "the standard error is")) << (w.empty() ? "" : w[0]);
}

// D12j: with the onset at zero strain (alpha = 1/lambda_c) the damage grows as the square of
// the stretch excess, D ~ (D''(lambda_c)/2) (lambda/alpha - lambda_c)^2, so the first rows
// are linear within their errors. The linear range counted by the gate is the rows where
// |2 B1 D(1 + e) e| (the damage term of sigma22 in case 2) stays below the point error.
TEST(VerdictMd, AnOnsetAtZeroStrainKeepsTheRowsWhereDamageIsBelowThePointError) {
  NdmParameters truth = dissertation_parameters(Model::pp);
  const double lc = critical_stretch(), a = 1.0 / lc;
  truth["alpha"] = a;
  const double sd = 1e6;
  SynthOptions so;
  so.points = 120;
  so.noise_sd = sd;
  so.seed = 5;
  so.max_extension = 0.12;
  so.max_shear = 0.2;
  so.cases = {2, 6};
  const StressStrainData d = synthesize(truth, so);
  // rows of case 2 whose damage term (closed form, true constants) is below the point error
  const double k = 1.0 / std::abs(2 * std::pow(lc, -13) - std::pow(lc, -7));
  int expected = 0;
  for (int i = 1; i <= so.points; ++i) {
    const double e = so.max_extension * i / so.points, x = (1 + e) / a;
    const double D = x > lc ? 1 + k * (2 * std::pow(x, -13) - std::pow(x, -7)) : 0.0;
    if (std::abs(2 * truth["B1"] * D * e) > sd) break;
    ++expected;
  }
  ASSERT_GT(expected, 20); // the premise: a long linear range although the onset is at zero
  FitOptions o;
  o.model = Model::pp;
  o.alpha_mode = AlphaMode::hold;
  o.alpha = a;
  const FitReport r = fit_ndm(d, o);
  MdCardGates g;
  g.replicas = 4;
  // the fitted constants differ from the truth within their errors: a margin of 25 % of rows
  g.min_linear_points = static_cast<int>(0.75 * expected);
  EXPECT_FALSE(any_has(gate_warnings(r, d, g), "case 2: "));
  g.min_linear_points = static_cast<int>(1.25 * expected) + 1;
  EXPECT_TRUE(any_has(gate_warnings(r, d, g), "case 2: "));
}

TEST(VerdictMd, DeterministicDataNeedNeitherReplicasNorPointErrors) {
  auto d = pp_data(80, 0.0); // no noise, no recorded errors
  for (auto& c : d.cases)
    c.stress_stderr.resize(0, 6);
  const FitReport rep = fit(d);
  MdCardGates g; // one "replica"
  g.deterministic = true;
  EXPECT_FALSE(any_has(gate_warnings(rep, d, g), "replica"));
  EXPECT_FALSE(any_has(gate_warnings(rep, d, g), "chi^2"));
  g.deterministic = false;
  EXPECT_TRUE(any_has(gate_warnings(rep, d, g), "replica"));
  EXPECT_TRUE(any_has(gate_warnings(rep, d, g), "no point errors"));
}
