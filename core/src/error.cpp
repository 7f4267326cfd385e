#include "pnc/core/error.hpp"

#include "pnc/core/params.hpp"

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
} // namespace

InputError::InputError(ErrorContext ctx)
    : std::runtime_error(format_message(ctx)), ctx_(std::move(ctx)) {}

void fail(std::string source, std::string field, std::string value, std::string rule) {
  throw InputError(
      ErrorContext{std::move(source), std::move(field), std::move(value), std::move(rule)});
}

} // namespace pnc
