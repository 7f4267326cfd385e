// core: a pnc error as data, so that another process (a unit of a run folder, a LAMMPS stage
// child) can record it and the process that reads the record throws the same kind again with
// the same exit code (core/error.hpp, docs/errors.md).
//
// Record layout (JSON object, no units): "exit_code" (integer: 1 InputError, 6
// SimulationError, 7 ToolError, 2 anything else), "what" (the one-line message), and the
// kind's parts: InputError "source", "field", "value", "rule"; SimulationError "entity",
// "step" (integer, < 0 not known), "time" (number or null when not known), "time_unit",
// "message"; ToolError "tool", "doing", "message", "log_path".
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <exception>

namespace pnc {

/// The record of `e` (layout above).
nlohmann::json error_record(const std::exception& e);

/// Throws the error `record` describes: InputError, SimulationError or ToolError with the
/// recorded parts, otherwise std::runtime_error(what). A record that is not an object, or
/// lacks a part, still throws (missing parts are empty): reading a record never crashes.
[[noreturn]] void rethrow_error_record(const nlohmann::json& record);

} // namespace pnc
