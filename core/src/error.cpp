#include "pnc/core/error.hpp"

#include "pnc/core/params.hpp"

#include <cmath>
#include <cstdio>
#include <utility>

namespace pnc {

namespace {
std::string format_message(const ErrorContext& c) {
  std::string m = c.source.empty() ? std::string("<input>") : c.source;
  if (!c.field.empty()) m += ": field '" + c.field + "'";
  // A value is shown whole up to 200 characters: messages stay one readable line.
  if (!c.value.empty()) m += ": value '" + clip(c.value, 200) + "'";
  m += ": " + c.rule;
  return m;
}

/// A tool's or a simulation's text as one line: line breaks become " | ", trailing blanks go,
/// and at most 1000 characters are kept (a tool's output can be a whole log).
std::string one_line(const std::string& s) {
  std::string o;
  o.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '\r' || c == '\n') {
      while (i + 1 < s.size() && (s[i + 1] == '\r' || s[i + 1] == '\n'))
        ++i;
      if (!o.empty() && i + 1 < s.size()) o += " | ";
    } else {
      o += c;
    }
  }
  while (!o.empty() && (o.back() == ' ' || o.back() == '\t'))
    o.pop_back();
  return clip(o, 1000);
}

std::string format_simulation(const SimulationContext& c) {
  std::string m = c.entity.empty() ? std::string("<simulation>") : c.entity;
  std::string when;
  if (c.step >= 0) when = "step " + std::to_string(c.step);
  if (std::isfinite(c.time)) {
    char t[64];
    std::snprintf(t, sizeof t, "%.6g", c.time);
    when += (when.empty() ? "t = " : ", t = ") + std::string(t) +
            (c.time_unit.empty() ? std::string(" (unit not stated)") : " " + c.time_unit);
  }
  if (!when.empty()) m += ": " + when;
  return m + ": " + one_line(c.message);
}

std::string format_tool(const ToolContext& c) {
  std::string m = (c.tool.empty() ? std::string("an external tool") : c.tool) + " failed";
  if (!c.doing.empty()) m += " while " + c.doing;
  m += ": " + (c.message.empty() ? std::string("no message") : one_line(c.message));
  if (!c.log_path.empty()) m += " (log " + c.log_path + ")";
  return m;
}
} // namespace

InputError::InputError(ErrorContext ctx)
    : Error(format_message(ctx), exit_code::bad_input), ctx_(std::move(ctx)) {}

SimulationError::SimulationError(SimulationContext ctx)
    : Error(format_simulation(ctx), exit_code::simulation_failed), ctx_(std::move(ctx)) {}

ToolError::ToolError(ToolContext ctx)
    : Error(format_tool(ctx), exit_code::tool_failed), ctx_(std::move(ctx)) {}

void fail(std::string source, std::string field, std::string value, std::string rule) {
  throw InputError(
      ErrorContext{std::move(source), std::move(field), std::move(value), std::move(rule)});
}

void fail_tool(std::string tool, std::string doing, std::string message, std::string log_path) {
  throw ToolError(
      ToolContext{std::move(tool), std::move(doing), std::move(message), std::move(log_path)});
}

void fail_simulation(std::string entity, long long step, double time, std::string time_unit,
                     std::string message) {
  throw SimulationError(
      SimulationContext{std::move(entity), step, time, std::move(time_unit), std::move(message)});
}

int exit_code_of(const std::exception& e) noexcept {
  if (const auto* pe = dynamic_cast<const Error*>(&e)) return pe->exit_code();
  return exit_code::internal_error;
}

std::string with_log(const std::string& message, const std::string& log) {
  const std::string tag = "(log " + log + ")";
  if (log.empty() || message.find(tag) != std::string::npos) return message;
  return message + (message.empty() ? "" : " ") + tag;
}

} // namespace pnc
