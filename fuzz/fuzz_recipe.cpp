// Fuzz target: RVE recipes (pnc::rve::read_recipe: JSON or TOML text, then parse_recipe's
// validation). Built twice: PNC_FUZZ_SUFFIX ".json" (fuzz_recipe_json) and ".toml"
// (fuzz_recipe_toml); the extension selects the parser.
#include "fuzz_util.hpp"

#include "pnc/rve/recipe.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static pnc::fuzz::ScratchFile file(PNC_FUZZ_SUFFIX);
  const std::string& path = file.write(data, size);
  pnc::fuzz::expect_clean([&] { (void)pnc::rve::read_recipe(path); });
  return 0;
}
