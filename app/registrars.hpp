#pragma once
// Subcommand families that live in their own translation units (each includes CLI11).
// A registrar adds its subcommands to `app` and, when one of them is chosen, sets `action`
// to the function that runs it (returning the exit code).
#include <functional>

namespace CLI {
class App;
}

namespace pnc::app {
using Action = std::function<int()>;
void register_rve(CLI::App& app, Action& action);      // app/cmd_rve.cpp     (docs/rve.md)
void register_gimp(CLI::App& app, Action& action);     // app/cmd_gimp.cpp    (docs/gimp.md)
void register_thermo(CLI::App& app, Action& action);   // app/cmd_thermo.cpp (docs/thermo.md)
void register_material(CLI::App& app, Action& action); // app/cmd_material.cpp (docs/drive.md)
} // namespace pnc::app
