// The registry of MD region kinds (md_region.hpp).
#include "md_region.hpp"

#include "pnc/core/error.hpp"

#include <map>
#include <stdexcept>

namespace pnc::gimp::escm {

namespace {

// Function-local: the registrations run during static initialisation of other files.
std::map<std::string, MdRegionFactory>& registry() {
  static std::map<std::string, MdRegionFactory> r;
  return r;
}

} // namespace

bool register_md_region(const std::string& kind, MdRegionFactory make) {
  if (!registry().emplace(kind, std::move(make)).second)
    throw std::logic_error("escm: MD region kind '" + kind + "' registered twice");
  return true;
}

bool md_region_known(const std::string& kind) {
  return registry().count(kind) > 0;
}

std::vector<std::string> md_region_kinds() {
  std::vector<std::string> k;
  for (const auto& [name, make] : registry())
    k.push_back(name);
  return k;
}

std::string md_region_kinds_text() {
  std::string s;
  std::size_t k = 0;
  const std::size_t n = registry().size();
  for (const auto& [name, make] : registry()) {
    if (k > 0) s += k + 1 == n ? " or " : ", ";
    s += "\"" + name + "\"";
    ++k;
  }
  return s.empty() ? std::string("none (this pnc was built without an MD region)") : s;
}

std::unique_ptr<MdRegion> make_md_region(const std::string& kind, const std::string& src) {
  const auto it = registry().find(kind);
  if (it == registry().end())
    fail(src, "md.type", "\"" + kind + "\"",
         "unknown MD region kind: " + md_region_kinds_text() + " in this build");
  return it->second();
}

} // namespace pnc::gimp::escm
