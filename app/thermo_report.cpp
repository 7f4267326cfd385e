#include "thermo_report.hpp"

#include "fit_report.hpp" // seconds_text

#include "pnc/core/html_page.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <utility>

namespace pnc::app {

namespace {
namespace fs = std::filesystem;
using html::Tone;

const char* kLevel[3] = {"noise", "weak (below 2 s.e.)", "resolved"};

std::string pm(double v, double se, const char* f = "{:.4g}") {
  if (!std::isfinite(v)) return "—";
  return fmt::format(fmt::runtime(f), v) + " ± " + fmt::format("{:.2g}", se);
}

/// "What was run": command, output, software, time.
void add_run(html::Page& page, const ThermoRun& run,
             std::vector<std::pair<std::string, std::string>> extra) {
  page.section("What was run");
  std::vector<std::pair<std::string, std::string>> rows = {
      {"command", "`" + run.command_line + "`"}, {"output folder", "`" + run.out + "`"}};
  rows.insert(rows.end(), extra.begin(), extra.end());
  rows.push_back({"results", "`" + run.h5 + "`"});
  rows.push_back({"software", version_string()});
  rows.push_back({"finished", utc_timestamp()});
  rows.push_back({"wall time", seconds_text(run.seconds)});
  page.facts(rows);
}

void add_figures(html::Page& page, const ThermoRun& run,
                 const std::vector<std::pair<std::string, std::string>>& captions) {
  page.section("Figures");
  if (!run.plots) {
    page.paragraph("Not drawn (--no-plots).");
    return;
  }
  if (run.pngs.empty()) {
    page.paragraph("Not drawn: " + run.plot_warning, Tone::warning);
    return;
  }
  for (const auto& png : run.pngs) {
    std::string caption = fs::path(png).filename().string();
    for (const auto& [name, text] : captions)
      if (fs::path(png).filename() == name) caption = text;
    page.figure(png, caption, fs::relative(png, run.out).string());
  }
}

void add_warnings(html::Page& page, const ThermoRun& run) {
  std::vector<std::string> w = run.notes;
  if (!run.plot_warning.empty()) w.push_back("plotting: " + run.plot_warning);
  page.warnings(w);
}

Tone tone_of(int level) {
  return level == 2 ? Tone::good : level == 1 ? Tone::warning : Tone::bad;
}

/// Delta A of the reference (zero-strain) state and its standard error, kcal/mol; NaN and 0
/// when the run has no reference state.
std::pair<double, double> reference_dA(const thermo::TiResult& r) {
  for (const auto& st : r.states)
    if (st.state.kind == "ref") return {st.ti.dA.value, st.ti.dA.se};
  return {std::nan(""), 0.0};
}
} // namespace

int resolution(double value, double se) {
  if (!std::isfinite(value) || !std::isfinite(se)) return 0;
  const double a = std::fabs(value);
  return a > 2 * se ? 2 : a > se ? 1 : 0;
}

std::string write_ti_report(const ThermoRun& run, const thermo::TiSpec& spec,
                            const thermo::TiResult& r, double worst_fd) {
  html::Page page("pnc thermo ti: " + run.out);
  const auto [a0, s0] = reference_dA(r);
  // the verdict: the free energy of deformation, Delta A(state) - Delta A(ref), against its error
  std::vector<std::pair<Tone, std::string>> reasons;
  int worst = 2, deformed = 0;
  for (const auto& st : r.states) {
    if (st.state.kind == "ref" || !std::isfinite(a0)) continue;
    ++deformed;
    const double d = st.ti.dA.value - a0, se = std::hypot(st.ti.dA.se, s0);
    const int lv = resolution(d, se);
    worst = std::min(worst, lv);
    if (lv < 2)
      reasons.push_back({tone_of(lv), fmt::format("state {}: ΔA − ΔA(ref) = {} kcal/mol is {}",
                                                  st.state.id, pm(d, se), kLevel[lv])});
  }
  for (const auto& f : r.fits)
    if (std::isfinite(f.modulus) && resolution(f.modulus, f.modulus_se) < 2)
      reasons.push_back(
          {tone_of(resolution(f.modulus, f.modulus_se)),
           fmt::format("{} modulus {} GPa is {}", f.kind, pm(f.modulus * 1e-9, f.modulus_se * 1e-9),
                       kLevel[resolution(f.modulus, f.modulus_se)])});
  if (deformed == 0)
    page.verdict("Computed: no deformed state relative to a reference", Tone::neutral, reasons);
  else if (worst == 2)
    page.verdict("Resolved: every free energy of deformation exceeds twice its standard error",
                 reasons.empty() ? Tone::good : Tone::warning, reasons);
  else
    page.verdict(worst == 0 ? "Noise: an error bar reaches the value it belongs to"
                            : "Weak: a free energy of deformation is below twice its error",
                 tone_of(worst), reasons);
  add_run(page, run,
          {{"quadrature", fmt::format("{} rule, {} λ point(s)", spec.rule, spec.points)},
           {"sampling",
            fmt::format("{} + {} steps of {} fs per point, dH/dλ every {} steps "
                        "({}), {} blocks, T = {} K",
                        spec.sampling.equil_steps, spec.sampling.prod_steps,
                        spec.sampling.timestep_fs, spec.sampling.sample_every, spec.dhdl_method,
                        spec.sampling.blocks, spec.sampling.temperature)}});
  page.section("What to do next");
  std::vector<std::string> next;
  if (worst < 2 || !reasons.empty())
    next.push_back("Longer production (`--prod-steps`), more blocks or larger strains (`--vol`, "
                   "`--dev`) shrink the error bars relative to the differences (a new `--out` "
                   "folder: one folder keeps one protocol).");
  next.push_back("The free energy of deformation and the stress work of `pnc characterize` "
                 "cases can be compared with `pnc thermo work` (docs/theory.md section 4).");
  page.list(next);
  page.section("Key numbers");
  html::Table t;
  t.caption = "ΔA = A(λ=1) − A(λ=0) per deformation state (kcal/mol, ± 1 standard error)";
  t.header = {"state",       "kind",          "strain parameter",
              "volume (Å³)", "ΔA (kcal/mol)", "ΔA − ΔA(ref) (kcal/mol)",
              "resolution"};
  t.numeric = {false, false, true, true, true, true, false};
  for (const auto& st : r.states) {
    const bool ref = st.state.kind == "ref";
    const double d = st.ti.dA.value - a0, se = std::hypot(st.ti.dA.se, s0);
    t.rows.push_back({st.state.id, st.state.kind, fmt::format("{:.6g}", st.state.strain),
                      fmt::format("{:.6g}", st.volume), pm(st.ti.dA.value, st.ti.dA.se),
                      ref ? "0" : pm(d, se), ref ? "" : kLevel[resolution(d, se)]});
  }
  page.table(t);
  html::Table m;
  m.caption = "Response of ΔA to the strain (quadratic fit, D65)";
  m.header = {"kind", "modulus (GPa)", "V0 (Å³)"};
  m.numeric = {false, true, true};
  for (const auto& f : r.fits)
    if (std::isfinite(f.modulus))
      m.rows.push_back({f.kind == "vol" ? "bulk modulus K (vol)" : "shear modulus μ (dev)",
                        pm(f.modulus * 1e-9, f.modulus_se * 1e-9), fmt::format("{:.6g}", f.v0)});
  if (!m.rows.empty())
    page.table(m);
  else
    page.paragraph("No modulus: the quadratic fit of ΔA needs at least three strains of a kind.");
  page.facts(
      {{"kT", fmt::format("{:.6g} kcal/mol", units::kB_kcal_mol_K * spec.sampling.temperature)},
       {"finite-difference check of dH/dλ (largest relative difference to LAMMPS)",
        fmt::format("{:.2e}", worst_fd)}});
  add_figures(page, run,
              {{"dhdl_vs_lambda.png", "The TI integrand ⟨dH/dλ⟩ (kcal/mol) per state against λ; "
                                      "error bars 1 standard error."},
               {"dA_vs_strain.png", "ΔA (kcal/mol) against the volumetric and deviatoric strain; "
                                    "error bars 1 standard error."}});
  add_warnings(page, run);
  return page.write_report(run.out);
}

std::string write_persistence_report(const ThermoRun& run, const thermo::PersistenceSpec& spec,
                                     const thermo::PersistenceResult& r) {
  html::Page page("pnc thermo persistence: " + run.out);
  const double si = units::j_m_per_kcal_mol_A;
  // the 95 % half-width is the error bar here (D270)
  const int lv = r.ei0.value > 0 ? resolution(r.ei0.value, r.ei0_ci95) : 0;
  std::vector<std::pair<Tone, std::string>> reasons;
  if (!(r.ei0.value > 0))
    reasons.push_back({Tone::bad, fmt::format("EI(0) = {} kcal/mol Å is not positive",
                                              pm(r.ei0.value, r.ei0_ci95))});
  else if (lv < 2)
    reasons.push_back({tone_of(lv), fmt::format("EI(0) = {} kcal/mol Å (95 % interval) is {}",
                                                pm(r.ei0.value, r.ei0_ci95), kLevel[lv])});
  if (lv == 2)
    page.verdict("Resolved: EI(0) exceeds twice its 95 % interval", Tone::good, reasons);
  else
    page.verdict(lv == 0 ? "Noise: the 95 % interval of EI(0) reaches its value"
                         : "Weak: EI(0) is below twice its 95 % interval",
                 tone_of(lv), reasons);
  add_run(page, run,
          {{"chain", fmt::format("{}, {} beads, length {:.4g} Å, supports {}", spec.chain,
                                 spec.beads, r.length, spec.supports)},
           {"pulling", fmt::format("spring {} kcal/mol/Å², {} rate(s), {} Å at {} fs steps, "
                                   "T = {} K",
                                   spec.spring_k, spec.rates.size(), spec.pull_distance,
                                   spec.timestep_fs, spec.temperature)}});
  page.section("What to do next");
  std::vector<std::string> next;
  if (lv < 2)
    next.push_back("More or slower rates (`--rates`), longer pulls (`--pull-distance`) or more "
                   "blocks narrow the zero-rate extrapolation.");
  next.push_back("Use EI(0) and ξp as the chain stiffness of the RVE model (docs/theory.md).");
  page.list(next);
  page.section("Key numbers");
  page.facts(
      {{"EI(0), zero-rate intercept",
        fmt::format("{} kcal/mol Å = {} N m² (95 % interval)", pm(r.ei0.value, r.ei0_ci95),
                    pm(r.ei0.value * si, r.ei0_ci95 * si))},
       {"persistence length ξp = EI/kT",
        fmt::format("{} Å at {} K (95 % interval)", pm(r.xi_p, r.xi_p_ci95), spec.temperature)},
       {"EI(rate)",
        fmt::format("{:.4g} + {:.4g} rate (kcal/mol Å, rate in Å/fs)", r.line.c[0], r.line.c[1])}});
  if (spec.chain == "harmonic")
    page.paragraph(fmt::format("By construction: EI = {:.4g} kcal/mol Å (discrete chain, this "
                               "loading), {:.4g} kcal/mol Å (continuum k_θ l0).",
                               r.expected_ei, r.expected_ei_continuum));
  html::Table t;
  t.caption = "Bending stiffness per pulling rate (± 1 standard error)";
  t.header = {"rate (Å/fs)", "EI (kcal/mol Å)", "EI from the end of the pull (kcal/mol Å)",
              "largest deflection (Å)"};
  t.numeric = {true, true, true, true};
  for (const auto& rr : r.rates)
    t.rows.push_back({fmt::format("{:.4g}", rr.rate), pm(rr.ei.value, rr.ei.se),
                      fmt::format("{:.4g}", rr.ei_end), fmt::format("{:.4g}", rr.d_max)});
  page.table(t);
  add_figures(page, run,
              {{"EI_vs_rate.png", "EI (N m²) against the pulling rate (m/s) and the straight "
                                  "line extrapolated to rate 0."}});
  add_warnings(page, run);
  return page.write_report(run.out);
}

namespace {
nlohmann::json jnum(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}
} // namespace

nlohmann::json ti_json(const ThermoRun& run, const thermo::TiSpec& spec, const thermo::TiResult& r,
                       const std::string& report, double worst_fd) {
  const double J = units::joule_per_kcal_mol;
  const auto [a0, s0] = reference_dA(r);
  nlohmann::json j;
  j["command"] = "thermo ti";
  j["out"] = run.out;
  j["h5"] = r.h5;
  j["plots"] = run.pngs;
  j["report"] = report;
  j["rule"] = spec.rule;
  j["temperature_K"] = spec.sampling.temperature;
  j["kT_J"] = units::boltzmann * spec.sampling.temperature;
  j["nodes"] = r.states.empty() ? std::vector<double>{} : r.states.front().ti.rule.nodes;
  j["weights"] = r.states.empty() ? std::vector<double>{} : r.states.front().ti.rule.weights;
  nlohmann::json sts = nlohmann::json::array();
  for (const auto& st : r.states) {
    nlohmann::json o;
    o["id"] = st.state.id;
    o["kind"] = st.state.kind;
    o["strain"] = st.state.strain;
    o["volume_m3"] = jnum(st.volume * units::m3_per_angstrom3);
    o["dA_J"] = jnum(st.ti.dA.value * J);
    o["dA_stderr_J"] = jnum(st.ti.dA.se * J);
    o["dA_minus_ref_J"] = jnum((st.ti.dA.value - a0) * J);
    o["dA_minus_ref_stderr_J"] =
        jnum(st.state.kind == "ref" ? 0.0 : std::hypot(st.ti.dA.se, s0) * J);
    std::vector<double> m, se;
    for (const auto& p : st.ti.points) {
      m.push_back(p.dhdl.value * J);
      se.push_back(p.dhdl.se * J);
    }
    o["dhdl_J"] = m;
    o["dhdl_stderr_J"] = se;
    sts.push_back(o);
  }
  j["states"] = sts;
  j["fd_check_max_relative_difference"] = worst_fd;
  nlohmann::json fits = nlohmann::json::object();
  for (const auto& f : r.fits)
    fits[f.kind] = {{"modulus_Pa", jnum(f.modulus)}, {"modulus_stderr_Pa", jnum(f.modulus_se)}};
  j["response"] = fits;
  j["wall_s"] = run.seconds;
  return j;
}

nlohmann::json persistence_json(const ThermoRun& run, const thermo::PersistenceSpec& spec,
                                const thermo::PersistenceResult& r, const std::string& report) {
  const double si = units::j_m_per_kcal_mol_A;      // (N m^2) per (kcal/mol A)
  const double mps = units::m_per_angstrom / 1e-15; // (m/s) per (A/fs)
  nlohmann::json j;
  j["command"] = "thermo persistence";
  j["h5"] = r.h5;
  j["plots"] = run.pngs;
  j["report"] = report;
  j["chain"] = spec.chain;
  j["temperature_K"] = spec.temperature;
  j["length_m"] = r.length * units::m_per_angstrom;
  nlohmann::json rs = nlohmann::json::array();
  for (const auto& rr : r.rates)
    rs.push_back({{"rate_m_per_s", rr.rate * mps},
                  {"EI_N_m2", jnum(rr.ei.value * si)},
                  {"EI_stderr_N_m2", jnum(rr.ei.se * si)},
                  {"EI_end_ratio_N_m2", jnum(rr.ei_end * si)}});
  j["rates"] = rs;
  j["EI0_N_m2"] = jnum(r.ei0.value * si);
  j["EI0_ci95_N_m2"] = jnum(r.ei0_ci95 * si);
  j["xi_p_m"] = jnum(r.xi_p * units::m_per_angstrom);
  j["xi_p_ci95_m"] = jnum(r.xi_p_ci95 * units::m_per_angstrom);
  j["expected_EI_N_m2"] = jnum(r.expected_ei * si);
  j["expected_EI_continuum_N_m2"] = jnum(r.expected_ei_continuum * si);
  j["wall_s"] = run.seconds;
  return j;
}

bool work_is_noise(const thermo::WorkIntegral& w) {
  return w.has_se && !(std::fabs(w.value.back()) > 2 * w.se_bound.back());
}

bool work_case_is_noise(const thermo::WorkCase& c, int runs) {
  return work_is_noise(c.da) || (runs == 2 && work_is_noise(c.da_s) && work_is_noise(c.da_u));
}

namespace {
std::string work_text(const thermo::WorkIntegral& w) {
  const double v = w.value.back();
  if (!w.has_se) return fmt::format("{:.4g} (no errors in the data)", v);
  return fmt::format("{:.4g} ± {:.2g} (bound {:.2g})", v, w.se_indep.back(), w.se_bound.back());
}

} // namespace

std::string write_work_report(const ThermoRun& run, const thermo::WorkResult& r) {
  html::Page page("pnc thermo work: " + run.out);
  std::vector<std::pair<Tone, std::string>> reasons;
  int resolved = 0;
  for (const auto& c : r.cases) {
    const bool judged = c.da.has_se;
    resolved += judged && !work_case_is_noise(c, r.runs) ? 1 : 0;
    if (!judged)
      reasons.push_back({Tone::warning, fmt::format("case {}: the data carry no standard "
                                                    "errors: da = {} J/m³ is not judged",
                                                    c.id, work_text(c.da))});
    else if (work_is_noise(c.da))
      reasons.push_back({Tone::bad, fmt::format("case {}: da = {} J/m³ is within twice its "
                                                "error bound",
                                                c.id, work_text(c.da))});
    else if (work_case_is_noise(c, r.runs))
      reasons.push_back({Tone::bad, fmt::format("case {}: its entropic and energetic parts are "
                                                "both within twice their error bounds",
                                                c.id)});
    if (c.softening)
      reasons.push_back({Tone::warning, fmt::format("case {}: the stress softens (yield or "
                                                    "damage): its integral is work, not a "
                                                    "free energy",
                                                    c.id)});
  }
  const int n = static_cast<int>(r.cases.size());
  int noise = 0;
  for (const auto& c : r.cases)
    noise += work_case_is_noise(c, r.runs) ? 1 : 0;
  if (resolved == n)
    page.verdict(fmt::format("Resolved: every case ({}) exceeds twice its error bound", n),
                 Tone::good, reasons);
  else if (noise == n)
    page.verdict("No result: no case exceeds twice its error bound (exit code 4)", Tone::bad,
                 reasons);
  else if (resolved > 0)
    page.verdict(
        fmt::format("Partly resolved: {} of {} cases exceed twice their error bound", resolved, n),
        Tone::warning, reasons);
  else
    page.verdict("Not judged: no case is resolved and the data carry no standard errors",
                 Tone::warning, reasons);
  add_run(
      page, run,
      {{"runs", r.runs == 2 ? fmt::format("2, at T1 = {} K and T2 = {} K (mean {} K)", r.t1, r.t2,
                                          r.temperature)
                            : fmt::format("1, at T = {} K", r.temperature)},
       {"reference volume V0", fmt::format("{:.6g} m³ ({:.0f} Å³)", r.volume, r.volume * 1e30)}});
  page.section("What to do next");
  std::vector<std::string> next;
  if (resolved < n)
    next.push_back("More replicas or longer holds in `pnc characterize` shrink the stress "
                   "errors; larger strains grow the signal (quadratically, while elastic).");
  if (r.runs == 1)
    next.push_back("A second `pnc characterize` run at another temperature (`--from` twice) "
                   "splits da into entropic and energetic parts.");
  next.push_back("The free energy per case is in work.h5 and work.csv (docs/formats.md).");
  page.list(next);
  page.section("Key numbers");
  page.paragraph("At the largest strain of each case: da = ∫ σ : dε (J/m³) ± its standard error "
                 "for independent points, and its bound for any correlation between the points "
                 "(decision D143: within twice the bound is noise); ΔA = V0 da.");
  html::Table t;
  t.caption = "Free energy of deformation per case (at its largest strain)";
  t.header = {"case", "largest |ε_ij|", "da (J/m³)", "ΔA (kcal/mol)", "verdict"};
  if (r.runs == 2) {
    t.header.insert(t.header.begin() + 4, "entropic −TΔs (J/m³)");
    t.header.insert(t.header.begin() + 5, "energetic Δu (J/m³)");
  }
  t.numeric.assign(t.header.size(), true);
  t.numeric.front() = false;
  t.numeric.back() = false;
  const double kc = r.volume * units::kcal_mol_per_joule;
  for (const auto& c : r.cases) {
    const auto k = static_cast<Eigen::Index>(c.da.value.size() - 1);
    std::vector<std::string> row = {
        std::to_string(c.id), fmt::format("{:.4g}", c.strain.row(k).cwiseAbs().maxCoeff()),
        work_text(c.da),
        c.da.has_se ? pm(c.da.value.back() * kc, c.da.se_indep.back() * kc)
                    : fmt::format("{:.4g}", c.da.value.back() * kc)};
    if (r.runs == 2) {
      row.push_back(work_text(c.da_s));
      row.push_back(work_text(c.da_u));
    }
    row.push_back(std::string(!c.da.has_se                    ? "not judged (no errors)"
                              : work_case_is_noise(c, r.runs) ? "noise"
                                                              : "resolved") +
                  (c.softening ? ", softening" : ""));
    t.rows.push_back(row);
  }
  page.table(t);
  add_figures(page, run,
              {{"work.png", "da against the largest strain component per case; error bars 1 "
                            "standard error, the band ± twice the any-correlation bound."}});
  ThermoRun with_notes = run;
  with_notes.notes.insert(with_notes.notes.end(), r.notes.begin(), r.notes.end());
  add_warnings(page, with_notes);
  return page.write_report(run.out);
}

} // namespace pnc::app
