#pragma once
// Helpers shared by the C ABI and the UMAT shim (internal to the plugin).
#include <cstddef>
#include <cstring>

namespace pnc::fe_material::detail {

/// Copies a message into a caller-owned buffer (may be NULL / 0), always NUL-terminated.
inline void copy_message(char* dst, std::size_t len, const char* text) noexcept {
  if (!dst || len == 0) return;
  if (!text) text = "";
  const std::size_t n = std::strlen(text);
  const std::size_t k = n < len - 1 ? n : len - 1;
  std::memcpy(dst, text, k);
  dst[k] = '\0';
}

} // namespace pnc::fe_material::detail
