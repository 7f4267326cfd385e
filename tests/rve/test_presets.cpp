// The presets derive from each other as JSON merge patches (rve/src/presets.cpp): every preset,
// as `pnc recipe show NAME` prints it and fully expanded, must equal what the hand-written
// literals gave before the patches. tests/rve/data/presets_before_patches.json holds those
// outputs (written by `pnc recipe show NAME` and `pnc recipe show NAME --expanded` before the
// refactor); the comparison is on the printed text, so an integer that became a float (or a
// key that moved) fails too.
#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"
#include "pnc/rve/recipe.hpp"

#include "common/run_command.hpp"
#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

using json = nlohmann::json;

namespace {
json fixture() {
  std::ifstream f(std::string(PNC_SOURCE_DIR) + "/tests/rve/data/presets_before_patches.json");
  return json::parse(f);
}
} // namespace

// Presets added after the refactor to patches, each checked by a test of its own below.
const std::vector<std::string> kAddedLater = {"card_glass"};

TEST(RvePresets, EveryPresetEqualsItsLiteralBeforeThePatches) {
  const json before = fixture();
  std::vector<std::string> names;
  for (const auto& [name, v] : before.items())
    names.push_back(name);
  names.insert(names.end(), kAddedLater.begin(), kAddedLater.end());
  std::sort(names.begin(), names.end());
  auto sorted = pnc::rve::preset_names();
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(names, sorted);
  for (const auto& name : pnc::rve::preset_names()) {
    if (std::find(kAddedLater.begin(), kAddedLater.end(), name) != kAddedLater.end()) continue;
    ASSERT_TRUE(before.contains(name)) << name;
    const json p = pnc::rve::preset_json(name);
    EXPECT_EQ(p.dump(2), before.at(name).at("preset").dump(2)) << name;
    const json e = pnc::rve::expanded_json(pnc::rve::parse_recipe(p, name));
    EXPECT_EQ(e.dump(2), before.at(name).at("expanded").dump(2)) << name;
  }
}

// card_glass is demo_glass with the protocol of the measured 24-replica run of docs/rve.md
// ("24 replicas"), its shears in both senses (D424), fitted over a stretch of 0.03 with 48
// replicas (D421), and nothing else changed: the expanded recipes differ in exactly these keys.
TEST(RvePresets, CardGlassIsDemoGlassWithTheMeasuredProtocolAndNothingElse) {
  const auto expanded = [](const std::string& n) {
    return pnc::rve::expanded_json(pnc::rve::parse_recipe(pnc::rve::preset_json(n), n));
  };
  json want = expanded("demo_glass");
  want["name"] = "card_glass";
  want["deform"]["cases"] = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  want["deform"]["strain_max"] = 0.05;
  want["deform"]["shear_strain_max"] = 0.10;
  want["deform"]["steps"] = 72;
  want["deform"]["hold_steps"] = 600;
  want["fit"].erase("strain_max");
  want["fit"]["stretch_max"] = 0.03;
  want["run"]["replicas"] = 48;
  EXPECT_EQ(expanded("card_glass"), want);
}

// The declared recipe keys (recipe_parameters.cpp): the TOML template of each model, read as a
// recipe file, is the recipe of that model's defaults; every key of the expanded recipe is
// declared; the declared ranges are the ones parse_recipe enforces (one value just inside and
// one just outside each bound of a few keys).
TEST(RvePresets, ParameterTemplatesReadBackAsTheDefaultRecipe) {
  namespace fs = std::filesystem;
  const fs::path dir = pnc::test::fresh_dir("recipe_template");
  for (const std::string model : {"pp", "pnc", "kg", "kg_platelet"}) {
    const auto p = dir / ("pnc_recipe_template_" + model + ".toml");
    std::ofstream(p) << pnc::rve::recipe_parameters(model).to_toml();
    json minimal = {{"model", model}};
    if (model == "pnc") minimal["clay"] = json::object(); // pnc needs its clay block
    const auto want = pnc::rve::expanded_json(pnc::rve::parse_recipe(minimal, "x"));
    EXPECT_EQ(pnc::rve::expanded_json(pnc::rve::read_recipe(p.string())), want) << model;
    // every key of the expanded recipe is a declared one of this model
    const auto decl = pnc::rve::recipe_parameters(model);
    for (const auto& [section, v] : want.items()) {
      if (!v.is_object()) {
        EXPECT_NO_THROW(decl.at(section)) << section;
        continue;
      }
      for (const auto& [key, x] : v.items())
        EXPECT_NO_THROW(decl.at(section + "." + key)) << model << ": " << section << "." << key;
    }
    fs::remove(p);
  }
  fs::remove(dir);
}

TEST(RvePresets, DeclaredBoundsAreTheEnforcedOnes) {
  struct Case {
    const char* section;
    const char* key;
    json inside, outside;
  };
  const std::vector<Case> cases = {
      {"deform", "timestep_fs", 50.0, 50.000001},
      {"deform", "reference_holds", 1000, 1001},
      {"build", "density", 2.99, 3.0},
      {"phase_check", "shear_strain", 0.1, 0.1001},
      {"equilibrate", "pushoff_steps", 100, 99},
      {"fit", "strain_max", 10.0, 10.5},
      {"equilibrate", "pressure_atm", -1e5, -1.0001e5},
      {"run", "replicas", 64, 65},
  };
  for (const auto& c : cases) {
    json j = {{c.section, {{c.key, c.inside}}}};
    if (std::string(c.section) == "deform" && std::string(c.key) == "timestep_fs")
      j["deform"]["hold_steps"] = 1000;
    EXPECT_NO_THROW(pnc::rve::parse_recipe(j, "r.json")) << j.dump();
    j[c.section][c.key] = c.outside;
    try {
      pnc::rve::parse_recipe(j, "r.json");
      ADD_FAILURE() << "accepted " << j.dump();
    } catch (const pnc::InputError& e) {
      const std::string field = std::string(c.section) + "." + c.key;
      EXPECT_EQ(e.context().field, field);
      EXPECT_EQ(e.context().rule, pnc::rve::recipe_parameters("pp").at(field).rule());
    }
  }
}

// Recipes beyond the presets whose expanded form (what run directories store and --resume
// compares) was written to tests/rve/data/expanded_before_declarations.json before
// expanded_json() was derived from the declarations: the two must agree as printed text.
namespace {
const std::vector<std::pair<std::string, json>>& expansion_inputs() {
  static const std::vector<std::pair<std::string, json>> in = {
      {"empty", json::object()},
      {"pp_fit_alpha_hold", json::parse(R"({"fit": {"hold_alpha": true, "alpha": 0.9,
          "strain_max": 0.05}, "deform": {"cases": [1, 4]}, "name": "x", "seed": 7})")},
      {"pnc_aspect", json::parse(R"({"model": "pnc", "clay": {"aspect_ratio": 4.19},
          "build": {"chains": 75}})")},
      {"pnc_cells", json::parse(R"({"model": "pnc", "clay": {"cells_a": 3, "gap_x": 12.5},
          "build": {"chains": 30}, "equilibrate": {"clay_steps": 100}})")},
      {"kg", json::parse(R"({"model": "kg", "forcefield": {"sigma": 4.0, "bond_length_sigma":
          0.95}, "build": {"chains": 40, "min_distance": 3.0}, "fit": {"fit_alpha": true}})")},
      {"kg_platelet", json::parse(R"({"model": "kg_platelet", "build": {"chains": 32,
          "min_distance": 3.5}, "forcefield": {"sigma": 5.0}, "platelet": {"beads_side": 6},
          "equilibrate": {"timestep_fs": 10.0}, "deform": {"timestep_fs": 10.0},
          "analysis": {"stress": "virial", "reference": "none", "moving_average": 5},
          "run": {"jobs": 3, "replicas": 2}})")},
  };
  return in;
}
} // namespace

TEST(RvePresets, ExpandedRecipesEqualTheirFormBeforeTheDeclarations) {
  std::ifstream f(std::string(PNC_SOURCE_DIR) +
                  "/tests/rve/data/expanded_before_declarations.json");
  const json before = json::parse(f);
  for (const auto& [name, recipe] : expansion_inputs()) {
    const json e = pnc::rve::expanded_json(pnc::rve::parse_recipe(recipe, name));
    ASSERT_TRUE(before.contains(name)) << name;
    EXPECT_EQ(e.dump(2), before.at(name).dump(2)) << name;
  }
}

// Models pnc and kg_platelet default to cases 1-6, also in a recipe with your own system
// (the declarations read there are the system's, the default the model's).
TEST(RvePresets, CaseDefaultsFollowTheModelAlsoWithYourOwnSystem) {
  const std::string path = std::string(PNC_SOURCE_DIR) + "/examples/rve/lj_fcc/recipe.toml";
  std::ifstream f(path);
  const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  json j = pnc::parse_toml(text, path);
  j["deform"].erase("cases");
  EXPECT_EQ(pnc::rve::parse_recipe(j, path).cases, (std::vector<int>{2, 6}));
  j["model"] = "pnc";
  EXPECT_EQ(pnc::rve::parse_recipe(j, path).cases, (std::vector<int>{1, 2, 3, 4, 5, 6}));
}

// `pnc recipe parameters` prints the declarations: JSON (every entry of every variant), a TOML
// template of one model (pp unless --model), Markdown tables; a bad --format is refused.
TEST(RvePresets, RecipeParametersCommandPrintsTheDeclarations) {
  const auto run = [](const std::string& args) {
    return pnc::test::run_command(std::string(PNC_EXE) + " recipe parameters " + args);
  };
  const auto j = run("--format json");
  ASSERT_EQ(j.code, 0);
  EXPECT_EQ(json::parse(j.out), pnc::rve::recipe_parameters("").to_json());
  const auto kg = run("--format toml --model kg");
  ASSERT_EQ(kg.code, 0);
  EXPECT_EQ(kg.out, pnc::rve::recipe_parameters("kg").to_toml());
  EXPECT_EQ(run("--format toml").out, pnc::rve::recipe_parameters("pp").to_toml());
  const auto md = run("--model kg_platelet");
  ASSERT_EQ(md.code, 0);
  EXPECT_EQ(md.out, pnc::rve::recipe_parameters("kg_platelet").to_markdown(3));
  EXPECT_EQ(md.out.find("`clay`"), std::string::npos); // not a section of this model
  EXPECT_NE(run("--format yaml 2>/dev/null").code, 0);
}
