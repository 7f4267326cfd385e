#pragma once
// fuzz/fuzzed_double.hpp: what the plugin targets (fuzz_material, fuzz_umat) share: the doubles
// they feed in and the canary values that show which outputs a call wrote.
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdint>
#include <cstring>

namespace pnc::fuzz {

/// A double that is mostly `base` scaled by a factor in [-2, 3], and now and then anything
/// finite (huge or tiny), zero, or any bit pattern (NaN, inf, denormals).
inline double fuzzed(FuzzedDataProvider& in, double base) {
  switch (in.ConsumeIntegralInRange<int>(0, 7)) {
  case 0:
    return in.ConsumeFloatingPoint<double>();
  case 1: {
    std::uint64_t bits = in.ConsumeIntegral<std::uint64_t>();
    double d;
    std::memcpy(&d, &bits, sizeof d);
    return d;
  }
  case 2:
    return 0.0;
  default:
    return base * in.ConsumeFloatingPointInRange<double>(-2.0, 3.0);
  }
}

/// Fills v[0..n) with canaries base, base - 1, ... (values no integration can return exactly).
inline void fill_canary(double* v, int n, double base) {
  for (int i = 0; i < n; ++i)
    v[i] = base - i;
}
/// True when v[from..to) still holds the canaries of fill_canary(v, ., base).
inline bool is_canary(const double* v, int from, int to, double base) {
  for (int i = from; i < to; ++i)
    if (v[i] != base - i) return false;
  return true;
}
inline bool all_finite(const double* v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

} // namespace pnc::fuzz
