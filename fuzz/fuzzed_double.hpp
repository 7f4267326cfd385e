#pragma once
// fuzz/fuzzed_double.hpp: the doubles the plugin targets (fuzz_material, fuzz_umat) feed in.
#include <fuzzer/FuzzedDataProvider.h>

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

} // namespace pnc::fuzz
