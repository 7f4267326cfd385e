#pragma once
// pnc/core/error.hpp: errors that name what broke.
//
// Every user-facing failure in pnc is an InputError: it names the file (or other source),
// the field (column, key, dataset), the offending value and the rule it broke, so that the
// one-line message printed by the CLI is enough to fix the input.
#include <stdexcept>
#include <string>

namespace pnc {

struct ErrorContext {
  std::string source; ///< file path or other origin ("<command line>", "<card>")
  std::string field;  ///< column, key or dataset name; may be empty
  std::string value;  ///< offending value as text; may be empty
  std::string rule;   ///< the rule that was broken
};

class InputError : public std::runtime_error {
public:
  explicit InputError(ErrorContext ctx);
  const ErrorContext& context() const noexcept { return ctx_; }

private:
  ErrorContext ctx_;
};

/// Throws InputError built from the four parts.
[[noreturn]] void fail(std::string source, std::string field, std::string value, std::string rule);

} // namespace pnc
