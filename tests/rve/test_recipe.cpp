// Recipes: presets parse and validate; invalid recipes name the field, the value and the rule.
#include "pnc/core/error.hpp"
#include "pnc/rve/recipe.hpp"

#include <gtest/gtest.h>

using namespace pnc::rve;
using json = nlohmann::json;

namespace {
pnc::ErrorContext error_of(const json& j) {
  try {
    parse_recipe(j, "r.json");
  } catch (const pnc::InputError& e) {
    return e.context();
  }
  ADD_FAILURE() << "expected an InputError for " << j.dump();
  return {};
}
} // namespace

TEST(RveRecipe, PresetsParse) {
  const Recipe demo = parse_recipe(preset_json("demo"), "demo");
  EXPECT_EQ(demo.name, "demo");
  EXPECT_EQ(demo.build.chains * demo.build.beads_per_chain, 600);
  EXPECT_EQ(demo.cases, (std::vector<int>{2, 6}));
  const Recipe paper = parse_recipe(preset_json("paper"), "paper");
  EXPECT_EQ(paper.build.chains * paper.build.beads_per_chain, 1500);
  EXPECT_EQ(paper.equilibrate.ensemble, "npt");
  EXPECT_DOUBLE_EQ(paper.equilibrate.pressure_atm, 0.0);
  EXPECT_DOUBLE_EQ(paper.deform.timestep_fs, 0.5); // section 6.3
  EXPECT_EQ(paper.deform.hold_steps, 10000);       // 5 ps
  EXPECT_EQ(paper.deform.sample_every, 10);        // 5 fs
  EXPECT_EQ(paper.moving_average, 13);
  EXPECT_EQ(paper.stress, "virial"); // eq. 6.23 by default
  // the expanded form parses back to the same expanded form
  EXPECT_EQ(expanded_json(parse_recipe(expanded_json(paper), "x")), expanded_json(paper));
  EXPECT_THROW(preset_json("nope"), pnc::InputError);
}

TEST(RveRecipe, InvalidRecipesNameFieldValueRule) {
  auto e = error_of(json{{"build", {{"density", -1.0}}}});
  EXPECT_EQ(e.source, "r.json");
  EXPECT_EQ(e.field, "build.density");
  EXPECT_EQ(e.value, "-1");
  EXPECT_FALSE(e.rule.empty());
  e = error_of(json{{"deform", {{"cases", {2, 9}}}}});
  EXPECT_EQ(e.field, "deform.cases");
  EXPECT_EQ(e.value, "9");
  e = error_of(json{{"deform", {{"strain_max", "0.1"}}}});
  EXPECT_EQ(e.field, "deform.strain_max");
  EXPECT_EQ(e.rule, "must be a number");
  e = error_of(json{{"equilibrate", {{"ensemble", "nph"}}}});
  EXPECT_EQ(e.field, "equilibrate.ensemble");
  e = error_of(json{{"deform", {{"stran_max", 0.1}}}});
  EXPECT_EQ(e.field, "deform.stran_max");
  EXPECT_NE(e.rule.find("unknown key"), std::string::npos);
  e = error_of(json{{"analysis", {{"moving_average", 4}}}});
  EXPECT_EQ(e.field, "analysis.moving_average");
  e = error_of(json{{"model", "pnc"}});
  EXPECT_EQ(e.field, "model"); // clay builder not there yet: said, not faked
  e = error_of(json{{"build", {{"chains", 2}}}});
  EXPECT_EQ(e.field, "build.chains"); // box smaller than twice the cutoff
  e = error_of(json{{"deform", {{"cases", {1}}}}});
  EXPECT_EQ(e.field, "deform.cases"); // pp uses cases 2 and 6
  e = error_of(json{{"deform", {{"hold_steps", 50}}}});
  EXPECT_EQ(e.field, "deform.hold_steps");
}
