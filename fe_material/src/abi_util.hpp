#pragma once
// Helpers shared by the C ABI and the UMAT shim (internal to the plugin).
#include <cmath>
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

/// Index of the first non-finite entry of x[0..n-1], or -1.
inline int first_non_finite(const double* x, int n) noexcept {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(x[i])) return i;
  return -1;
}

/// A bad entry found by check_state() or check_result(); empty (what == nullptr) when all
/// entries are fine. Each entry point prints it in its own words (argument names differ).
struct Finding {
  const char* what = nullptr; ///< "state", "stress", "tangent"
  int index = -1;             ///< 0-based entry
  double value = 0.0;
  const char* rule = nullptr;
  explicit operator bool() const noexcept { return what != nullptr; }
};

constexpr const char* kStateRule = "state variables must be finite";
constexpr const char* kResultRule =
    "the increment gives a non-finite result (the strain is beyond what the law can represent "
    "in double precision); nothing was written";

/// The state at the start of an increment (n entries): every entry finite. Both entry points
/// (pnc_material_integrate, umat_) call it before the kernel.
inline Finding check_state(const double* state, int n) noexcept {
  const int i = first_non_finite(state, n);
  if (i >= 0) return {"state", i, state[i], kStateRule};
  return {};
}

/// The result of an increment: stress (6 entries), end state (n) and tangent (36, or NULL)
/// all finite. Both entry points call it before writing anything to the caller.
inline Finding check_result(const double* stress, const double* state, int n,
                            const double* tangent) noexcept {
  int i = first_non_finite(stress, 6);
  if (i >= 0) return {"stress", i, stress[i], kResultRule};
  i = first_non_finite(state, n);
  if (i >= 0) return {"state", i, state[i], kResultRule};
  if (tangent) {
    i = first_non_finite(tangent, 36);
    if (i >= 0) return {"tangent", i, tangent[i], kResultRule};
  }
  return {};
}

} // namespace pnc::fe_material::detail
