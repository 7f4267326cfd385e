#pragma once
// CLI11 validators of numeric options: every number option has a stated range, and a
// floating-point option refuses NaN and infinities (CLI::Range lets NaN through: every
// comparison with NaN is false).
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace pnc::app {

/// A finite number in [lo, hi], or in (lo, hi] with lo_open.
inline CLI::Validator FiniteRange(double lo, double hi, bool lo_open = false) {
  char b[96];
  std::snprintf(b, sizeof b, "%c%.6g, %.6g]", lo_open ? '(' : '[', lo, hi);
  const std::string range = b;
  return CLI::Validator(
      [lo, hi, lo_open, range](std::string& in) -> std::string {
        const char* s = in.c_str();
        char* e = nullptr;
        const double x = std::strtod(s, &e);
        if (e == s || *e != '\0') return "Value " + in + " is not a number";
        if (!std::isfinite(x)) return "Value " + in + " is not finite: must be in " + range;
        if (x < lo || x > hi || (lo_open && x == lo))
          return "Value " + in + " not in range " + range;
        return std::string();
      },
      "FINITE in " + range, "FINITE");
}

/// A finite number in (0, hi].
inline CLI::Validator FinitePositive(double hi) {
  return FiniteRange(0.0, hi, true);
}

} // namespace pnc::app
