#pragma once
// Shared formatting of constants for the human-readable reports and the JSON output.
#include "pnc/core/error.hpp"
#include "pnc/damage/card.hpp"

#include <nlohmann/json.hpp>
#include <string>

namespace pnc::app {
/// Value in display units: GPa for stiffness-like constants, plain for alpha.
double display_value(const std::string& name, double si);
const char* display_units(const std::string& name);
/// Constants table (name, value +- std error, fitted/held, note) for stderr.
std::string constants_table(const damage::Card& c);
nlohmann::json constants_json(const damage::Card& c);
/// Fit quality (R^2 per case/component) and the per-case regression next to the printed
/// tables of the dissertation.
std::string fit_tables(const damage::FitRecord& f, damage::Model m);
/// Keys follow the JSON unit rule (D238; docs/schemas/common.schema.json "fit").
nlohmann::json fit_json(const damage::FitRecord& f);
/// The card's verdict and its reasons, one per line, for stderr and as JSON.
std::string verdict_text(const damage::Verdict& v);
nlohmann::json verdict_json(const damage::Verdict& v);
/// Exit code of a command that wrote a card with this verdict: 0, or kExitNotUsable.
constexpr int kExitNotUsable = pnc::exit_code::card_not_usable; // 4, docs/errors.md
/// NaN/inf become null in JSON.
nlohmann::json num(double v);
} // namespace pnc::app
