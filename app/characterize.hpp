#pragma once
// `pnc characterize`, `pnc run-unit`, `pnc status`: the MD -> fit pipeline as a plan of units
// run locally or through Slurm (pnc/campaign/: campaign.hpp, executor.hpp, slurm.hpp;
// docs/rve.md, docs/cluster.md, decisions D240-D246).
#include "campaign_driver.hpp"

#include "pnc/rve/characterize.hpp"
#include "pnc/rve/recipe.hpp"

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace pnc::app {

struct CharacterizeArgs {
  std::string recipe, out;
  bool resume = false, json = false, no_plots = false;
  bool refit = false; ///< --refit (D400): a finished run fitted again with a changed fit section
  int jobs = 0, ranks = 0, equilibrate_ranks = 0;
  int replicas = 0; ///< --replicas: the recipe's run.replicas overridden (0: not given; D418)
  std::string executor = "local"; ///< "local" or "slurm"
  SlurmOptions slurm;             ///< slurm: overrides of the recipe's section, --wait
};
int run_characterize(const CharacterizeArgs& a);

/// Options `pnc characterize` and `pnc run-unit` hand to the fit unit (plan parameters).
struct FitUnitArgs {
  std::string recipe, out; ///< the recipe argument as given, the run folder
  bool no_plots = false;
  int replicas = 0; ///< --replicas as given (0: the recipe's), for the command the card records
};
/// The fit unit: fit of cases.h5 -> card.h5, plots, report.md and summary.json (what
/// `pnc characterize --json` prints). Returns 0, 3 (fit not converged) or 4 (card not usable).
int run_fit_unit(const rve::Recipe& r, const rve::MdOutcome& md, const FitUnitArgs& a);
std::string summary_path(const std::string& dir); ///< DIR/summary.json

/// Registers `pnc run-unit` and `pnc status` (app/cmd_campaign.cpp).
using Action = std::function<int()>;
void register_campaign(CLI::App& app, Action& action);

std::string preset_list();
rve::Recipe load_recipe(const std::string& arg);

} // namespace pnc::app
