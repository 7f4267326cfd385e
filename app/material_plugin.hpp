#pragma once
// The material plugin as `pnc material drive` and `pnc card export` load it: the built
// libpnc_material.so through the C ABI (pnc::fe_material::Plugin), the entry point the
// solvers use, never a private path into damage/ (docs/decisions.md D160).
#include "pnc/fe_material/material.hpp"

#include <string>

namespace pnc::app {

/// Where the plugin is, in this order: `option` (--plugin) if not empty; the environment
/// variable PNC_MATERIAL_PLUGIN if set and not empty; else next to this executable
/// (/proc/self/exe): the build tree's fe_material/ beside app/, then the install's
/// ../lib (and ../lib/<multiarch>). The one place that knows these paths (D161).
/// Throws pnc::InputError naming every place looked at when nothing is found.
std::string find_material_plugin(const std::string& option);

/// Loads the plugin found by find_material_plugin(); throws pnc::InputError naming the path.
pnc::fe_material::Plugin load_material_plugin(const std::string& option);

/// Reads a card through the plugin. A "not usable" card is refused (InputError with the
/// card's reasons) unless allow_not_usable.
pnc::fe_material::Material load_card(const pnc::fe_material::Plugin& plugin,
                                     const std::string& card, bool allow_not_usable);

} // namespace pnc::app
