#include "material_plugin.hpp"

#include "pnc/core/locate.hpp"

#include "pnc/core/error.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

namespace pnc::app {

namespace fs = std::filesystem;

namespace {
constexpr const char* kSoname = "libpnc_material.so.1";
} // namespace

std::string find_material_plugin(const std::string& option) {
  if (!option.empty()) {
    if (!fs::exists(option))
      fail("<command line>", "--plugin", option, "the material plugin file does not exist");
    return option;
  }
  if (const char* env = std::getenv("PNC_MATERIAL_PLUGIN"); env && *env) {
    if (!fs::exists(env))
      fail("<environment>", "PNC_MATERIAL_PLUGIN", env, "the material plugin file does not exist");
    return env;
  }
  const fs::path dir = pnc::executable_dir(); // pnc/core/locate.hpp
  std::vector<fs::path> candidates;
  if (!dir.empty()) {
    candidates.push_back(dir / ".." / "fe_material" / kSoname); // build tree: <build>/app/pnc
    candidates.push_back(dir / ".." / "lib" / kSoname);         // install: <prefix>/bin/pnc
#ifdef PNC_MULTIARCH
    candidates.push_back(dir / ".." / "lib" / PNC_MULTIARCH / kSoname);
#endif
  }
  std::string looked;
  for (const auto& c : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(c, ec)) return fs::weakly_canonical(c, ec).string();
    looked += (looked.empty() ? "" : ", ") + c.lexically_normal().string();
  }
  fail("<plugin lookup>", "libpnc_material.so.1", looked.empty() ? "(no executable path)" : looked,
       "the material plugin was not found next to this executable; pass --plugin PATH or set "
       "PNC_MATERIAL_PLUGIN");
}

pnc::fe_material::Plugin load_material_plugin(const std::string& option) {
  const std::string path = find_material_plugin(option);
  try {
    return pnc::fe_material::Plugin(path);
  } catch (const pnc::fe_material::Error& e) {
    fail(path, "", "", e.what());
  }
}

pnc::fe_material::Material load_card(const pnc::fe_material::Plugin& plugin,
                                     const std::string& card, bool allow_not_usable) {
  try {
    return plugin.from_card(card, allow_not_usable);
  } catch (const pnc::fe_material::Error& e) {
    // the plugin's message already names the card, the field, the value and the rule
    std::string msg = e.what();
    if (msg.rfind(card + ": ", 0) == 0) msg = msg.substr(card.size() + 2);
    fail(card, "", "", msg);
  }
}

} // namespace pnc::app
