#pragma once
// What the kernel does with huge-page advice (D430), for the tests: whether it can collapse
// (transparent huge pages not "never", Linux >= 6.1), how many kB of huge pages back an address
// range (read from /proc/self/smaps), and whether PNC_HUGE_PAGES=0 switched the advice off.
#include <sys/utsname.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

namespace pnc::test {

/// The kernel's transparent huge page mode: "always", "madvise", "never" ("" when unknown).
inline std::string thp_mode() {
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  if (!std::getline(f, line)) return "";
  const auto a = line.find('['), b = line.find(']');
  return a == std::string::npos || b == std::string::npos ? "" : line.substr(a + 1, b - a - 1);
}

/// Whether this kernel backs advised memory with transparent huge pages and collapses on
/// request: THP not "never" and Linux >= 6.1.
inline bool kernel_can_collapse() {
  const std::string mode = thp_mode();
  if (mode.empty() || mode == "never") return false;
  utsname u{};
  if (::uname(&u) != 0) return false;
  int major = 0, minor = 0;
  if (std::sscanf(u.release, "%d.%d", &major, &minor) != 2) return false;
  return major > 6 || (major == 6 && minor >= 1);
}

/// kB of AnonHugePages in the mappings of /proc/self/smaps that overlap [lo, hi).
inline long huge_kb_in(std::uintptr_t lo, std::uintptr_t hi) {
  std::ifstream f("/proc/self/smaps");
  std::string line;
  bool inside = false;
  long kb = 0;
  while (std::getline(f, line)) {
    std::uintptr_t a = 0, b = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> a >> dash >> b && dash == '-') {
      inside = a < hi && b > lo;
      continue;
    }
    long v = 0;
    if (inside && std::sscanf(line.c_str(), "AnonHugePages: %ld kB", &v) == 1) kb += v;
  }
  return kb;
}

inline bool huge_pages_switched_off() {
  const char* v = std::getenv("PNC_HUGE_PAGES");
  return v && std::strcmp(v, "0") == 0;
}

/// kB of huge pages over a vector's elements.
template <class V> long huge_kb_of(const V& v) {
  const auto lo = reinterpret_cast<std::uintptr_t>(v.data());
  return huge_kb_in(lo, lo + v.size() * sizeof(v[0]));
}

} // namespace pnc::test
