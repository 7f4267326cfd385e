#include "characterize_report.hpp"

#include "fit_report.hpp"
#include "report.hpp"

#include "pnc/core/html_page.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"
#include "pnc/damage/moduli.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/rve/phase_check.hpp"
#include "pnc/rve/user_system.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

namespace pnc::app {

namespace {

namespace fs = std::filesystem;
using html::Tone;

const char* kComp[6] = {"11", "22", "33", "23", "13", "12"};

std::string code_block(const std::string& s) {
  return "```\n" + s + "```\n";
}

/// Mean and standard error over replicas of one value (sd / sqrt(N)); N = 1: the value, NaN.
std::pair<double, double> mean_se(const std::vector<double>& v) {
  double m = 0;
  for (double x : v)
    m += x;
  m /= static_cast<double>(v.size());
  if (v.size() < 2) return {m, std::nan("")};
  double ss = 0;
  for (double x : v)
    ss += (x - m) * (x - m);
  return {m, std::sqrt(ss / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()))};
}

bool all_positive(const std::vector<double>& v) {
  for (double x : v)
    if (!(x > 0)) return false;
  return !v.empty();
}

/// One panel per component set: the six stress components of a case against its driven strain.
Panel components_panel(const std::string& title, const std::string& xlabel) {
  Panel p;
  p.title = title;
  p.xlabel = xlabel;
  p.ylabel = "stress (MPa)";
  for (int j = 0; j < 6; ++j)
    p.series.push_back(
        {Series::Style::line_points, std::string("σ") + kComp[j], {}, {}, {}, j, 0.8});
  return p;
}

void drop_empty_errors(Panel& p) {
  for (auto& s : p.series)
    if (!all_positive(s.yerr)) s.yerr.clear();
}

/// senses.png (D428): per shear run both ways, the two senses along the case and their paired
/// difference, over the fitted rows; no panel when the run has no such pair.
Figure senses_figure(const rve::Recipe& r, const rve::MdOutcome& md,
                     const std::vector<rve::SensePair>& senses, const std::string& plots_dir) {
  Figure f;
  f.png = (fs::path(plots_dir) / "senses.png").string();
  f.title = fmt::format("Both senses of each shear ({}, {} replica{})", r.name,
                        md.statistics.replicas, md.statistics.replicas == 1 ? "" : "s");
  for (const auto& s : senses) {
    Panel p;
    p.title = fmt::format("{} and case {}", case_label(s.positive_id), s.negative_id);
    p.xlabel = std::string("|γ") + kComp[s.voigt] + "|";
    p.ylabel = std::string("σ") + kComp[s.voigt] + " along the case (MPa)";
    Series pos{
        Series::Style::line_points, fmt::format("+γ (case {})", s.positive_id), {}, {}, {}, 0, 0.8};
    Series neg{Series::Style::line_points,
               fmt::format("−γ (case {}), sign turned", s.negative_id),
               {},
               {},
               {},
               1,
               0.8};
    Series diff{Series::Style::line_points, "difference (+γ − −γ)", {}, {}, {}, 2, 1.5};
    for (std::size_t k = 0; k < s.t.size(); ++k) {
      for (Series* x : {&pos, &neg, &diff})
        x->x.push_back(s.t[k]);
      pos.y.push_back(s.positive[k] / 1e6);
      pos.yerr.push_back(s.positive_se[k] / 1e6);
      neg.y.push_back(s.negative[k] / 1e6);
      neg.yerr.push_back(s.negative_se[k] / 1e6);
      diff.y.push_back(s.difference[k] / 1e6);
      diff.yerr.push_back(s.difference_se[k] / 1e6);
    }
    p.series = {pos, neg, diff};
    drop_empty_errors(p);
    f.panels.push_back(std::move(p));
  }
  f.columns = std::min<int>(3, static_cast<int>(f.panels.size()));
  return f;
}

/// The report.md body as before the HTML page: RVE, equilibration, phase check, deformation,
/// statistics, constants, replica fits, fit quality, derived moduli, solver, wall time.
std::string details_markdown(const CharacterizeRun& c) {
  using namespace pnc::damage;
  const auto& r = c.recipe;
  const auto& md = c.md;
  const auto& data = c.data;
  const auto& card = c.card;
  const auto& rep = c.rep;
  const auto& replica_fits = c.replica_fits;
  const auto& trend = c.trend;
  const DerivedModuli dm = derive_moduli(card.params);
  const double total_s = c.seconds;
  const auto& e = md.equilibrated;
  std::string rep_md;
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
                          "force field of docs/theory.md §3.1 (decision D13 units).\n\n",
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
  const nlohmann::json& clay_info = c.clay_info; // read_clay_info
  if (r.model == "pnc") {
    const auto cp = fs::path(md.build_record).parent_path() / "clay.json";
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
          fs::relative(cp, c.out).string());
    else
      rep_md += fmt::format("Clay record {} is missing or unreadable.\n\n", cp.string());
  }
  rep_md += "Equilibration (one line per stage, with the criterion that ended it):\n\n";
  for (const auto& line : e.criteria)
    rep_md += "- " + line + "\n";
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
  rep_md += rve::replica_bootstrap_markdown(c.bootstrap); // D431: empty with < 2 replicas
  rep_md += rve::replica_trend_markdown(trend, c.max_shape_error);
  rep_md += rve::sense_pairs_markdown(c.senses); // D428
  rep_md += "\n## Fit quality and the dissertation's tables\n\n" +
            code_block(fit_tables(card.fit, c.model));
  rep_md +=
      fmt::format("\n## Derived moduli\n\n| quantity | this run | dissertation |\n|---|---|---|\n"
                  "| E (isotropic formula, pure polymer; docs/theory.md §1.5) | {:.3f} GPa | 0.162 "
                  "GPa (published table) |\n"
                  "| E by inversion of C0 (E1) | {:.3f} GPa | -- |\n| nu12 | {:.3f} | -- |\n"
                  "| G12 | {:.3f} GPa | 0.109 GPa (C44, Table 6.11) |\n\n",
                  dm.E_isotropic_formula * 1e-9, dm.E1 * 1e-9, dm.nu12, dm.G12 * 1e-9);
  rep_md += fmt::format("Solver: {} after {} iterations; {}\n\n", rep.termination, rep.iterations,
                        rep.converged ? "converged" : "NOT converged");
  rep_md += fmt::format(
      "\nWall time: build {:.1f} s, equilibration {:.1f} s, phase check {:.1f} s, "
      "cases {:.1f} s, total {:.1f} s (this invocation).\n",
      md.seconds_build, md.seconds_equilibrate, md.seconds_phase, md.seconds_cases, total_s);
  return rep_md;
}

} // namespace

nlohmann::json read_clay_info(const rve::Recipe& r, const rve::MdOutcome& md) {
  nlohmann::json clay; // what the builder wrote (clay.json next to build.h5), model pnc
  if (r.model != "pnc") return clay;
  std::ifstream cf(fs::path(md.build_record).parent_path() / "clay.json");
  if (cf) clay = nlohmann::json::parse(cf, nullptr, false);
  return clay.is_discarded() ? nlohmann::json() : clay;
}

std::vector<Figure> characterize_figures(const rve::Recipe& r, const rve::MdOutcome& md,
                                         const damage::StressStrainData& data,
                                         const damage::Card& card,
                                         const std::vector<rve::SensePair>& senses,
                                         const std::string& plots_dir) {
  std::vector<Figure> figs;
  figs.push_back(fit_figure(data, card, (fs::path(plots_dir) / "fit.png").string(),
                            fmt::format("MD data ({}) and the fitted NDM: card {}", r.name,
                                        damage::verdict_name(card.verdict.level))));
  const rve::CombinedCases& st = md.statistics;
  const bool subtract = r.reference == "subtract";
  const int nrep = st.replicas;
  Figure f;
  f.png = (fs::path(plots_dir) / "stress.png").string();
  f.title = fmt::format("MD stress of every case ({}; {} replica{}, error bars: standard errors)",
                        r.name, nrep, nrep == 1 ? "" : "s");
  f.columns = subtract ? 4 : 3;
  for (const auto& cc : st.cases) {
    const std::string xl = (cc.voigt < 3 ? "ε" : "γ") + std::string(kComp[cc.voigt]);
    Panel raw = components_panel(fmt::format("case {} ({}): {}", cc.id, case_label(cc.id),
                                             subtract ? "as measured" : "as fitted"),
                                 xl);
    Panel rel = components_panel(fmt::format("case {}: minus the reference (fitted)", cc.id), xl);
    // the driven component drawn heavier
    raw.series[static_cast<std::size_t>(cc.voigt)].width = 2.0;
    rel.series[static_cast<std::size_t>(cc.voigt)].width = 2.0;
    for (int j = 0; j < 6; ++j) {
      Series& s = raw.series[static_cast<std::size_t>(j)];
      if (subtract) { // zero strain: the reference state of the replicas
        std::vector<double> refs;
        for (const auto& ref : st.reference)
          refs.push_back(ref[j]);
        const auto [m, se] = mean_se(refs);
        s.x.push_back(0.0);
        s.y.push_back(m / 1e6);
        s.yerr.push_back((nrep >= 2 ? se : st.reference_se[0][j]) / 1e6);
      }
      for (Eigen::Index k = 0; k < cc.strain.rows(); ++k) {
        s.x.push_back(cc.strain(k, cc.voigt));
        if (!subtract) {
          s.y.push_back(cc.stress(k, j) / 1e6);
          s.yerr.push_back(cc.stress_stderr(k, j) / 1e6);
          continue;
        }
        std::vector<double> v;
        for (int rep = 0; rep < nrep; ++rep)
          v.push_back(cc.replica_stress[rep](k, j) + st.reference[rep][j]);
        const auto [m, se] = mean_se(v);
        s.y.push_back(m / 1e6);
        // one replica: the hold's own block error, without the reference's (D131)
        const double e1 = cc.replica_stderr[0](k, j), r1 = st.reference_se[0][j];
        s.yerr.push_back((nrep >= 2 ? se : std::sqrt(std::max(0.0, e1 * e1 - r1 * r1))) / 1e6);
        Series& t = rel.series[static_cast<std::size_t>(j)];
        t.x.push_back(cc.strain(k, cc.voigt));
        t.y.push_back(cc.stress(k, j) / 1e6);
        t.yerr.push_back(cc.stress_stderr(k, j) / 1e6);
      }
    }
    drop_empty_errors(raw);
    drop_empty_errors(rel);
    f.panels.push_back(std::move(raw));
    if (subtract) f.panels.push_back(std::move(rel));
  }
  if (!f.panels.empty()) figs.push_back(std::move(f));
  if (Figure both = senses_figure(r, md, senses, plots_dir); !both.panels.empty())
    figs.push_back(std::move(both));
  return figs;
}

std::string write_characterize_report(const CharacterizeRun& c) {
  const auto& md = c.md;
  const auto& e = md.equilibrated;
  const auto& r = c.recipe;
  html::Page page("pnc characterize: recipe `" + r.name + "`");
  add_verdict(page, c.card.verdict);
  page.section("What was run");
  std::string cases;
  for (int id : r.cases)
    cases += (cases.empty() ? "" : ", ") + std::to_string(id);
  page.facts(
      {{"command", "`" + c.command + "`"},
       {"recipe",
        "`" + r.name + "` (as run: `" + fs::relative(md.recipe_path, c.out).string() + "`)"},
       {"run folder", "`" + c.out + "`"},
       {"deformation cases", cases},
       {"replicas",
        fmt::format("{} (error bars: {}){}", md.statistics.replicas, md.statistics.error_method,
                    md.replica_history.empty() ? std::string()
                                               : "; " + md.replica_history + " (D418)")},
       {"model fitted", std::string("NDM, ") + damage::model_name(c.model)},
       {"software", version_string()},
       {"finished", utc_timestamp()},
       {"wall time", fmt::format("{} (build {}, equilibration {}, phase check {}, cases {}{})",
                                 seconds_text(c.seconds), seconds_text(md.seconds_build),
                                 seconds_text(md.seconds_equilibrate),
                                 seconds_text(md.seconds_phase), seconds_text(md.seconds_cases),
                                 c.plots.seconds > 0 ? ", plotting " + seconds_text(c.plots.seconds)
                                                     : std::string())}});
  page.section("What to do next");
  std::vector<std::string> next;
  if (md.phase.done && !md.phase.solid)
    next.push_back("The phase check finds that the RVE relaxes within a hold: its shear and "
                   "damage constants are not defined. A solid on the hold time scale (a glass: "
                   "a lower temperature, or a glassy model such as `demo_glass`) is needed "
                   "(docs/rve.md).");
  for (const auto& s : next_steps(c.card.verdict, true))
    next.push_back(s);
  page.list(next);
  page.section("Figures");
  if (!c.plots_requested)
    page.paragraph("Figures not drawn (--no-plots).");
  else if (!c.plots.warning.empty())
    page.paragraph("Figures not drawn: " + c.plots.warning, Tone::warning);
  for (const auto& png : c.plots.pngs) {
    const bool fit = fs::path(png).filename() == "fit.png";
    page.figure(png,
                fit ? "The fit: MD data (points ± their standard errors) and the fitted NDM "
                      "(line) per case and fitted component; under each, the residuals (in units "
                      "of the point's standard error when the data have errors, else MPa); the "
                      "grey band is outside the fit range."
                    : "MD stress of every case, all six components: as measured (the point at "
                      "zero strain is the reference state) and relative to the reference (the "
                      "data fitted); error bars are standard errors.",
                fs::relative(png, c.out).string());
  }
  page.section("Key numbers");
  page.table(
      {{"equilibrated RVE", "value"},
       {{"density", fmt::format("{:.4f} g/cm³", e.density)},
        {"pressure (with kinetic term)",
         fmt::format("{:.0f} ± {:.0f} atm", e.pressure_total, e.pressure_total_se)},
        {"temperature", fmt::format("{:.1f} K", e.temperature)},
        {"void fraction", std::isfinite(e.void_fraction) ? fmt::format("{:.4f}", e.void_fraction)
                                                         : std::string("not measured")}},
       {false, true},
       "",
       true});
  if (md.phase.done)
    page.paragraph(fmt::format("Phase check: {}; shear modulus over a hold G_hold = {:.3g} ± "
                               "{:.2g} GPa, bulk modulus K = {:.3g} ± {:.2g} GPa.",
                               md.phase.phase, md.phase.G_hold_Pa * 1e-9,
                               md.phase.G_hold_se_Pa * 1e-9, md.phase.K_Pa * 1e-9,
                               md.phase.K_se_Pa * 1e-9));
  add_card_numbers(page, c.card);
  add_warnings(page, c.card.verdict, c.rep.warnings, c.plots.warning);
  page.markdown(details_markdown(c), c.out);
  const std::string md_path = (fs::path(c.out) / "report.md").string();
  page.write((fs::path(c.out) / "report.html").string(), md_path);
  return md_path;
}

namespace {
/// The clay block of the JSON (build/clay.json, which stays in A and g/mol) in SI (D284).
nlohmann::json clay_si_json(const nlohmann::json& clay) {
  static const std::map<std::string, std::pair<std::string, double>> si = {
      {"clay_mass_g_mol", {"clay_mass_kg_per_mol", 1e-3}},
      {"polymer_mass_g_mol", {"polymer_mass_kg_per_mol", 1e-3}},
      {"platelet_length_A", {"platelet_length_m", units::m_per_angstrom}},
      {"platelet_width_A", {"platelet_width_m", units::m_per_angstrom}},
      {"platelet_thickness_A", {"platelet_thickness_m", units::m_per_angstrom}},
      {"clay_bounding_volume_A3", {"clay_bounding_volume_m3", units::m3_per_angstrom3}},
      {"box_volume_A3", {"box_volume_m3", units::m3_per_angstrom3}},
      {"min_polymer_clay_distance_A", {"min_polymer_clay_distance_m", units::m_per_angstrom}}};
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [k, v] : clay.items()) {
    const auto it = si.find(k);
    if (it == si.end())
      out[k] = v;
    else
      out[it->second.first] =
          v.is_number() ? nlohmann::json(v.get<double>() * it->second.second) : v;
  }
  return out;
}
} // namespace

nlohmann::json characterize_json(const CharacterizeRun& c, const std::string& card_path,
                                 const std::string& report_path, const std::string& html_path) {
  const auto& r = c.recipe;
  const auto& md = c.md;
  const auto& card = c.card;
  const auto& e = md.equilibrated;
  const damage::DerivedModuli dm = damage::derive_moduli(card.params);
  nlohmann::json j;
  j["command"] = "characterize";
  j["recipe"] = r.name;
  j["out"] = c.out;
  j["cases_h5"] = md.cases_h5;
  j["card"] = card_path;
  j["report"] = report_path;
  j["report_html"] = html_path;
  if (!c.plots.warning.empty()) j["plot_warning"] = c.plots.warning;
  j["plots"] = c.plots.pngs;
  // SI keys (D238, D284); the text output, the report and the files keep g/cm^3, atm and A
  j["equilibrated"] = {
      {"ensemble", r.system.enabled ? std::string("user stages") : r.equilibrate.ensemble},
      {"density_kg_per_m3", e.density * 1000.0},
      {"pressure_Pa", e.pressure_total * units::pa_per_atm},
      {"pressure_stderr_Pa", e.pressure_total_se * units::pa_per_atm},
      {"pressure_virial_Pa", e.pressure_virial * units::pa_per_atm},
      {"temperature_K", e.temperature},
      {"void_fraction", e.void_fraction},
      {"min_distance_m", e.min_distance * units::m_per_angstrom}};
  if (c.clay_info.is_object()) j["clay"] = clay_si_json(c.clay_info);
  if (md.phase.done) j["phase_check"] = rve::phase_json(md.phase);
  j["constants"] = constants_json(card);
  j["fit"] = fit_json(card.fit);
  j["verdict"] = verdict_json(card.verdict);
  j["statistics"] = rve::statistics_json(md.statistics); // error model, D130-D134
  if (!md.replica_history.empty()) j["statistics"]["replica_history"] = md.replica_history; // D418
  if (c.bootstrap.shown()) j["statistics"]["bootstrap"] = rve::replica_bootstrap_json(c.bootstrap);
  if (!c.senses.empty()) j["statistics"]["sense_pairs"] = rve::sense_pairs_json(c.senses); // D428
  j["moduli"] = {{"E_isotropic_formula_Pa", num(dm.E_isotropic_formula)},
                 {"E1_Pa", num(dm.E1)},
                 {"G12_Pa", num(dm.G12)}};
  j["wall_s"] = {{"build", md.seconds_build},
                 {"equilibrate", md.seconds_equilibrate},
                 {"phase_check", md.seconds_phase},
                 {"cases", md.seconds_cases},
                 {"total", c.seconds}};
  return j;
}

void print_characterize_summary(const CharacterizeRun& c, const std::string& card_path,
                                const std::string& report_path, const std::string& html_path) {
  const auto& card = c.card;
  const auto& md = c.md;
  const auto& e = md.equilibrated;
  const damage::DerivedModuli dm = damage::derive_moduli(card.params);
  std::cerr << constants_table(card) << fit_tables(card.fit, c.model) << verdict_text(card.verdict);
  std::cerr << fmt::format("pnc characterize: equilibrated density {:.4f} g/cm3, P {:.0f} atm, "
                           "void fraction {:.4f}; E (isotropic formula) {:.3f} GPa\n",
                           e.density, e.pressure_total, e.void_fraction,
                           dm.E_isotropic_formula * 1e-9);
  if (md.phase.done)
    std::cerr << "pnc characterize: phase check: " << md.phase.phase
              << (md.phase.solid ? "" : " -- shear and damage constants held as not identified")
              << "\n";
  std::cerr << rve::replica_bootstrap_summary(c.bootstrap); // D431: empty with < 2 replicas
  std::cerr << rve::sense_pairs_summary(c.senses);          // D428
  std::cerr << "  cases: " << md.cases_h5 << "\n  card: " << card_path
            << "\n  report: " << html_path << " (and " << report_path << ")\n";
  for (const auto& p : c.plots.pngs)
    std::cerr << "  plot: " << p << "\n";
  std::cerr << fmt::format("  wall time {:.1f} s\n", c.seconds);
}

} // namespace pnc::app
