#pragma once
// The pnc subcommands as plain functions over plain option structs; CLI11 lives only in
// main.cpp. Each run_* returns the process exit code, prints its human-readable report on
// stderr and, with json = true, one JSON object on stdout.
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace pnc::app {

struct FitArgs {
  std::string data, model = "pnc", out, prior, plots, loss = "none";
  bool no_plots = false, fit_alpha = false, hold_alpha = false, json = false;
  bool no_unit_check = false;
  std::optional<double> alpha;
  double loss_scale = 1.0;
  int max_iterations = 200;
  double strain_max = 0;  ///< fit range (D12h), 0 = every row
  double stretch_max = 0; ///< fit range by lambda_max - 1 (D12m), 0 = every row
  bool isotropic = false; ///< pp: C44 and B4 derived by isotropy (D396)
  std::string command_line;
  /// the long flags `pnc fit` declares (main.cpp: long_flags of its CLI11 command): a FitOptions
  /// rule on field f is reported on the flag "--" + f with '_' -> '-' when that flag is one of them
  std::set<std::string> flags;
};
int run_fit(const FitArgs& a);

struct CardShowArgs {
  std::string card;
  bool json = false;
  double max_strain = 1.0;
};
int run_card_show(const CardShowArgs& a);

struct CardTablesArgs {
  std::string model = "pnc", out;
  bool json = false;
  std::string command_line;
};
int run_card_tables(const CardTablesArgs& a);

struct CardExportArgs {
  std::string card, format = "abaqus", name, out, plugin;
  bool with_rotation = false, allow_not_usable = false;
};
int run_card_export(const CardExportArgs& a); // app/cmd_card_export.cpp

struct SynthArgs {
  std::string model = "pnc", card, out;
  std::vector<int> cases;
  int points = 200;
  double max_extension = 0.2, max_shear = 0.4, noise_mpa = 2.0;
  unsigned long long seed = 1;
  bool json = false;
};
int run_synth(const SynthArgs& a);

} // namespace pnc::app
