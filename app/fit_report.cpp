#include "fit_report.hpp"

#include "pnc/core/version.hpp"
#include "pnc/damage/moduli.hpp"
#include "pnc/damage/reference.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

namespace pnc::app {

namespace {

namespace fs = std::filesystem;
using html::Tone;

const char* kComp[6] = {"11", "22", "33", "23", "13", "12"};

std::string stress_label(int comp) {
  return std::string("σ") + kComp[comp];
}
std::string strain_label(int comp) {
  return (comp < 3 ? std::string("ε") : std::string("γ")) + kComp[comp];
}

/// The driven strain where the fit range ends in case `c` (midway between the last fitted row
/// and the first one beyond), NaN when every row is fitted.
double fit_limit(const damage::CaseCurve& c, int driven, double strain_max) {
  if (!(strain_max > 0)) return std::nan("");
  for (Eigen::Index k = 0; k < c.strain.rows(); ++k)
    if (c.strain.row(k).cwiseAbs().maxCoeff() > strain_max * (1 + 1e-12))
      return k == 0 ? c.strain(k, driven) : 0.5 * (c.strain(k - 1, driven) + c.strain(k, driven));
  return std::nan("");
}

std::string r2_note(double r2) {
  if (!std::isfinite(r2)) return "";
  if (r2 < 0) return "worse than the mean of the data";
  if (r2 < 0.9) return "poorly described (< 0.9)";
  return "";
}

/// R^2 as text: 4 significant digits, "> 0.9999" when it would round to 1.
std::string r2_text(double r2) {
  if (!std::isfinite(r2)) return "–";
  return r2 >= 0.99995 ? std::string("> 0.9999") : fmt::format("{:.4g}", r2);
}

std::string num(double v, const char* f = "{:.4g}") {
  return std::isfinite(v) ? fmt::format(fmt::runtime(f), v) : std::string("–");
}

} // namespace

std::string case_label(int case_id) {
  const std::string n = damage::deformation_case(case_id).name;
  return n.substr(0, n.find(" ("));
}

std::string seconds_text(double s) {
  if (s < 59.5) return fmt::format("{:.2g} s", s);
  const long long t = std::llround(s);
  return fmt::format("{} min {} s", t / 60, t % 60);
}

Figure fit_figure(const damage::StressStrainData& data, const damage::Card& card,
                  const std::string& png, const std::string& title) {
  Figure f;
  f.png = png;
  f.title = title;
  f.columns = 4;
  for (const auto& c : data.cases) {
    const auto& dc = damage::deformation_case(c.id);
    const int driven = damage::single_driven(dc, "the fit report"); // D360
    const auto at_data = damage::stress_path(card.params, c.strain);
    const int n = 200;
    // the load t of the last point: the model line runs along the case, also a negative one (D424)
    const double top = (damage::driven_sense(dc) * c.strain.col(driven)).maxCoeff();
    damage::PathMatrix path(n + 1, 6);
    for (int i = 0; i <= n; ++i)
      path.row(i) = damage::case_strain(c.id, top * i / n).transpose();
    const auto model = damage::stress_path(card.params, path);
    const bool errors = c.stress_stderr.rows() == c.stress.rows() && c.stress.rows() > 0;
    for (int comp : dc.active) {
      Panel p;
      double r2 = std::nan("");
      for (const auto& cf : card.fit.components)
        if (cf.case_id == c.id && cf.component == comp) r2 = cf.r2;
      p.title = fmt::format("case {} ({}): {}", c.id, case_label(c.id), stress_label(comp)) +
                (std::isfinite(r2) ? ", R² " + (r2 >= 0.99995 ? r2_text(r2) : "= " + r2_text(r2))
                                   : std::string());
      p.xlabel = strain_label(driven);
      p.ylabel = stress_label(comp) + " (MPa)";
      Series d{Series::Style::points, errors ? "data ± s.e." : "data", {}, {}, {}, 0, 0.0};
      Series m{Series::Style::line, "NDM fit", {}, {}, {}, 1, 0.0};
      p.residual.style = Series::Style::points;
      for (Eigen::Index k = 0; k < c.stress.rows(); ++k) {
        const double x = c.strain(k, driven), y = c.stress(k, comp) / 1e6;
        const double res = y - at_data(k, comp) / 1e6;
        d.x.push_back(x);
        d.y.push_back(y);
        p.residual.x.push_back(x);
        if (errors) {
          const double e = c.stress_stderr(k, comp) / 1e6;
          d.yerr.push_back(e);
          p.residual.y.push_back(e > 0 ? res / e : std::nan("")); // in units of its error
        } else {
          p.residual.y.push_back(res);
        }
      }
      for (int i = 0; i <= n; ++i) {
        m.x.push_back(path(i, driven));
        m.y.push_back(model(i, comp) / 1e6);
      }
      p.residual_label = errors ? "residual / s.e." : "residual (MPa)";
      p.fit_limit = fit_limit(c, driven, card.fit.strain_max);
      p.series = {d, m};
      f.panels.push_back(std::move(p));
    }
  }
  return f;
}

Tone verdict_tone(damage::VerdictLevel level) {
  switch (level) {
  case damage::VerdictLevel::usable:
    return Tone::good;
  case damage::VerdictLevel::usable_with_warnings:
    return Tone::warning;
  default:
    return Tone::bad;
  }
}

void add_verdict(html::Page& page, const damage::Verdict& v) {
  std::vector<std::pair<Tone, std::string>> reasons;
  for (const auto& r : v.reasons)
    reasons.emplace_back(r.rfind("not usable", 0) == 0 ? Tone::bad : Tone::warning, r);
  std::string level = std::string("Verdict: ") + damage::verdict_name(v.level);
  if (v.level == damage::VerdictLevel::not_usable)
    level += " (the card is written and marked; the plugin refuses it unless the host allows "
             "unusable cards)";
  page.verdict(level, verdict_tone(v.level), reasons);
}

std::vector<std::string> next_steps(const damage::Verdict& v, bool md) {
  const std::string range = md ? "`fit.strain_max` in the recipe" : "`--strain-max`";
  const std::string noise =
      md ? "more replicas (`\"run\": {\"replicas\": N}`, N >= 3) or longer holds "
           "(`deform.hold_steps`)"
         : "more points per curve, or curves averaged over replicas with their standard "
           "errors in the sd11_Pa..sd12_Pa columns";
  struct Rule {
    const char* key;
    std::string advice;
  };
  const std::vector<Rule> rules = {
      {"solver failed",
       "The solver failed: check the data for outliers (`--loss huber`) and start from a "
       "known card (`--prior`)."},
      {"solver stopped", "Raise the iteration limit (`--max-iterations`) or start from a known "
                         "card (`--prior`)."},
      {"worse than their mean",
       "A curve is described worse than by its mean: the stress change along it is below the "
       "noise, or the law does not follow it. Lower the noise with " +
           noise + ", or restrict the fit to the range the law describes with " + range + "."},
      {"poorly described", "A curve is poorly described (R² < 0.9): look at its residual panel; "
                           "a trend calls for a narrower fit range (" +
                               range + "), scatter for " + noise + "."},
      {"run in long stretches", "The residuals of a curve follow a trend the law misses: narrow "
                                "the fit range (" +
                                    range + ") or let alpha be fitted (`--fit-alpha`)."},
      {"misses a trend",
       "The replicas share a trend the law misses: narrow the fit range (" + range + ")."},
      {"chi^2/dof", "The scatter about the fit does not match the point errors: check the error "
                    "estimate and the fit range (" +
                        range + ")."},
      {"not defined by these data", "Some constants are not defined by these data: add the "
                                    "deformation cases that load them, or a solid RVE."},
      {"not identified", "A constant is not identified: add the cases that load it and strain "
                         "past the damage onset."},

      {"independent replica", "Run independent replicas (`\"run\": {\"replicas\": 3}` or more) "
                              "so that the errors include the structure-to-structure scatter."},
      {"no point errors", md ? "The data carry no errors (static 0 K rows): run at a finite "
                               "temperature with replicas to get them."
                             : "Give the data standard errors (columns sd11_Pa..sd12_Pa) so that "
                               "chi²/dof can be checked."},
      {"linear range", "Too few points in the linear range: more strain steps at small strain "
                       "(`deform.steps`, or a smaller `deform.strain_max`)."},
      {"the standard error exceeds",
       "A constant is not resolved to the required accuracy: " + noise + "."},
      {"the standard error is",
       "A constant is not resolved to the required accuracy: " + noise + "."},
      {"alpha is held", "Let alpha be fitted (`--fit-alpha`, or the automatic default)."},
      {"damage onset at the stretch", "Fit alpha instead of holding it (`--fit-alpha`)."},
      {"Young's modulus", "Check the units of the data (CSV stresses in MPa) and the stress sign "
                          "(tension positive)."},
      {"positive definite", "Check the units and sign of the data; C0 must be a stiffness."},
      {"Poisson ratio", "Check the lateral stresses of the extension cases (their sign and "
                        "reference)."},
      {"half the onset strain", "Check the stress sign (tension positive) and the reference "
                                "state of the data."},
  };
  std::vector<std::string> out;
  for (const auto& reason : v.reasons)
    for (const auto& rule : rules)
      if (reason.find(rule.key) != std::string::npos) {
        if (std::find(out.begin(), out.end(), rule.advice) == out.end()) out.push_back(rule.advice);
        break;
      }
  if (v.level == damage::VerdictLevel::usable)
    out.push_back("Nothing to fix: load the card in your solver (docs/plugin.md) or drive it "
                  "along a path first (`pnc material drive`, docs/drive.md).");
  else if (out.empty())
    out.push_back("Read the reasons above: each names the gate and the value that failed it.");
  return out;
}

void add_card_numbers(html::Page& page, const damage::Card& c) {
  using namespace pnc::damage;
  const auto& names = constant_names(c.params.model);
  html::Table t;
  t.caption = "Fitted constants (stiffness-like constants in GPa, alpha dimensionless); the "
              "standard error is the card's.";
  t.header = {"constant", "value", "± std. error", "units", "status"};
  t.numeric = {false, true, true, false, false};
  t.side_by_side = true;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const double s = names[i] == "alpha" ? 1.0 : 1e-9;
    const std::string status =
        i < c.status.size() ? c.status[i] : (c.fitted[i] ? "fitted" : "held");
    t.rows.push_back({names[i], fmt::format("{:.5g}", c.params.k[i] * s),
                      num(c.std_error[i] * s, "{:.2g}"), names[i] == "alpha" ? "1" : "GPa",
                      status + (c.note[i].empty() ? "" : ": " + c.note[i])});
  }
  page.table(t);
  if (c.fit.present) {
    html::Table q;
    q.caption = fmt::format(
        "Fit quality per curve (standard errors from {}){}{}", c.fit.error_model,
        std::isfinite(c.fit.chi2) && c.fit.dof > 0
            ? fmt::format("; chi²/dof = {:.3g} ({} dof)", c.fit.chi2 / c.fit.dof, c.fit.dof)
            : std::string(),
        !std::isnan(c.fit.shape_error) // D417
            ? fmt::format("; the law's shape error (trend common to the replicas, 97.5 % bound): "
                          "≤ {:.3g} % of a curve's stress",
                          100 * c.fit.shape_error)
            : std::string());
    q.header = {"case", "component", "points", "R²", "rms (MPa)", "runs-test p", "note"};
    q.numeric = {true, false, true, true, true, true, false};
    q.side_by_side = true;
    for (const auto& f : c.fit.components)
      q.rows.push_back({std::to_string(f.case_id), stress_label(f.component),
                        std::to_string(f.points), r2_text(f.r2), num(f.rms / 1e6, "{:.3g}"),
                        num(f.runs_p, "{:.2g}"), r2_note(f.r2)});
    page.table(q);
  }
  const DerivedModuli d = derive_moduli(c.params);
  html::Table m;
  m.caption = "Derived moduli of C0, both readings: compliance inversion (the orthotropic "
              "moduli) and the printed formula (docs/theory.md §1.5)";
  m.header = {"modulus", "GPa", "reading"};
  m.numeric = {false, true, false};
  m.side_by_side = true;
  m.rows = {{"E1", num(d.E1 / 1e9), "inversion"},   {"E2", num(d.E2 / 1e9), "inversion"},
            {"E3", num(d.E3 / 1e9), "inversion"},   {"G23", num(d.G23 / 1e9), "inversion"},
            {"G13", num(d.G13 / 1e9), "inversion"}, {"G12", num(d.G12 / 1e9), "inversion"}};
  if (c.params.model == Model::pnc)
    m.rows.push_back({"E2 (printed formula)", num(d.E2_as_printed / 1e9),
                      "printed formula (labelled E2; equals E1)"});
  else
    m.rows.push_back({"E (isotropic formula)", num(d.E_isotropic_formula / 1e9),
                      "isotropic formula (C11, C12)"});
  m.rows.push_back({"ν12, ν13, ν23", fmt::format("{:.3g}, {:.3g}, {:.3g}", d.nu12, d.nu13, d.nu23),
                    "inversion (dimensionless)"});
  page.table(m);
  html::Table s;
  s.caption = "Strength of each case: first local maximum of the driven stress along the case "
              "path (strain ≤ 1)";
  s.header = {"case", "stress", "peak (MPa)", "at strain"};
  s.numeric = {false, false, true, true};
  s.side_by_side = true;
  for (int id : model_cases(c.params.model)) {
    const CaseStrength cs = case_strength(c.params, id, 1.0);
    s.rows.push_back({fmt::format("{} ({})", id, case_label(id)), stress_label(cs.component),
                      cs.peak ? num(*cs.peak / 1e6) : "no peak (monotonic)",
                      cs.peak ? num(cs.strain_at_peak) : "–"});
  }
  page.table(s);
}

void add_warnings(html::Page& page, const damage::Verdict& v, const std::string& solver,
                  const std::string& figures) {
  page.section("Warnings");
  std::vector<std::string> warns;
  if (!solver.empty()) warns.push_back("solver: " + solver);
  if (!figures.empty()) warns.push_back("figures: " + figures);
  if (!warns.empty()) page.list(warns, Tone::warning);
  if (!v.reasons.empty())
    page.paragraph(fmt::format("The verdict's {} finding{} are listed at the top of the page.",
                               v.reasons.size(), v.reasons.size() == 1 ? "" : "s"));
  else if (warns.empty())
    page.paragraph("None.");
}

std::string write_fit_report(const FitRun& run, const damage::StressStrainData& data,
                             const damage::Card& card) {
  const fs::path card_path(run.card);
  const std::string stem = fs::path(card_path).replace_extension("").string();
  const std::string html_path = stem + "_report.html", md_path = stem + "_report.md";
  const fs::path base = card_path.parent_path();
  html::Page page("pnc fit: " + card_path.filename().string());
  add_verdict(page, card.verdict);
  page.section("What was run");
  page.facts({{"command", "`" + run.command_line + "`"},
              {"input", fmt::format("`{}` ({} cases, {} points; data hash {})", run.data,
                                    data.cases.size(), data.points(), card.fit.data_hash)},
              {"stress definition", data.stress_definition},
              {"model", std::string("NDM, ") + damage::model_name(card.params.model)},
              {"card", "`" + run.card + "`"},
              {"software", version_string()},
              {"finished", utc_timestamp()},
              {"wall time",
               seconds_text(run.seconds) +
                   (run.plots.seconds > 0
                        ? fmt::format(" (of which plotting {})", seconds_text(run.plots.seconds))
                        : std::string())},
              {"solver",
               fmt::format("{} after {} iterations", card.fit.termination, card.fit.iterations)}});
  page.section("What to do next");
  page.list(next_steps(card.verdict, false));
  page.section("Figures");
  if (run.plots_dir.empty())
    page.paragraph("Figures not drawn (--no-plots).");
  else if (!run.plots.warning.empty())
    page.paragraph("Figures not drawn: " + run.plots.warning, Tone::warning);
  for (const auto& png : run.plots.pngs)
    page.figure(png,
                "Data (points, ± their standard errors when stored) and the fitted NDM (line) "
                "per case and stress component; under each, the residuals; the grey band is "
                "outside the fit range.",
                fs::relative(png, base.empty() ? fs::path(".") : base).string());
  page.section("Key numbers");
  add_card_numbers(page, card);
  add_warnings(page, card.verdict, card.fit.warnings, run.plots.warning);
  page.write(html_path, md_path);
  return html_path;
}

} // namespace pnc::app
