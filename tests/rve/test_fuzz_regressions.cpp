// Inputs fuzz_recipe_json and fuzz_recipe_toml found (fuzz/regressions/recipe_*/), read
// through read_recipe: each must be refused with a clean pnc::InputError.
#include "common/fuzz_regressions.hpp"

#include "pnc/rve/recipe.hpp"

TEST(FuzzRegressions, JsonRecipesAreRefusedCleanly) {
  pnc::test::expect_regressions_refused(
      "recipe_json", [](const std::string& f) { (void)pnc::rve::read_recipe(f); });
}

TEST(FuzzRegressions, TomlRecipesAreRefusedCleanly) {
  pnc::test::expect_regressions_refused(
      "recipe_toml", [](const std::string& f) { (void)pnc::rve::read_recipe(f); });
}
