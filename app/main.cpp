// pnc: command-line entry point. One subcommand per file (cmd_*.cpp); CLI11 only here.
// Exit codes (pnc::exit_code in core/error.hpp; the table with what the user does:
// docs/errors.md): 0 success; 1 bad input (pnc::InputError, one line "pnc: error: ..." naming
// file, field, value, rule) or a command line CLI11 cannot parse (one line, the nearest valid
// names for a mistyped subcommand or option: cli_errors.hpp); 2 internal error (a bug);
// 3 a fit (or a stress-controlled step of `pnc material drive`) that did not converge; 4 a
// card written with the verdict "not usable"; 5 `pnc material drive` outside a reference's
// tolerances; 6 a simulation that failed (pnc::SimulationError); 7 an external tool that
// failed (pnc::ToolError: LAMMPS, mpirun; the line names the tool's log); 128 + N for a long
// command stopped by signal N (130 SIGINT, 143 SIGTERM) with its work up to the last
// checkpoint kept and one line "pnc: interrupted by SIGINT: <where>; continue with: <the
// command> --resume" on stderr. `--help` and `--version` exit 0.
#include "checks.hpp"
#include "cli_errors.hpp"
#include "commands.hpp"
#include "registrars.hpp"
#include "run_control.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/run_log.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/version.hpp"

#include <CLI/CLI.hpp>

#include <functional>
#include <iostream>
#include <set>

namespace {
constexpr const char* kInternalError =
    "internal error (a bug: please report it with the command line and pnc --version)";

// `pnc fit`: its options into `fa`.
CLI::App* add_fit_command(CLI::App& app, pnc::app::FitArgs& fa) {
  using namespace pnc::app;
  auto* fit =
      app.add_subcommand("fit", "Joint NDM fit (Ceres) of stress-strain curves -> card + plots");
  fit->add_option("--data", fa.data,
                  "Stress-strain data: CSV (case,e11..g12,s11_Pa..s12_Pa; _MPa, _GPa or the bare "
                  "s11.. of older files, MPa, too) or cases.h5")
      ->required();
  fit->add_option("--model", fa.model,
                  "pnc (nanocomposite, cases 1-3 required) or pp (pure polymer: any of cases 1-9 "
                  "with an extension case)")
      ->check(CLI::IsMember({"pnc", "pp"}));
  fit->add_option("--out", fa.out, "Material card to write (HDF5)")->required();
  fit->add_flag("--fit-alpha", fa.fit_alpha,
                "Always fit the critical-stretch factor alpha (1/lambda_c = 0.8035..1.5, D12i); "
                "default: fitted when "
                "the data pass the damage onset");
  fit->add_flag("--hold-alpha", fa.hold_alpha,
                "Hold alpha at --alpha (or the tables' value) even past the damage onset");
  fit->add_flag("--no-unit-check", fa.no_unit_check,
                "Accept fitted stiffnesses outside 0.1 MPa..1000 GPa (refused by default as a "
                "probable unit mistake)");
  fit->add_option("--alpha", fa.alpha, "Value of alpha (default: 0.861 pnc, 0.941 pp)")
      ->check(FiniteRange(0.5, 1.5));
  fit->add_option("--loss", fa.loss, "Robust loss: none, huber, cauchy")
      ->check(CLI::IsMember({"none", "huber", "cauchy"}));
  fit->add_option("--loss-scale", fa.loss_scale,
                  "Scale of the robust loss (MPa, or data std. errors), in (0, 1e6]")
      ->check(FinitePositive(1e6));
  fit->add_option("--strain-max", fa.strain_max,
                  "Fit only the leading rows of each curve whose strain components are all <= "
                  "this (dimensionless; 0 = every row; the card records it)")
      ->check(FiniteRange(0.0, 10.0));
  fit->add_option("--stretch-max", fa.stretch_max,
                  "Fit only the leading rows of each curve whose largest principal stretch minus "
                  "one is <= this (dimensionless; 0 = every row; excludes --strain-max; D12m)")
      ->check(FiniteRange(0.0, 10.0))
      ->excludes("--strain-max");
  fit->add_flag("--isotropic", fa.isotropic,
                "Model pp only: an isotropic solid with isotropic damage, C44 = (C11 - C12)/2 and "
                "B4 = B1 - B2/2 derived, not fitted (D396)");
  fit->add_option("--max-iterations", fa.max_iterations, "Solver iteration limit (1 to 1e6)")
      ->check(CLI::Range(1, 1000000));
  fit->add_option("--prior", fa.prior,
                  "Card whose constants are used where the data cannot determine them "
                  "(default: the dissertation's tables)");
  fit->add_option("--plots", fa.plots, "Directory for the PNG plots (default: <card>_plots)");
  fit->add_flag("--no-plots", fa.no_plots, "Do not draw plots");
  fit->add_flag("--json", fa.json, "Print one JSON object with the key numbers on stdout");
  return fit;
}

// The long flags a command declares, "--name" each (FitArgs::flags).
std::set<std::string> long_flags(const CLI::App& cmd) {
  std::set<std::string> flags;
  for (const CLI::Option* o : cmd.get_options())
    for (const std::string& name : o->get_lnames())
      flags.insert("--" + name);
  return flags;
}

// The subcommands of `pnc card` the user chose from.
struct CardCommands {
  CLI::App* show;
  CLI::App* tables;
  CLI::App* cexport;
};

// `pnc card show|tables|export`: their options into `cs`, `ct`, `ce`.
CardCommands add_card_commands(CLI::App& app, pnc::app::CardShowArgs& cs,
                               pnc::app::CardTablesArgs& ct, pnc::app::CardExportArgs& ce) {
  using namespace pnc::app;
  auto* card = app.add_subcommand("card", "Inspect or create material cards");
  card->require_subcommand(1);
  auto* show =
      card->add_subcommand("show", "Constants, errors, derived moduli and strengths of a card");
  show->add_option("card", cs.card, "Material card (HDF5)")->required();
  show->add_option("--max-strain", cs.max_strain, "Strain up to which strengths are searched")
      ->check(FiniteRange(1e-6, 10.0));
  show->add_flag("--json", cs.json, "Print one JSON object on stdout");
  auto* tables =
      card->add_subcommand("tables", "Write the dissertation's tabulated constants as a card");
  tables->add_option("--model", ct.model, "pnc or pp")->check(CLI::IsMember({"pnc", "pp"}));
  tables->add_option("--out", ct.out, "Card to write (HDF5)")->required();
  tables->add_flag("--json", ct.json, "Print one JSON object on stdout");
  auto* cexport = card->add_subcommand(
      "export", "The card as host input: Abaqus/CalculiX material blocks, JSON or bare PROPS");
  cexport->add_option("card", ce.card, "Material card (HDF5)")->required();
  cexport->add_option("--format", ce.format, "abaqus, calculix, json or props (default abaqus)")
      ->check(CLI::IsMember({"abaqus", "calculix", "json", "props"}));
  cexport->add_option("--name", ce.name,
                      "Material name (default PNC; CalculiX gets the ABAQUS prefix)");
  cexport->add_option("--out", ce.out, "Write to this file instead of stdout");
  cexport->add_flag("--with-rotation", ce.with_rotation,
                    "Always append the platelet rotation R (9 PROPS), even when it is I");
  cexport->add_option(
      "--plugin", ce.plugin,
      "libpnc_material.so to load (default: $PNC_MATERIAL_PLUGIN, else next to pnc)");
  cexport->add_flag("--allow-not-usable", ce.allow_not_usable,
                    "Export a card whose verdict is 'not usable'");
  return {show, tables, cexport};
}

// `pnc synth`: its options into `sa`.
CLI::App* add_synth_command(CLI::App& app, pnc::app::SynthArgs& sa) {
  using namespace pnc::app;
  auto* synth =
      app.add_subcommand("synth", "Synthetic stress-strain curves from the NDM plus noise");
  synth->add_option("--model", sa.model, "pnc or pp (dissertation constants)")
      ->check(CLI::IsMember({"pnc", "pp"}));
  synth->add_option("--card", sa.card, "Use this card's constants instead of the dissertation's");
  synth->add_option("--cases", sa.cases, "Case ids (default: the model's cases)")->delimiter(',');
  synth->add_option("--points", sa.points, "Points per case (3 to 100000)")
      ->check(CLI::Range(3, 100000));
  synth->add_option("--max-extension", sa.max_extension, "Largest normal strain, in (0, 1)")
      ->check(FiniteRange(0.0, 1.0, true));
  synth->add_option("--max-shear", sa.max_shear, "Largest engineering shear strain, in (0, 2)")
      ->check(FiniteRange(0.0, 2.0, true));
  synth
      ->add_option("--noise-mpa", sa.noise_mpa,
                   "Standard deviation of the stress noise (MPa, 0 to 10000)")
      ->check(FiniteRange(0.0, 1e4));
  synth->add_option("--seed", sa.seed, "Random seed");
  synth->add_option("--out", sa.out, "Output file (.csv or .h5)")->required();
  synth->add_flag("--json", sa.json, "Print one JSON object on stdout");
  return synth;
}

// Runs the chosen command; an exception becomes its one-line message and exit code (the
// table at the top of this file).
int run_reporting_errors(const std::function<int()>& command) {
  using namespace pnc::app;
  try {
    return command();
  } catch (const pnc::Interrupted& e) {
    std::cerr << "pnc: interrupted by " << signal_name(e.signal()) << ": " << e.detail()
              << "; continue with: " << resume_command() << std::endl;
    return pnc::exit_code::stopped_by_signal(e.signal());
  } catch (const pnc::Error& e) { // InputError 1, SimulationError 6, ToolError 7 (with its log)
    std::cerr << "pnc: error: " << e.what() << "\n";
    return e.exit_code();
  } catch (const std::exception& e) {
    std::cerr << "pnc: error: " << kInternalError << ": " << e.what() << "\n";
    return pnc::exit_code::internal_error;
  } catch (...) { // not even a std::exception (e.g. H5::Exception): a bug all the same
    std::cerr << "pnc: error: " << kInternalError << ": an exception of unknown type\n";
    return pnc::exit_code::internal_error;
  }
}
} // namespace

int main(int argc, char** argv) {
  using namespace pnc::app;
  CLI::App app{"pnc: multiscale toolkit for polymer nanocomposites (Nair 2010 method).\n"
               "Fits the nano-scale damage model (NDM) to stress-strain curves and writes a "
               "material card (HDF5, SI units) for the fe_material plugin."};
  configure_cli(app); // before any option: subcommands inherit it
  app.require_subcommand(1);
  app.set_version_flag("--version", pnc::version_string());
  set_command_line(argc, argv);
  const std::string cmdline = command_line();

  FitArgs fa;
  fa.command_line = cmdline;
  CLI::App* fit = add_fit_command(app, fa);
  fa.flags = long_flags(*fit);
  CardShowArgs cs;
  CardTablesArgs ct;
  ct.command_line = cmdline;
  CardExportArgs ce;
  const CardCommands card = add_card_commands(app, cs, ct, ce);
  CLI::App* show = card.show;
  CLI::App* tables = card.tables;
  CLI::App* cexport = card.cexport;
  SynthArgs sa;
  CLI::App* synth = add_synth_command(app, sa);

  // Subcommand families in their own files (registrars.hpp).
  Action action;
#ifdef PNC_HAVE_RVE_COMMANDS
  register_rve(app, action);
#endif
#ifdef PNC_HAVE_GIMP_COMMANDS
  register_gimp(app, action);
#endif
#ifdef PNC_HAVE_THERMO_COMMANDS
  register_thermo(app, action);
#endif
  register_material(app, action);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return report_parse_error(app, e, argc, argv);
  }
  const int code = run_reporting_errors([&]() -> int {
    if (*fit) return run_fit(fa);
    if (*show) return run_card_show(cs);
    if (*tables) return run_card_tables(ct);
    if (*cexport) return run_card_export(ce);
    if (*synth) return run_synth(sa);
    if (action) return action();
    return 0;
  });
  pnc::finish_run_log(code); // the run folder's pnc.log ends with the exit code (run_log.hpp)
  return code;
}
