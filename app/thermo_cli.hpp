#pragma once
// Pieces the `pnc thermo` subcommands share (app/cmd_thermo.cpp, app/cmd_thermo_ti.cpp).
// Units: LAMMPS real (kcal/mol, A, fs, K).
#include "registrars.hpp"
#include "thermo_report.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace pnc::app {

/// LAMMPS runs at most 2^31 - 1 steps in one `run` command.
constexpr long kMaxRunSteps = 2000000000L;

/// `v` as JSON, null when not finite.
nlohmann::json jnum(double v);
/// Draws with plot_thermo.py; a failure is printed once and kept in `run` for the report.
std::vector<std::string> run_plot(const std::vector<std::string>& args, ThermoRun& run);
/// "a,b,c" -> numbers ("none" or "": none); a bad item names `field` (<command line>).
std::vector<double> parse_list(const std::string& text, const char* field);

/// Adds `pnc thermo ti` to `thermo` (app/cmd_thermo_ti.cpp) and registers its plan's units
/// with `pnc run-unit`.
void register_thermo_ti(CLI::App* thermo, Action& action);

} // namespace pnc::app
