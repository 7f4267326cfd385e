// The presets derive from each other as JSON merge patches (rve/src/presets.cpp): every preset,
// as `pnc recipe show NAME` prints it and fully expanded, must equal what the hand-written
// literals gave before the patches. tests/rve/data/presets_before_patches.json holds those
// outputs (written by `pnc recipe show NAME` and `pnc recipe show NAME --expanded` before the
// refactor); the comparison is on the printed text, so an integer that became a float (or a
// key that moved) fails too.
#include "pnc/rve/recipe.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>

using json = nlohmann::json;

namespace {
json fixture() {
  std::ifstream f(std::string(PNC_SOURCE_DIR) + "/tests/rve/data/presets_before_patches.json");
  return json::parse(f);
}
} // namespace

TEST(RvePresets, EveryPresetEqualsItsLiteralBeforeThePatches) {
  const json before = fixture();
  std::vector<std::string> names;
  for (const auto& [name, v] : before.items())
    names.push_back(name);
  auto sorted = pnc::rve::preset_names();
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(names, sorted); // json objects iterate in key order
  for (const auto& name : pnc::rve::preset_names()) {
    ASSERT_TRUE(before.contains(name)) << name;
    const json p = pnc::rve::preset_json(name);
    EXPECT_EQ(p.dump(2), before.at(name).at("preset").dump(2)) << name;
    const json e = pnc::rve::expanded_json(pnc::rve::parse_recipe(p, name));
    EXPECT_EQ(e.dump(2), before.at(name).at("expanded").dump(2)) << name;
  }
}
