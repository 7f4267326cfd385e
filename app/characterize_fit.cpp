// The fit unit of `pnc characterize`: cases.h5 -> NDM fit -> card, figures, report.html and
// report.md (characterize_report.hpp) and summary.json (app/characterize.hpp). Units: cases.h5 and
// cards in Pa (SI).
#include "characterize.hpp"
#include "characterize_report.hpp"
#include "figures.hpp"
#include "report.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/version.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/damage/moduli.hpp"
#include "pnc/rve/replica_bootstrap.hpp"
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
/// The fit unit's results, from which the card, the report and the summary are made.
struct MdFit {
  damage::FitOptions o;
  damage::StressStrainData data;
  damage::FitReport rep;
  rve::ReplicaFits replica_fits;
  rve::ReplicaBootstrap bootstrap; ///< the calibration check of the card's errors (D431)
  damage::Card card;
  rve::ReplicaTrend trend;
  std::vector<rve::SensePair> senses; ///< the shears run both ways, side by side (D428)
  double max_shape_error = 0;         ///< the tolerance the verdict judged the shape by (D417)
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
  o.stretch_max = r.fit_stretch_max;                      // recipe fit.stretch_max (D12m)
  o.isotropic = r.fit_isotropic;                          // recipe fit.isotropic (D396)
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
    std::vector<double> between(card.std_error.size(), std::nan(""));
    for (std::size_t j = 0; j < between.size() && j < replica_fits.se.size(); ++j)
      if (card.fitted[j]) between[j] = replica_fits.coverage_factor * replica_fits.se[j];
    const int raised = rve::raise_errors(card.std_error, between);
    honest.std_error = card.std_error;
    card.fit.error_model += fmt::format(
        "; per constant the larger of that and the between-replica standard error of {} "
        "separate replica fits (Student t factor {:.3g}; D130): {} constant(s) raised",
        replica_fits.replicas, replica_fits.coverage_factor, raised);
  }
  // decision D431: the joint fit bootstrapped over the replicas checks those errors against its
  // own sampling spread and raises any that is smaller (never lowers one)
  f.bootstrap =
      rve::bootstrap_joint_fit(md.statistics, o, rep, card.std_error, r.fit_bootstrap, r.seed);
  if (f.bootstrap.applicable) {
    const int raised = rve::apply_bootstrap(f.bootstrap, card.std_error);
    honest.std_error = card.std_error;
    card.fit.error_model += fmt::format(
        "; checked by a bootstrap of the joint fit over the replicas ({} resamples, D431): {} "
        "constant(s) raised to its spread",
        f.bootstrap.resamples, raised);
  }
  // decision D12k: with >= 3 replicas the residuals of the mean curves are correlated along
  // the curves; misfit is tested across replicas instead of by the runs test and chi^2 p
  f.trend = rve::replica_trend_test(md.statistics, rep, o.strain_max, o.stretch_max);
  f.senses = rve::sense_pairs(md.statistics, o.strain_max, o.stretch_max); // D428
  const rve::ReplicaTrend& trend = f.trend;
  MdCardGates gates;
  f.max_shape_error = gates.max_shape_error;
  if (trend.applicable) {
    VerdictLimits limits;
    limits.independent_residuals = false;
    card.verdict = judge_fit(honest, limits);
    // decision D417: the law's shape error (the largest bound of a trend common to the
    // replicas, as a share of its stress) above max_shape_error is a warning, resolved or not;
    // it goes on the card either way
    rve::judge_replica_trend(trend, limits.p_misfit, gates.max_shape_error, card.verdict);
    card.fit.shape_error = trend.shape_error();
  }
  // decision D12f: what "usable" means for an MD card (replicas, chi^2/dof, relative errors,
  // points in the linear range)
  gates.replicas = md.statistics.replicas;
  gates.deterministic = r.deform.temperature == 0;
  judge_md_card(honest, data, gates, card.verdict);
  return f;
}

} // namespace

std::string summary_path(const std::string& dir) {
  return (fs::path(dir) / "summary.json").string();
}

int run_fit_unit(const rve::Recipe& r, const rve::MdOutcome& md, const FitUnitArgs& a) {
  using namespace pnc::damage;
  std::cerr << "pnc characterize [fit] " << md.cases_h5 << "\n";
  const MdFit f = fit_md(r, md);
  const std::string card_path = (fs::path(a.out) / "card.h5").string();
  const std::string command =
      fmt::format("pnc characterize {} --out {}{}", a.recipe, a.out,
                  a.replicas > 0 ? fmt::format(" --replicas {}", a.replicas) : std::string());
  write_card(card_path, f.card, command);
  // decision D130: every replica's own fit, for checks of the error bars across runs
  if (const std::string csv = rve::replica_fits_csv(f.replica_fits); !csv.empty())
    write_text_atomically((fs::path(a.out) / "replica_fits.csv").string(), csv);
  // every figure of the run in one plotting process, after the card is written (a plotting
  // failure is a warning: the run and its report are complete without figures)
  CharacterizeRun run{r,           md,
                      f.data,      f.rep,
                      f.card,      f.replica_fits,
                      f.bootstrap, f.trend,
                      f.senses,    f.max_shape_error,
                      f.o.model,   a.out,
                      command,     read_clay_info(r, md),
                      0.0,         !a.no_plots,
                      {}};
  if (!a.no_plots) {
    const std::string plots = (fs::path(a.out) / "plots").string();
    make_output_directory(plots, "--out");
    run.plots = draw_figures(characterize_figures(r, md, f.data, f.card, f.senses, plots),
                             (fs::path(plots) / "figures.json").string(), "pnc characterize");
  }
  // the campaign's wall time: from the first unit's start to now (every unit of this run)
  run.seconds = campaign::epoch_seconds() - md.started_s;
  const std::string report_path = write_characterize_report(run);
  const std::string html_path = (fs::path(a.out) / "report.html").string();
  print_characterize_summary(run, card_path, report_path, html_path);
  // what `pnc characterize --json` prints, kept in the run folder (the fit is a unit)
  write_text_atomically(summary_path(a.out),
                        characterize_json(run, card_path, report_path, html_path).dump() + "\n");
  if (f.card.verdict.level == VerdictLevel::not_usable) {
    std::cerr << "pnc: error: the card is NOT USABLE (reasons above); it was written, marked, "
                 "and the plugin refuses it unless the host allows unusable cards\n";
    return kExitNotUsable;
  }
  if (!f.rep.converged) {
    std::cerr << "pnc: error: the fit did not converge (" << f.rep.termination
              << "): " << f.rep.message << "; the card was written but check it before use\n";
    return pnc::exit_code::not_converged;
  }
  return 0;
}

} // namespace pnc::app
