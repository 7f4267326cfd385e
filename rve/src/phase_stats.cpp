// Phase check: estimators (autocorrelation with block errors, integrated time, slope), the
// classification and its wording (decisions D125-D129). Pure functions, no LAMMPS.
#include "pnc/rve/phase_check.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace pnc::rve {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
nlohmann::json jnum(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}
} // namespace

double integrated_time(const std::vector<double>& x, double dt) {
  const std::size_t n = x.size();
  if (n < 4) return kNaN;
  double m = 0;
  for (double v : x)
    m += v;
  m /= static_cast<double>(n);
  auto c = [&](std::size_t k) {
    double s = 0;
    for (std::size_t i = 0; i + k < n; ++i)
      s += (x[i] - m) * (x[i + k] - m);
    return s / static_cast<double>(n - k);
  };
  const double c0 = c(0);
  if (!(c0 > 0)) return 0.5 * dt;
  // Sokal's window: tau(W) = 1/2 + sum_{k<=W} rho(k); stop at the first W >= 5 tau(W)
  double tau = 0.5;
  for (std::size_t w = 1; w < n / 2; ++w) {
    tau += c(w) / c0;
    if (static_cast<double>(w) >= 5.0 * tau) break;
  }
  return std::max(0.5, tau) * dt;
}

AcfEstimate autocorrelation(const std::vector<std::vector<double>>& series, double dt, int max_lag,
                            int blocks) {
  if (series.empty() || max_lag < 0 || blocks < 2)
    throw std::invalid_argument("autocorrelation: no series, negative lag or < 2 blocks");
  const std::size_t n = series[0].size();
  for (const auto& s : series)
    if (s.size() != n) throw std::invalid_argument("autocorrelation: series of unequal length");
  const auto K = static_cast<std::size_t>(max_lag);
  if (n < K + 2 * static_cast<std::size_t>(blocks))
    throw std::invalid_argument(fmt::format(
        "autocorrelation: {} samples are too few for lags up to {} and {} blocks", n, K, blocks));
  const std::size_t origins = n - K, per = origins / static_cast<std::size_t>(blocks);
  std::vector<std::vector<double>> dev(series.size());
  AcfEstimate e;
  for (std::size_t c = 0; c < series.size(); ++c) {
    double m = 0;
    for (double v : series[c])
      m += v;
    m /= static_cast<double>(n);
    dev[c].resize(n);
    for (std::size_t i = 0; i < n; ++i)
      dev[c][i] = series[c][i] - m;
    e.tau_int += integrated_time(series[c], dt) / static_cast<double>(series.size());
  }
  e.blocks = blocks;
  e.block_length = static_cast<double>(per) * dt;
  e.blocks_ok = e.block_length >= kMinBlockOverTau * e.tau_int;
  std::vector<double> bv(static_cast<std::size_t>(blocks));
  e.block_values.reserve(K + 1);
  for (std::size_t k = 0; k <= K; ++k) {
    for (std::size_t b = 0; b < bv.size(); ++b) {
      double s = 0;
      for (const auto& d : dev)
        for (std::size_t i = b * per; i < (b + 1) * per; ++i)
          s += d[i] * d[i + k];
      bv[b] = s / static_cast<double>(per * dev.size());
    }
    double m = 0;
    for (double v : bv)
      m += v;
    m /= static_cast<double>(bv.size());
    double var = 0;
    for (double v : bv)
      var += (v - m) * (v - m);
    var /= static_cast<double>(bv.size() - 1);
    e.block_values.push_back(bv);
    e.lag.push_back(static_cast<double>(k) * dt);
    e.value.push_back(m);
    e.se.push_back(std::sqrt(var / static_cast<double>(bv.size())));
  }
  return e;
}

std::pair<double, double> window_mean(const AcfEstimate& e, std::size_t k0, std::size_t k1) {
  k1 = std::min(k1, e.block_values.size() - 1);
  k0 = std::min(k0, k1);
  const std::size_t nb = e.block_values[0].size();
  std::vector<double> w(nb, 0.0);
  for (std::size_t k = k0; k <= k1; ++k)
    for (std::size_t b = 0; b < nb; ++b)
      w[b] += e.block_values[k][b] / static_cast<double>(k1 - k0 + 1);
  double m = 0;
  for (double v : w)
    m += v;
  m /= static_cast<double>(nb);
  double var = 0;
  for (double v : w)
    var += (v - m) * (v - m);
  return {m, std::sqrt(var / static_cast<double>(nb - 1) / static_cast<double>(nb))};
}

MeanSe hold_mean_se(const std::vector<double>& x) {
  MeanSe m;
  m.mean = m.se = kNaN;
  if (x.size() < 8) return m;
  const double tau = integrated_time(x, 1.0);
  const int nb =
      std::min<int>(10, static_cast<int>(static_cast<double>(x.size()) / (kMinBlockOverTau * tau)));
  m.ok = nb >= 4;
  m.blocks = std::max(4, nb);
  const std::size_t per = x.size() / static_cast<std::size_t>(m.blocks);
  std::vector<double> bm(static_cast<std::size_t>(m.blocks), 0.0);
  double all = 0;
  for (std::size_t b = 0; b < bm.size(); ++b) {
    for (std::size_t i = 0; i < per; ++i)
      bm[b] += x[b * per + i];
    bm[b] /= static_cast<double>(per);
    all += bm[b];
  }
  m.mean = all / static_cast<double>(bm.size());
  double var = 0;
  for (double v : bm)
    var += (v - m.mean) * (v - m.mean);
  m.se = std::sqrt(var / static_cast<double>(bm.size() - 1) / static_cast<double>(bm.size()));
  return m;
}

std::pair<double, double> slope_se(const std::vector<double>& t, const std::vector<double>& y) {
  const std::size_t n = std::min(t.size(), y.size());
  if (n < 3) return {kNaN, kNaN};
  double mt = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    mt += t[i];
    my += y[i];
  }
  mt /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double stt = 0, sty = 0;
  for (std::size_t i = 0; i < n; ++i) {
    stt += (t[i] - mt) * (t[i] - mt);
    sty += (t[i] - mt) * (y[i] - my);
  }
  if (!(stt > 0)) return {kNaN, kNaN};
  const double b = sty / stt;
  double ss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = y[i] - my - b * (t[i] - mt);
    ss += r * r;
  }
  return {b, std::sqrt(ss / static_cast<double>(n - 2) / stt)};
}

// decision D128
void classify(PhaseCheckResult& r) {
  const double plateau = r.G_hold_Pa + std::max(0.0, r.G_plateau_Pa);
  const bool resolved = r.G_hold_Pa > kResolvedSigmas * r.G_hold_se_Pa;
  const double frac = plateau > 0 ? r.G_hold_Pa / plateau : kNaN;
  r.solid = resolved && std::isfinite(frac) && frac >= kSolidFraction;
  r.phase = r.solid ? "solid on the hold time scale" : "relaxes within a hold";
  std::string why;
  if (!resolved)
    why = fmt::format("the shear stress left after a step strain, G_hold = {:.3g} +- {:.2g} GPa, "
                      "is not resolved (not > {:.0f} standard errors)",
                      r.G_hold_Pa * 1e-9, r.G_hold_se_Pa * 1e-9, kResolvedSigmas);
  else
    why = fmt::format(
        "G_hold = {:.3g} +- {:.2g} GPa is {:.0f} % of the short-time plateau "
        "G_hold + max(0, mean G_acf over {:.2g}-{:.2g} ps) = {:.3g} GPa ({} {:.0f} %)",
        r.G_hold_Pa * 1e-9, r.G_hold_se_Pa * 1e-9, 100 * frac, 0.5 * kPlateauTime_s * 1e12,
        1.5 * kPlateauTime_s * 1e12, plateau * 1e-9, r.solid ? ">=" : "<", 100 * kSolidFraction);
  r.summary = fmt::format(
      "The RVE {} (hold {:.3g} ps at {:.1f} K): {}. Stress autocorrelation G_acf(t): {:.3g} +- "
      "{:.2g} GPa at t = 0, {:.3g} +- {:.2g} GPa at {:.1f} ps (mean over {:.2g}-{:.2g} ps: {:.3g} "
      "+- {:.2g} GPa), "
      "{:.3g} +- {:.2g} GPa at the hold time. Bulk modulus K = {:.3g} +- {:.2g} GPa.",
      r.solid     ? "is a solid on the hold time scale"
      : !resolved ? "relaxes within a hold as far as these data show (no shear stress is resolved "
                    "after a step strain)"
                  : "relaxes within a hold (most of its short-time shear modulus is gone after "
                    "one hold)",
      r.hold_time_s * 1e12, r.temperature_K, why, r.G_t0_Pa * 1e-9, r.G_t0_se_Pa * 1e-9,
      r.G_at_plateau_time_Pa * 1e-9, r.G_at_plateau_time_se_Pa * 1e-9, kPlateauTime_s * 1e12,
      0.5 * kPlateauTime_s * 1e12, 1.5 * kPlateauTime_s * 1e12, r.G_plateau_Pa * 1e-9,
      r.G_plateau_se_Pa * 1e-9, r.G_acf_hold_Pa * 1e-9, r.G_acf_hold_se_Pa * 1e-9, r.K_Pa * 1e-9,
      r.K_se_Pa * 1e-9);
  if (!r.blocks_ok)
    r.summary += fmt::format(" The autocorrelation blocks ({:.3g} ps) are shorter than {:.0f} "
                             "correlation times ({:.3g} ps): its error bars may be too small.",
                             r.block_s * 1e12, kMinBlockOverTau, r.tau_int_s * 1e12);
  if (!(r.K_Pa > kResolvedSigmas * r.K_se_Pa))
    r.summary += fmt::format(" K is not resolved (not > {:.0f} standard errors): a larger "
                             "phase_check.bulk_strain or a larger RVE would resolve it.",
                             kResolvedSigmas);
  if (!r.holds_blocks_ok)
    r.summary += " Some hold means had fewer than 4 blocks of 5 correlation times: their error "
                 "bars may be too small.";
  if (r.cavitates)
    r.summary += fmt::format(" Under a volumetric expansion of {:.3g} the box cavitates (void "
                             "fraction {:.4f} -> {:.4f}, P {:.3g} -> {:.3g} MPa).",
                             r.cav_strain, r.cav_void_first, r.cav_void_last,
                             r.cav_P_first_Pa * 1e-6, r.cav_P_last_Pa * 1e-6);
  if (!r.solid)
    r.summary += " Shear and damage constants fitted to these holds would be noise: the fit "
                 "holds them at the prior as not identified.";
}

nlohmann::json phase_json(const PhaseCheckResult& r) {
  return {{"phase", r.phase},
          {"solid", r.solid},
          {"hold_time_s", r.hold_time_s},
          {"temperature_K", r.temperature_K},
          {"nve_temperature_first_K", r.nve_T_first_K},
          {"nve_temperature_last_K", r.nve_T_last_K},
          {"G_t0_Pa", jnum(r.G_t0_Pa)},
          {"G_t0_stderr_Pa", jnum(r.G_t0_se_Pa)},
          {"G_plateau_Pa", jnum(r.G_plateau_Pa)},
          {"G_plateau_stderr_Pa", jnum(r.G_plateau_se_Pa)},
          {"plateau_time_s", kPlateauTime_s},
          {"G_at_plateau_time_Pa", jnum(r.G_at_plateau_time_Pa)},
          {"G_at_plateau_time_stderr_Pa", jnum(r.G_at_plateau_time_se_Pa)},
          {"G_acf_late_Pa", jnum(r.G_acf_late_Pa)},
          {"G_acf_late_stderr_Pa", jnum(r.G_acf_late_se_Pa)},
          {"G_acf_hold_Pa", jnum(r.G_acf_hold_Pa)},
          {"G_acf_hold_stderr_Pa", jnum(r.G_acf_hold_se_Pa)},
          {"G_hold_Pa", jnum(r.G_hold_Pa)},
          {"G_hold_stderr_Pa", jnum(r.G_hold_se_Pa)},
          {"tau_int_s", jnum(r.tau_int_s)},
          {"block_s", jnum(r.block_s)},
          {"blocks_ok", r.blocks_ok},
          {"holds_blocks_ok", r.holds_blocks_ok},
          {"K_Pa", jnum(r.K_Pa)},
          {"K_stderr_Pa", jnum(r.K_se_Pa)},
          {"cavitation_strain", r.cav_strain},
          {"cavitation_P_first_Pa", jnum(r.cav_P_first_Pa)},
          {"cavitation_P_last_Pa", jnum(r.cav_P_last_Pa)},
          {"cavitation_void_first", jnum(r.cav_void_first)},
          {"cavitation_void_last", jnum(r.cav_void_last)},
          {"cavitates", r.cavitates},
          {"density_drift_kg_per_m3_per_s", jnum(r.drift_kg_m3_s)},
          {"density_drift_stderr_kg_per_m3_per_s", jnum(r.drift_se_kg_m3_s)}};
}

std::string phase_markdown(const PhaseCheckResult& r) {
  std::string s = "## Phase check: " + r.phase + "\n\n" + r.summary + "\n\n";
  s += "| quantity | value |\n|---|---|\n";
  s += fmt::format("| G_acf(0) (stress autocorrelation) | {:.4g} +- {:.2g} GPa |\n",
                   r.G_t0_Pa * 1e-9, r.G_t0_se_Pa * 1e-9);
  s += fmt::format("| G_acf({:.1f} ps) | {:.4g} +- {:.2g} GPa |\n", kPlateauTime_s * 1e12,
                   r.G_at_plateau_time_Pa * 1e-9, r.G_at_plateau_time_se_Pa * 1e-9);
  s += fmt::format("| plateau: mean G_acf over {:.2g}-{:.2g} ps | {:.4g} +- {:.2g} GPa |\n",
                   0.5 * kPlateauTime_s * 1e12, 1.5 * kPlateauTime_s * 1e12, r.G_plateau_Pa * 1e-9,
                   r.G_plateau_se_Pa * 1e-9);
  s += fmt::format("| mean G_acf over t_hold/2 .. t_hold | {:.4g} +- {:.2g} GPa |\n",
                   r.G_acf_late_Pa * 1e-9, r.G_acf_late_se_Pa * 1e-9);
  s += fmt::format("| G_acf(t_hold = {:.3g} ps) | {:.4g} +- {:.2g} GPa |\n", r.hold_time_s * 1e12,
                   r.G_acf_hold_Pa * 1e-9, r.G_acf_hold_se_Pa * 1e-9);
  s += fmt::format("| G_hold (shear step pair, second half of the hold) | {:.4g} +- {:.2g} GPa |\n",
                   r.G_hold_Pa * 1e-9, r.G_hold_se_Pa * 1e-9);
  s += fmt::format("| NVE run: mean T, first / last tenth | {:.1f} K, {:.1f} / {:.1f} K |\n",
                   r.temperature_K, r.nve_T_first_K, r.nve_T_last_K);
  s += fmt::format("| correlation time / block length | {:.3g} ps / {:.3g} ps ({}) |\n",
                   r.tau_int_s * 1e12, r.block_s * 1e12, r.blocks_ok ? "ok" : "blocks TOO SHORT");
  s += fmt::format("| K (volume pair) | {:.4g} +- {:.2g} GPa |\n", r.K_Pa * 1e-9, r.K_se_Pa * 1e-9);
  s += fmt::format("| cavitation hold (volumetric strain {:.3g}): P second / last quarter | "
                   "{:.3g} +- {:.2g} / {:.3g} +- {:.2g} MPa |\n",
                   r.cav_strain, r.cav_P_first_Pa * 1e-6, r.cav_P_first_se_Pa * 1e-6,
                   r.cav_P_last_Pa * 1e-6, r.cav_P_last_se_Pa * 1e-6);
  s += fmt::format("| void fraction after the first quarter / at the end | {:.4f} / {:.4f}{} |\n",
                   r.cav_void_first, r.cav_void_last, r.cavitates ? " (CAVITATES)" : "");
  if (std::isfinite(r.drift_kg_m3_s))
    s += fmt::format("| density drift, second half of the NPT run | {:.3g} +- {:.2g} kg/m^3 per "
                     "ns |\n",
                     r.drift_kg_m3_s * 1e-9, r.drift_se_kg_m3_s * 1e-9);
  s += fmt::format("\nClassification (decision D128): solid when G_hold > {:.0f} s.e. and G_hold "
                   ">= {:.0f} % of G_hold + max(0, plateau). Numbers in {}/phase.h5.\n\n",
                   kResolvedSigmas, 100 * kSolidFraction, "phase");
  return s;
}

} // namespace pnc::rve
