// The bootstrap of the joint fit over replicas (replica_bootstrap.hpp, decision D431).
#include "pnc/rve/replica_bootstrap.hpp"

#include "pnc/core/error.hpp"
#include "pnc/rve/replica_fits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace pnc::rve {

double ReplicaBootstrap::ratio_stderr(std::size_t i) const {
  return i < ratio.size() && resamples >= 2 ? ratio[i] / std::sqrt(2.0 * (resamples - 1))
                                            : std::nan("");
}

damage::StressStrainData replica_mean_data(const CombinedCases& c, const std::vector<int>& pick) {
  damage::StressStrainData d;
  d.source = "replica mean";
  d.stress_definition = c.stress_definition;
  for (const auto& cc : c.cases) {
    damage::CaseCurve cv;
    cv.id = cc.id;
    cv.strain = cc.strain;
    replica_mean_curve(cc, pick, cv.stress, cv.stress_stderr);
    d.cases.push_back(std::move(cv));
  }
  return d;
}

ReplicaBootstrap bootstrap_joint_fit(const CombinedCases& c, const damage::FitOptions& options,
                                     const damage::FitReport& joint,
                                     const std::vector<double>& card_error, int resamples,
                                     std::uint64_t seed) {
  ReplicaBootstrap b;
  b.replicas = c.replicas;
  b.seed = seed;
  b.names = damage::constant_names(options.model);
  const std::size_t nk = b.names.size();
  b.value.assign(nk, std::nan(""));
  b.card_error.assign(nk, std::nan(""));
  b.spread.assign(nk, std::nan(""));
  b.ratio.assign(nk, std::nan(""));
  b.raised.assign(nk, false);
  for (std::size_t i = 0; i < nk && i < joint.params.k.size(); ++i) {
    b.value[i] = joint.params.k[i];
    if (i < joint.fitted.size() && joint.fitted[i] && i < card_error.size())
      b.card_error[i] = card_error[i];
  }
  if (c.replicas < kBootstrapMinReplicas || c.cases.empty()) {
    b.why_not = fmt::format("needs >= {} replicas (this run: {}): with fewer the resamples are "
                            "too few and too alike",
                            kBootstrapMinReplicas, c.replicas);
    return b;
  }
  if (resamples < 20) {
    b.why_not = fmt::format("fit.bootstrap = {} resamples (off below 20)", resamples);
    return b;
  }
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> draw(0, c.replicas - 1);
  std::vector<double> sum(nk, 0.0), sum2(nk, 0.0);
  std::vector<int> pick(static_cast<std::size_t>(c.replicas));
  for (int s = 0; s < resamples; ++s) {
    for (auto& p : pick)
      p = draw(rng);
    try {
      const damage::FitReport f = damage::fit_ndm(replica_mean_data(c, pick), options);
      if (!f.converged) {
        ++b.failed;
        continue;
      }
      for (std::size_t i = 0; i < nk; ++i) {
        // deviations from the card's value: no cancellation in the sums at GPa scale
        const double d = f.params.k[i] - b.value[i];
        sum[i] += d;
        sum2[i] += d * d;
      }
      ++b.resamples;
    } catch (const InputError&) {
      ++b.failed;
    }
  }
  if (b.resamples < 20) {
    b.why_not = fmt::format("only {} of {} refits converged", b.resamples, resamples);
    return b;
  }
  const double m = b.resamples;
  // a resample's mean of N draws varies by sqrt((N-1)/N) x the sampling error of the run's
  // mean: the spread is scaled back (D431), so that it estimates the spread over runs
  const double bias = std::sqrt(static_cast<double>(c.replicas) / (c.replicas - 1));
  for (std::size_t i = 0; i < nk; ++i) {
    if (!std::isfinite(b.card_error[i])) continue;
    const double mean = sum[i] / m;
    b.spread[i] = bias * std::sqrt(std::max(0.0, (sum2[i] - m * mean * mean) / (m - 1)));
    b.ratio[i] = b.spread[i] / b.card_error[i];
  }
  b.applicable = true;
  return b;
}

int apply_bootstrap(ReplicaBootstrap& b, std::vector<double>& std_error) {
  if (!b.applicable) return 0;
  std::vector<double> floor(b.spread.size(), std::nan(""));
  for (std::size_t i = 0; i < floor.size(); ++i)
    if (std::isfinite(b.ratio[i])) floor[i] = b.spread[i];
  return raise_errors(std_error, floor, &b.raised);
}

std::string replica_bootstrap_markdown(const ReplicaBootstrap& b) {
  if (!b.shown()) return "";
  std::string s = "### Calibration of the error bars: bootstrap of the joint fit\n\n";
  if (!b.applicable) return s + "Not run: " + b.why_not + " (D431).\n\n";
  s += fmt::format(
      "The joint fit repeated on {} resamples of the {} replicas drawn with replacement (seed "
      "{}; {} refit(s) failed and are left out). The spread of a constant over the resamples, "
      "times sqrt(N/(N-1)) for the bootstrap's bias, is its sampling error as the joint fit "
      "gives it; the card's error (D130) should not be smaller. Ratio = spread / card error, with "
      "its own sampling error: near 1 or below, "
      "the card's error covers the spread; where the spread is larger the card's error was "
      "raised to it (D431).\n\n| constant | value | card error (before) | bootstrap spread | "
      "ratio | raised |\n|---|---|---|---|---|---|\n",
      b.resamples, b.replicas, b.seed, b.failed);
  for (std::size_t i = 0; i < b.names.size(); ++i) {
    if (!std::isfinite(b.ratio[i])) continue;
    const bool alpha = b.names[i] == "alpha";
    const double u = alpha ? 1.0 : 1e-9;
    const char* unit = alpha ? "" : " GPa";
    s += fmt::format("| {} | {:.4g}{} | {:.3g}{} | {:.3g}{} | {:.2f} +- {:.2f} | {} |\n",
                     b.names[i], b.value[i] * u, unit, b.card_error[i] * u, unit, b.spread[i] * u,
                     unit, b.ratio[i], b.ratio_stderr(i), b.raised[i] ? "yes" : "no");
  }
  return s + "\n";
}

std::string replica_bootstrap_summary(const ReplicaBootstrap& b) {
  if (!b.shown()) return "";
  if (!b.applicable)
    return "pnc characterize: error bars not checked by a bootstrap (D431): " + b.why_not + "\n";
  double lo = INFINITY, hi = -INFINITY;
  std::string raised;
  for (std::size_t i = 0; i < b.names.size(); ++i) {
    if (!std::isfinite(b.ratio[i])) continue;
    lo = std::min(lo, b.ratio[i]);
    hi = std::max(hi, b.ratio[i]);
    if (b.raised[i]) raised += (raised.empty() ? "" : ", ") + b.names[i];
  }
  return fmt::format("pnc characterize: error bars checked by a bootstrap over the {} replicas "
                     "({} resamples{}, D431): spread / card error {:.2f}-{:.2f}; raised to the "
                     "spread: {}\n",
                     b.replicas, b.resamples,
                     b.failed > 0 ? fmt::format(", {} refit(s) failed, left out", b.failed) : "",
                     lo, hi, raised.empty() ? "none" : raised);
}

nlohmann::json replica_bootstrap_json(const ReplicaBootstrap& b) {
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  if (!b.shown()) return nullptr;
  nlohmann::json j = {{"applicable", b.applicable},
                      {"replicas", b.replicas},
                      {"resamples", b.resamples},
                      {"failed", b.failed},
                      {"seed", b.seed}};
  if (!b.applicable) {
    j["why_not"] = b.why_not;
    return j;
  }
  nlohmann::json cs = nlohmann::json::object();
  for (std::size_t i = 0; i < b.names.size(); ++i) {
    if (!std::isfinite(b.ratio[i])) continue;
    const std::string unit = b.names[i] == "alpha" ? "1" : "Pa";
    cs[b.names[i]] = {{"card_error_before_" + unit, num(b.card_error[i])},
                      {"spread_" + unit, num(b.spread[i])},
                      {"ratio", num(b.ratio[i])},
                      {"ratio_stderr", num(b.ratio_stderr(i))},
                      {"raised", static_cast<bool>(b.raised[i])}};
  }
  j["constants"] = cs;
  return j;
}

} // namespace pnc::rve
