// The fit unit of `pnc characterize`: cases.h5 -> NDM fit -> card, plots, report.md and
// summary.json (app/characterize.hpp). Units: cases.h5 and cards in Pa (SI).
#include "characterize.hpp"
#include "plot.hpp"
#include "report.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/version.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/moduli.hpp"
#include "pnc/rve/replica_fits.hpp"
#include "pnc/rve/replica_trend.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace pnc::app {

namespace fs = std::filesystem;

namespace {
std::string code_block(const std::string& s) {
  return "```\n" + s + "```\n";
}
/// The fit unit's results, from which the card, the report and the summary are made.
struct MdFit {
  damage::FitOptions o;
  damage::StressStrainData data;
  damage::FitReport rep;
  rve::ReplicaFits replica_fits;
  damage::Card card;
  rve::ReplicaTrend trend;
};

struct FitContext {
  const rve::Recipe& r;
  const rve::MdOutcome& md;
  const FitUnitArgs& a;
  MdFit f;
  std::string card_path, command, report_path;
  std::vector<std::string> pngs;
  damage::DerivedModuli dm;
  double total_s = 0;
  nlohmann::json clay_info; ///< the builder's clay.json (model pnc)
};

/// The joint NDM fit of cases.h5 with the replicas' honest errors and the MD verdict gates.
MdFit fit_md(const rve::Recipe& r, const rve::MdOutcome& md) {
  using namespace pnc::damage;
  MdFit f;
  FitOptions& o = f.o;
  // the bead-spring glass (model kg) is a pure polymer: the pure-polymer NDM (decision D138)
  // and the glass with a platelet (kg_platelet) a nanocomposite: the nanocomposite NDM (D175)
  o.model = parse_model(r.model == "kg"            ? std::string("pp")
                        : r.model == "kg_platelet" ? std::string("pnc")
                                                   : r.model,
                        md.recipe_path + ": model");
  // recipe fit_alpha = true always fits alpha; otherwise automatic (D12b). The MD pipeline
  // writes SI stresses itself, so an implausible stiffness is a verdict, not a unit mistake.
  o.alpha_mode = r.fit_alpha    ? AlphaMode::fit
                 : r.hold_alpha ? AlphaMode::hold
                                : AlphaMode::automatic;
  if (r.fit_alpha_start > 0) o.alpha = r.fit_alpha_start; // recipe fit.alpha (decision D138)
  o.strain_max = r.fit_strain_max;                        // recipe fit.strain_max (D12h)
  o.check_units = false;
  // decision D128: a material that relaxes within a hold does not define its shear and damage
  // constants; only the normal (bulk-like) block of C0 stays fitted
  if (md.phase.done && !md.phase.solid)
    for (const auto& n : constant_names(o.model))
      if (!(n.size() == 3 && n[0] == 'C' && n[1] <= '3' && n[2] <= '3'))
        o.undefined.push_back(
            {n, fmt::format("the phase check finds that the RVE relaxes within a hold (G_hold = "
                            "{:.3g} +- {:.2g} GPa; phase/phase.h5), so shear and damage "
                            "responses are not carried over a strain hold",
                            md.phase.G_hold_Pa * 1e-9, md.phase.G_hold_se_Pa * 1e-9)});
  o.validate();
  f.data = read_stress_strain(md.cases_h5);
  const StressStrainData& data = f.data;
  f.rep = fit_ndm(data, o);
  const FitReport& rep = f.rep;
  // decision D130: with >= 2 replicas every replica is fitted on its own as well
  f.replica_fits = rve::fit_replicas(md.statistics, o);
  const rve::ReplicaFits& replica_fits = f.replica_fits;
  f.card = card_from_fit(rep, data, "none");
  Card& card = f.card;
  // decision D130: the joint fit treats the points of the replica-mean curves as independent,
  // but a replica's deviations are correlated along its curves; the card's standard error of a
  // constant is the larger of the joint fit's and the between-replica one (t x sd/sqrt(N) of
  // the replicas' own fits), so that no reported error is smaller than the scatter between
  // independent RVEs says
  FitReport honest = rep;
  if (replica_fits.replicas >= 2) {
    int raised = 0;
    for (std::size_t j = 0; j < card.std_error.size() && j < replica_fits.se.size(); ++j) {
      if (!card.fitted[j] || !std::isfinite(replica_fits.se[j])) continue;
      const double between = replica_fits.coverage_factor * replica_fits.se[j];
      if (!(between <= card.std_error[j])) {
        card.std_error[j] = between;
        ++raised;
      }
    }
    honest.std_error = card.std_error;
    card.fit.error_model += fmt::format(
        "; per constant the larger of that and the between-replica standard error of {} "
        "separate replica fits (Student t factor {:.3g}; D130): {} constant(s) raised",
        replica_fits.replicas, replica_fits.coverage_factor, raised);
  }
  // decision D12k: with >= 3 replicas the residuals of the mean curves are correlated along
  // the curves; misfit is tested across replicas instead of by the runs test and chi^2 p
  f.trend = rve::replica_trend_test(md.statistics, rep, o.strain_max);
  const rve::ReplicaTrend& trend = f.trend;
  if (trend.applicable) {
    static const char* kVoigt[6] = {"11", "22", "33", "23", "13", "12"};
    VerdictLimits limits;
    limits.independent_residuals = false;
    card.verdict = judge_fit(honest, limits);
    if (trend.p_family < limits.p_misfit) {
      const auto worst = std::min_element(
          trend.curves.begin(), trend.curves.end(),
          [](const rve::TrendCurve& x, const rve::TrendCurve& y) { return x.p < y.p; });
      card.verdict.warn(fmt::format(
          "the model misses a trend common to the {} replicas (case {} sigma{}: Legendre "
          "coefficients of the residuals against their between-replica errors, p = {:.2g}, "
          "Bonferroni over {} curves; D12k)",
          trend.replicas, worst->case_id, kVoigt[worst->component % 6], trend.p_family,
          trend.curves.size()));
    }
  }
  // decision D12f: what "usable" means for an MD card (replicas, chi^2/dof, relative errors,
  // points in the linear range)
  MdCardGates gates;
  gates.replicas = md.statistics.replicas;
  gates.deterministic = r.deform.temperature == 0;
  judge_md_card(honest, data, gates, card.verdict);
  return f;
}

/// report.md: the RVE, its equilibration and phase check, the statistics, the constants, the
/// fit's quality, the derived moduli, the verdict, the plots and the wall times.
std::string report_markdown(FitContext& ctx) {
  using namespace pnc::damage;
  [[maybe_unused]] const rve::Recipe& r = ctx.r;
  [[maybe_unused]] const rve::MdOutcome& md = ctx.md;
  [[maybe_unused]] const FitUnitArgs& a = ctx.a;
  [[maybe_unused]] const Card& card = ctx.f.card;
  [[maybe_unused]] const FitOptions& o = ctx.f.o;
  [[maybe_unused]] const StressStrainData& data = ctx.f.data;
  [[maybe_unused]] const FitReport& rep = ctx.f.rep;
  [[maybe_unused]] const rve::ReplicaFits& replica_fits = ctx.f.replica_fits;
  [[maybe_unused]] const rve::ReplicaTrend& trend = ctx.f.trend;
  [[maybe_unused]] const std::vector<std::string>& pngs = ctx.pngs;
  [[maybe_unused]] const DerivedModuli& dm = ctx.dm;
  [[maybe_unused]] const double total_s = ctx.total_s;
  [[maybe_unused]] const std::string& card_path = ctx.card_path;
  [[maybe_unused]] const std::string& command = ctx.command;
  const auto& e = md.equilibrated;
  std::string rep_md;
  rep_md += fmt::format("# pnc characterize: recipe `{}`\n\n", r.name);
  rep_md +=
      fmt::format("{} -- {} UTC. Command: `{}`.\n\n", version_string(), utc_timestamp(), command);
  rep_md += "## RVE\n\n";
  if (r.system.enabled) // your own system (rve/user_system.hpp)
    rep_md += rve::user_system_report(r.system);
  else if (r.model == "kg" || r.model == "kg_platelet")
    rep_md += fmt::format(
        "{} chains x {} beads ({} beads, {} g/mol), built at {} g/cm3, seed {}; glassy "
        "bead-spring polymer (FENE + LJ 12-6, sigma {} A, eps/k_B {:.0f} K, tau {:.0f} fs, "
        "stress unit eps/sigma^3 = {:.1f} MPa; decision D135).\n\n",
        r.build.chains, r.build.beads_per_chain, r.build.chains * r.build.beads_per_chain,
        r.kg.bead_mass, r.build.density, r.seed, r.kg.sigma, r.kg.temperature_unit(), r.kg.tau_fs(),
        r.kg.stress_unit_pa() * 1e-6);
  else
    rep_md += fmt::format("{} chains x {} beads ({} beads, 21 g/mol), built at {} g/cm3, seed {}; "
                          "force field of section 6.1 (decision D13 units).\n\n",
                          r.build.chains, r.build.beads_per_chain,
                          r.build.chains * r.build.beads_per_chain, r.build.density, r.seed);
  if (r.model == "kg_platelet") // what the builder wrote (platelet.json), decision D170
    rep_md += fmt::format(
        "Embedded platelet (decision D170): {0} x {0} x {1} beads at {2} sigma, normal x2, "
        "harmonic bond network K = {3} eps/sigma^2; platelet-polymer LJ eps_wp = {4} eps, "
        "sigma_wp = {5} sigma (record {6}).\n\n",
        r.platelet.beads_side, r.platelet.layers, r.platelet.spacing_sigma,
        r.platelet.bond_K_reduced, r.platelet.epsilon_wp_reduced, r.platelet.sigma_wp_sigma,
        (fs::path(md.build_record).parent_path() / "platelet.json").string());
  nlohmann::json& clay_info =
      ctx.clay_info; // what the builder wrote (clay.json next to build.h5), model pnc
  if (r.model == "pnc") {
    const auto cp = fs::path(md.build_record).parent_path() / "clay.json";
    std::ifstream cf(cp);
    if (cf) clay_info = nlohmann::json::parse(cf, nullptr, false);
    if (clay_info.is_object() && !clay_info.is_discarded())
      rep_md += fmt::format(
          "Montmorillonite platelet (C2/m cell, Table 3.1): {} x {} cells, {} atoms, {:.2f} x "
          "{:.2f} x {:.2f} A (aspect ratio {:.2f}); clay volume fraction {:.4f}, weight fraction "
          "{:.4f} (definitions in {}).\n\n",
          clay_info.value("cells_a", 0), clay_info.value("cells_b", 0),
          clay_info.value("clay_atoms", 0), clay_info.value("platelet_length_A", 0.0),
          clay_info.value("platelet_width_A", 0.0), clay_info.value("platelet_thickness_A", 0.0),
          clay_info.value("aspect_ratio_length_over_width", 0.0),
          clay_info.value("volume_fraction", 0.0), clay_info.value("weight_fraction", 0.0),
          fs::relative(cp, a.out).string());
    else
      rep_md += fmt::format("Clay record {} is missing or unreadable.\n\n", cp.string());
  }
  rep_md += "Equilibration (one line per stage, with the criterion that ended it):\n\n";
  for (const auto& c : e.criteria)
    rep_md += "- " + c + "\n";
  rep_md += fmt::format(
      "\n| equilibrated RVE | value |\n|---|---|\n| ensemble | {} |\n| density | {:.4f} g/cm3 |\n"
      "| pressure (with kinetic term) | {:.0f} +- {:.0f} atm |\n| pressure (virial only) | {:.0f} "
      "atm |\n"
      "| temperature | {:.1f} K |\n| void fraction (1 A grid, farther than sigma from every bead) "
      "| {:.4f} |\n"
      "| smallest pair distance | {:.3f} A |\n\n",
      r.system.enabled ? std::string("user stages") : r.equilibrate.ensemble, e.density,
      e.pressure_total, e.pressure_total_se, e.pressure_virial, e.temperature, e.void_fraction,
      e.min_distance);
  if (md.phase.done) rep_md += rve::phase_markdown(md.phase);
  rep_md += fmt::format(
      "Deformation: cases {}, strain 0 -> {} in {} steps, {}. Stress handed to the fit: {}.\n\n",
      nlohmann::json(r.cases).dump(), r.deform.strain_max, r.deform.steps,
      r.deform.temperature == 0 // static rows (decision D120)
          ? std::string("static at 0 K (no hold)")
          : fmt::format("hold {} steps of {} fs, samples every {} steps", r.deform.hold_steps,
                        r.deform.timestep_fs, r.deform.sample_every),
      data.stress_definition);
  rep_md += md.statistics_markdown; // error method, replicas, block check (D130-D134)
  rep_md += "## Fitted constants\n\n" + code_block(constants_table(card));
  rep_md += rve::replica_fits_markdown(replica_fits, rep);
  rep_md += rve::replica_trend_markdown(trend);
  rep_md += "\n## Fit quality and the dissertation's tables\n\n" +
            code_block(fit_tables(card.fit, o.model));
  rep_md +=
      fmt::format("\n## Derived moduli\n\n| quantity | this run | dissertation |\n|---|---|---|\n"
                  "| E (eq. 6.47, pure polymer) | {:.3f} GPa | 0.162 GPa (Table 6.12) |\n"
                  "| E by inversion of C0 (E1) | {:.3f} GPa | -- |\n| nu12 | {:.3f} | -- |\n"
                  "| G12 | {:.3f} GPa | 0.109 GPa (C44, Table 6.11) |\n\n",
                  dm.E_eq647 * 1e-9, dm.E1 * 1e-9, dm.nu12, dm.G12 * 1e-9);
  rep_md += fmt::format("Solver: {} after {} iterations; {}\n\n", rep.termination, rep.iterations,
                        rep.converged ? "converged" : "NOT converged");
  rep_md += fmt::format("## Verdict: {}\n\n", verdict_name(card.verdict.level));
  for (const auto& reason : card.verdict.reasons)
    rep_md += "- " + reason + "\n";
  rep_md += card.verdict.level == VerdictLevel::not_usable
                ? "\nThis card is NOT USABLE: the fe_material plugin refuses it unless the host "
                  "allows unusable cards explicitly.\n\n"
                : "\n";
  if (!pngs.empty()) {
    rep_md += "## Plots\n\n";
    for (const auto& p : pngs)
      rep_md += fmt::format("![{0}]({0})\n", fs::relative(p, a.out).string());
  }
  rep_md += fmt::format(
      "\nWall time: build {:.1f} s, equilibration {:.1f} s (both summed over the replicas), "
      "phase check {:.1f} s, cases {:.1f} s (first start to last end), total {:.1f} s (first "
      "unit's start to the end of the fit).\n",
      md.seconds_build, md.seconds_equilibrate, md.seconds_phase, md.seconds_cases, total_s);
  return rep_md;
}

/// The key numbers on stderr and summary.json (what `--json` prints).
void print_and_summarize(const FitContext& ctx) {
  using namespace pnc::damage;
  [[maybe_unused]] const rve::Recipe& r = ctx.r;
  [[maybe_unused]] const rve::MdOutcome& md = ctx.md;
  [[maybe_unused]] const FitUnitArgs& a = ctx.a;
  [[maybe_unused]] const Card& card = ctx.f.card;
  [[maybe_unused]] const FitOptions& o = ctx.f.o;
  [[maybe_unused]] const StressStrainData& data = ctx.f.data;
  [[maybe_unused]] const FitReport& rep = ctx.f.rep;
  [[maybe_unused]] const rve::ReplicaFits& replica_fits = ctx.f.replica_fits;
  [[maybe_unused]] const rve::ReplicaTrend& trend = ctx.f.trend;
  [[maybe_unused]] const std::vector<std::string>& pngs = ctx.pngs;
  [[maybe_unused]] const DerivedModuli& dm = ctx.dm;
  [[maybe_unused]] const double total_s = ctx.total_s;
  [[maybe_unused]] const std::string& card_path = ctx.card_path;
  [[maybe_unused]] const std::string& command = ctx.command;
  [[maybe_unused]] const std::string& report_path = ctx.report_path;
  const auto& e = md.equilibrated;
  const nlohmann::json& clay_info = ctx.clay_info;
  std::cerr << constants_table(card) << fit_tables(card.fit, o.model) << verdict_text(card.verdict);
  std::cerr << fmt::format("pnc characterize: equilibrated density {:.4f} g/cm3, P {:.0f} atm, "
                           "void fraction {:.4f}; E (eq. 6.47) {:.3f} GPa\n",
                           e.density, e.pressure_total, e.void_fraction, dm.E_eq647 * 1e-9);
  if (md.phase.done)
    std::cerr << "pnc characterize: phase check: " << md.phase.phase
              << (md.phase.solid ? "" : " -- shear and damage constants held as not identified")
              << "\n";
  std::cerr << "  cases: " << md.cases_h5 << "\n  card: " << card_path
            << "\n  report: " << report_path << "\n";
  for (const auto& p : pngs)
    std::cerr << "  plot: " << p << "\n";
  std::cerr << fmt::format("  wall time {:.1f} s\n", total_s);
  {
    nlohmann::json j;
    j["command"] = "characterize";
    j["recipe"] = r.name;
    j["out"] = a.out;
    j["cases_h5"] = md.cases_h5;
    j["card"] = card_path;
    j["report"] = report_path;
    j["plots"] = pngs;
    j["equilibrated"] = {
        {"ensemble", r.system.enabled ? std::string("user stages") : r.equilibrate.ensemble},
        {"density_g_cm3", e.density},
        {"pressure_atm", e.pressure_total},
        {"pressure_stderr_atm", e.pressure_total_se},
        {"pressure_virial_atm", e.pressure_virial},
        {"temperature_K", e.temperature},
        {"void_fraction", e.void_fraction},
        {"min_distance_A", e.min_distance}};
    if (clay_info.is_object() && !clay_info.is_discarded()) j["clay"] = clay_info;
    if (md.phase.done) j["phase_check"] = rve::phase_json(md.phase);
    j["constants"] = constants_json(card);
    j["fit"] = fit_json(card.fit);
    j["verdict"] = verdict_json(card.verdict);
    j["statistics"] = rve::statistics_json(md.statistics); // error model, D130-D134
    j["moduli"] = {{"E_eq647_Pa", num(dm.E_eq647)}, {"E1_Pa", num(dm.E1)}, {"G12_Pa", num(dm.G12)}};
    j["seconds"] = {{"build", md.seconds_build},
                    {"equilibrate", md.seconds_equilibrate},
                    {"phase_check", md.seconds_phase},
                    {"cases", md.seconds_cases},
                    {"total", total_s}};
    // what `pnc characterize --json` prints, kept in the run folder (the fit is a unit)
    write_text_atomically(summary_path(a.out), j.dump() + "\n");
  }
}
} // namespace

std::string summary_path(const std::string& dir) {
  return (fs::path(dir) / "summary.json").string();
}

int run_fit_unit(const rve::Recipe& r, const rve::MdOutcome& md, const FitUnitArgs& a) {
  using namespace pnc::damage;
  std::cerr << "pnc characterize [fit] " << md.cases_h5 << "\n";
  FitContext c{r, md, a, fit_md(r, md), {}, {}, {}, {}, {}, 0, {}};
  const Card& card = c.f.card;
  const FitOptions& o = c.f.o;
  const StressStrainData& data = c.f.data;
  const FitReport& rep = c.f.rep;
  c.card_path = (fs::path(a.out) / "card.h5").string();
  c.command = fmt::format("pnc characterize {} --out {}", a.recipe, a.out);
  write_card(c.card_path, card, c.command);
  if (!a.no_plots)
    c.pngs = plot_fit(data, card.params, (fs::path(a.out) / "plots").string(),
                      fmt::format("MD ({}) and fitted NDM ({}) - card {}", r.name,
                                  model_name(o.model), verdict_name(card.verdict.level)));
  c.dm = derive_moduli(card.params);
  // the campaign's wall time: from the first unit's start to now (every unit of this run)
  c.total_s = rve::epoch_seconds() - md.started_s;
  const std::string rep_md = report_markdown(c);
  c.report_path = (fs::path(a.out) / "report.md").string();
  write_text_atomically(c.report_path, rep_md);
  print_and_summarize(c);
  if (card.verdict.level == VerdictLevel::not_usable) {
    std::cerr << "pnc: error: the card is NOT USABLE (reasons above); it was written, marked, "
                 "and the plugin refuses it unless the host allows unusable cards\n";
    return kExitNotUsable;
  }
  if (!rep.converged) {
    std::cerr << "pnc: error: the fit did not converge (" << rep.termination << "): " << rep.message
              << "; the card was written but check it before use\n";
    return 3;
  }
  return 0;
}

} // namespace pnc::app
