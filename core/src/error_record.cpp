#include "pnc/core/error_record.hpp"

#include "pnc/core/error.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace pnc {

nlohmann::json error_record(const std::exception& e) {
  nlohmann::json j = {{"exit_code", exit_code_of(e)}, {"what", e.what()}};
  if (const auto* ie = dynamic_cast<const InputError*>(&e)) {
    const auto& c = ie->context();
    j.update({{"source", c.source}, {"field", c.field}, {"value", c.value}, {"rule", c.rule}});
  } else if (const auto* se = dynamic_cast<const SimulationError*>(&e)) {
    const auto& c = se->context();
    j.update({{"entity", c.entity},
              {"step", c.step},
              {"time", std::isfinite(c.time) ? nlohmann::json(c.time) : nlohmann::json()},
              {"time_unit", c.time_unit},
              {"message", c.message}});
  } else if (const auto* te = dynamic_cast<const ToolError*>(&e)) {
    const auto& c = te->context();
    j.update(
        {{"tool", c.tool}, {"doing", c.doing}, {"message", c.message}, {"log_path", c.log_path}});
  }
  return j;
}

namespace {
std::string text(const nlohmann::json& r, const char* key) {
  if (!r.is_object()) return {};
  const auto it = r.find(key);
  return it != r.end() && it->is_string() ? it->get<std::string>() : std::string();
}
} // namespace

void rethrow_error_record(const nlohmann::json& r) {
  const auto code_it = r.is_object() ? r.find("exit_code") : r.end();
  const int code = r.is_object() && code_it != r.end() && code_it->is_number_integer()
                       ? code_it->get<int>()
                       : exit_code::internal_error;
  switch (code) {
  case exit_code::bad_input:
    throw InputError(
        ErrorContext{text(r, "source"), text(r, "field"), text(r, "value"), text(r, "rule")});
  case exit_code::simulation_failed: {
    const auto s = r.find("step");
    const auto t = r.find("time");
    throw SimulationError(SimulationContext{
        text(r, "entity"), s != r.end() && s->is_number_integer() ? s->get<long long>() : -1,
        t != r.end() && t->is_number() ? t->get<double>()
                                       : std::numeric_limits<double>::quiet_NaN(),
        text(r, "time_unit"), text(r, "message")});
  }
  case exit_code::tool_failed:
    throw ToolError(
        ToolContext{text(r, "tool"), text(r, "doing"), text(r, "message"), text(r, "log_path")});
  default: {
    const std::string w = text(r, "what");
    throw std::runtime_error(w.empty() ? std::string("an error without a message") : w);
  }
  }
}

} // namespace pnc
