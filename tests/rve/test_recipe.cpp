// Recipes: presets parse and validate; invalid recipes name the field, the value and the rule.
#include "pnc/core/error.hpp"
#include "pnc/rve/recipe.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

using namespace pnc::rve;
using namespace pnc::md;
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
  EXPECT_DOUBLE_EQ(paper.deform.timestep_fs,
                   0.5); // the source's hold time step (docs/rve.md, paper preset)
  EXPECT_EQ(paper.deform.hold_steps, 10000); // 5 ps
  EXPECT_EQ(paper.deform.sample_every, 10);  // 5 fs
  EXPECT_EQ(paper.moving_average, 1);        // no smoothing in the fit data (D133)
  EXPECT_EQ(paper.stress, "virial"); // the dissertation's virial-only stress (docs/theory.md §3.5),
                                     // said so in the preset
  EXPECT_EQ(demo.stress, "total"); // everything else: the total stress (D134)
  EXPECT_EQ(parse_recipe(json::object(), "x").stress, "total");
  EXPECT_EQ(parse_recipe(json::object(), "x").replicas, 1);
  for (const auto& n : preset_names()) {
    const Recipe p = parse_recipe(preset_json(n), n);
    EXPECT_EQ(p.moving_average, 1) << n;
    EXPECT_TRUE(preset_json(n)["analysis"].contains("stress")) << n; // each says which
  }
  EXPECT_EQ(parse_recipe(json{{"run", {{"replicas", 64}}}}, "x").replicas, 64);
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
  e = error_of(json{{"deform", {{"cases", {2, 10}}}}}); // ids 1..9 (D424)
  EXPECT_EQ(e.field, "deform.cases");
  EXPECT_EQ(e.value, "10");
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
  EXPECT_EQ(e.field, "model"); // "pnc" needs a clay block naming the platelet
  e = error_of(json{{"build", {{"chains", 2}}}});
  EXPECT_EQ(e.field, "build.chains"); // box smaller than twice the cutoff
  e = error_of(json{{"deform", {{"cases", {4, 6}}}}});
  EXPECT_EQ(e.field, "deform.cases"); // pp needs an extension case (1-3)
  EXPECT_EQ(parse_recipe(json{{"deform", {{"cases", {1, 3, 5}}}}}, "r.json").cases,
            (std::vector<int>{1, 3, 5})); // any extension case pools with the shears (D12l)
  e = error_of(json{{"deform", {{"hold_steps", 50}}}});
  EXPECT_EQ(e.field, "deform.hold_steps");
  for (const int bad : {0, 65}) {
    e = error_of(json{{"run", {{"replicas", bad}}}});
    EXPECT_EQ(e.field, "run.replicas");
    EXPECT_EQ(e.value, std::to_string(bad));
  }
  e = error_of(json{{"deform", {{"reference_holds", 0}}}});
  EXPECT_EQ(e.field, "deform.reference_holds");
}

namespace {
/// This process's folder for the recipe files of these tests (fresh_dir: new and private).
const std::filesystem::path& scratch() {
  static const std::filesystem::path d = pnc::test::fresh_dir("test_recipe");
  return d;
}
std::string write_temp(const std::string& name, const std::string& text) {
  const auto p = scratch() / name;
  std::ofstream(p) << text;
  return p.string();
}
} // namespace

// A TOML recipe with the same tables and keys as a JSON one is the same recipe: the two
// expanded forms are compared field by field (independent of parse order).
TEST(RveRecipe, TomlAndJsonGiveTheSameRecipe) {
  const std::string toml_text = R"(name = "t"
seed = 7
model = "pp"
[build]
chains = 40
density = 0.9
[deform]
cases = [2, 6]
strain_max = 0.05
[analysis]
moving_average = 5
)";
  const json j = {{"name", "t"},
                  {"seed", 7},
                  {"model", "pp"},
                  {"build", {{"chains", 40}, {"density", 0.9}}},
                  {"deform", {{"cases", {2, 6}}, {"strain_max", 0.05}}},
                  {"analysis", {{"moving_average", 5}}}};
  const auto tp = write_temp("pnc_recipe_test.toml", toml_text);
  const auto jp = write_temp("pnc_recipe_test.json", j.dump());
  const Recipe a = read_recipe(tp), b = read_recipe(jp);
  EXPECT_EQ(expanded_json(a), expanded_json(b));
  EXPECT_EQ(a.build.chains, 40);
  EXPECT_DOUBLE_EQ(a.deform.strain_max, 0.05);
  std::remove(tp.c_str());
  std::remove(jp.c_str());
}

TEST(RveRecipe, TomlErrorsNameTheFileAndTheField) {
  const auto bad_syntax = write_temp("pnc_recipe_bad1.toml", "[build\nchains = 3\n");
  try {
    read_recipe(bad_syntax);
    ADD_FAILURE() << "expected an InputError";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().source, bad_syntax);
    EXPECT_NE(e.context().rule.find("TOML"), std::string::npos);
  }
  const auto bad_value = write_temp("pnc_recipe_bad2.toml", "[build]\ndensity = -1.0\n");
  try {
    read_recipe(bad_value);
    ADD_FAILURE() << "expected an InputError";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().source, bad_value);
    EXPECT_EQ(e.context().field, "build.density");
  }
  const auto bad_date = write_temp("pnc_recipe_bad3.toml", "seed = 1979-05-27\n");
  try {
    read_recipe(bad_date);
    ADD_FAILURE() << "expected an InputError";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().field, "seed");
  }
  EXPECT_THROW(read_recipe(write_temp("pnc_recipe_bad4.yaml", "a: 1\n")), pnc::InputError);
  for (const char* n : {"pnc_recipe_bad1.toml", "pnc_recipe_bad2.toml", "pnc_recipe_bad3.toml",
                        "pnc_recipe_bad4.yaml"})
    std::filesystem::remove(scratch() / n);
}

// Every preset, printed as TOML (what `pnc recipe show NAME --toml` prints, plain and
// expanded), reads back as the same recipe.
TEST(RveRecipe, PresetsRoundTripThroughToml) {
  for (const auto& name : preset_names()) {
    const Recipe ref = parse_recipe(preset_json(name), name);
    for (const json& form : {preset_json(name), expanded_json(ref)}) {
      const auto p = write_temp("pnc_recipe_rt.toml", recipe_toml(form));
      EXPECT_EQ(expanded_json(read_recipe(p)), expanded_json(ref)) << name;
      std::filesystem::remove(p);
    }
  }
}

// Free text of a recipe ends up in the first line of a LAMMPS data file, in logs and reports:
// one line of printable ASCII, bounded length; the error names the field.
TEST(RveRecipe, NameMustBeOneBoundedLineOfPrintableText) {
  for (const std::string& bad :
       {std::string("demo\nAtoms # full"), std::string("tab\there"), std::string("cr\r"),
        std::string(""), std::string(kMaxTextChars + 1, 'n'), std::string("nul\0x", 5),
        std::string("del\x7f")}) {
    const auto e = error_of(json{{"name", bad}});
    EXPECT_EQ(e.source, "r.json");
    EXPECT_EQ(e.field, "name") << e.rule;
    EXPECT_FALSE(e.rule.empty());
    // the value shown in the message is itself one printable line
    for (char c : e.value)
      EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "control character echoed in " << e.value;
  }
  // at the limit, with blanks and punctuation: fine
  const std::string ok = std::string(kMaxTextChars - 6, 'x') + " (a-b)";
  EXPECT_EQ(parse_recipe(json{{"name", ok}}, "r.json").name, ok);
}

TEST(RveRecipe, DataFileTitleWithANewlineIsRefused) {
  const auto d = pnc::test::fresh_dir("test_recipe_title");
  const std::string data = (d / "rve.data").string();
  System s; // an empty system is enough: the title is checked first
  try {
    write_data_file(data, s, "demo\n1000000 atoms");
    ADD_FAILURE() << "expected an InputError";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().source, data);
    EXPECT_EQ(e.context().field, "title");
  }
  EXPECT_FALSE(std::filesystem::exists(data));
  std::filesystem::remove_all(d);
}

// Integers are read with a range and never narrowed: 4294967326 (2^32 + 30) is not 30 chains,
// 4294967298 (2^32 + 2) is not case 2; the same in TOML.
TEST(RveRecipe, IntegersOutsideTheirRangeAreRefusedNotWrapped) {
  auto e = error_of(json::parse(R"({"build": {"chains": 4294967326}})"));
  EXPECT_EQ(e.field, "build.chains");
  EXPECT_EQ(e.value, "4294967326");
  EXPECT_EQ(e.rule, "must be an integer in [1, 100000]");
  e = error_of(json::parse(R"({"deform": {"cases": [4294967298, 6]}})"));
  EXPECT_EQ(e.field, "deform.cases");
  EXPECT_EQ(e.value, "4294967298");
  e = error_of(json::parse(R"({"deform": {"hold_steps": 18446744073709551615}})"));
  EXPECT_EQ(e.field, "deform.hold_steps");
  EXPECT_EQ(e.value, "18446744073709551615");
  e = error_of(json::parse(R"({"seed": 2.0})"));
  EXPECT_EQ(e.field, "seed");
  e = error_of(json::parse(R"({"build": {"chains": 1000, "beads_per_chain": 5000}})"));
  EXPECT_EQ(e.field, "build.chains"); // 5e6 beads: above the 1e6 of one RVE
  EXPECT_NE(e.rule.find("at most 1000000"), std::string::npos) << e.rule;
  const auto toml = write_temp("pnc_recipe_wrap.toml", "[build]\nchains = 4294967326\n");
  try {
    read_recipe(toml);
    ADD_FAILURE() << "accepted";
  } catch (const pnc::InputError& x) {
    EXPECT_EQ(x.context().field, "build.chains");
    EXPECT_EQ(x.context().value, "4294967326");
  }
  std::filesystem::remove(toml);
}

// Deep nesting (60000 levels) in a JSON or TOML recipe is an InputError naming the file and
// the limit, not a crash; so is a JSON number beyond a double.
TEST(RveRecipe, DeepNestingAndHugeNumbersAreInputErrors) {
  const std::string deep = std::string(60000, '[') + std::string(60000, ']');
  const std::vector<std::pair<std::string, std::string>> files = {
      {"pnc_recipe_deep.json", deep},
      {"pnc_recipe_deep2.json", "{\"name\": " + deep + "}"},
      {"pnc_recipe_deep.toml", "name = " + deep + "\n"},
      {"pnc_recipe_big.json", "{\"build\": {\"density\": 1e400}}"}};
  for (const auto& [name, text] : files) {
    const auto p = write_temp(name, text);
    try {
      read_recipe(p);
      ADD_FAILURE() << name << " accepted";
    } catch (const pnc::InputError& e) {
      EXPECT_EQ(e.context().source, p);
      const std::string want = name == "pnc_recipe_big.json" ? "not valid JSON" : "nest deeper";
      EXPECT_NE(e.context().rule.find(want), std::string::npos) << e.what();
      EXPECT_LT(std::string(e.what()).size(), 600u);
    }
    std::filesystem::remove(p);
  }
}

TEST(RveRecipe, ShearAmplitudeAndStretchRangeAreOptionalAndRoundTrip) {
  // decision D12m: deform.shear_strain_max drives cases 4-6 to their own gamma; fit.stretch_max
  // is the fit range by lambda_max - 1, exclusive with fit.strain_max
  const Recipe plain = parse_recipe(json::object(), "r.json");
  EXPECT_EQ(plain.deform.shear_strain_max, 0.0);
  EXPECT_FALSE(expanded_json(plain)["deform"].contains("shear_strain_max")); // unchanged recipes
  EXPECT_FALSE(expanded_json(plain)["fit"].contains("stretch_max"));
  const json j{{"deform", {{"cases", {1, 4}}, {"strain_max", 0.1}, {"shear_strain_max", 0.2}}},
               {"fit", {{"stretch_max", 0.08}}}};
  const Recipe r = parse_recipe(j, "r.json");
  EXPECT_DOUBLE_EQ(r.fit_stretch_max, 0.08);
  DeformSpec d = r.deform;
  d.case_id = 1;
  EXPECT_DOUBLE_EQ(d.amplitude(), 0.1);
  d.case_id = 4;
  EXPECT_DOUBLE_EQ(d.amplitude(), 0.2);
  const Recipe back = parse_recipe(expanded_json(r), "expanded");
  EXPECT_DOUBLE_EQ(back.deform.shear_strain_max, 0.2);
  EXPECT_DOUBLE_EQ(back.fit_stretch_max, 0.08);
  auto e = error_of(json{{"deform", {{"shear_strain_max", 0.7}}}});
  EXPECT_EQ(e.field, "deform.shear_strain_max");
  e = error_of(json{{"fit", {{"stretch_max", 0.08}, {"strain_max", 0.08}}}});
  EXPECT_EQ(e.field, "fit.stretch_max");
  e = error_of(json{{"fit", {{"stretch_max", -1.0}}}});
  EXPECT_EQ(e.field, "fit.stretch_max");
}

TEST(RveRecipe, FitIsotropicIsOfThePurePolymerModelsOnly) {
  // decision D396: fit.isotropic derives C44 and B4 of the pure-polymer law; off by default and
  // then absent from the expanded recipe
  const Recipe plain = parse_recipe(json::object(), "r.json");
  EXPECT_FALSE(plain.fit_isotropic);
  EXPECT_FALSE(expanded_json(plain)["fit"].contains("isotropic"));
  for (const char* model : {"pp", "kg"}) {
    json j = model == std::string("kg") ? preset_json("demo_glass") : json{{"model", "pp"}};
    j["fit"]["isotropic"] = true;
    const Recipe r = parse_recipe(j, "r.json");
    EXPECT_TRUE(r.fit_isotropic) << model;
    EXPECT_TRUE(parse_recipe(expanded_json(r), "expanded").fit_isotropic) << model;
  }
  json composite = preset_json("demo_pnc");
  composite["fit"]["isotropic"] = true;
  auto e = error_of(composite);
  EXPECT_EQ(e.field, "fit.isotropic");
  EXPECT_EQ(e.value, "true");
  EXPECT_NE(e.rule.find("models pp and kg"), std::string::npos) << e.rule;
  e = error_of(json{{"fit", {{"isotropic", 1}}}, {"model", "pp"}}); // not a boolean
  EXPECT_EQ(e.field, "fit.isotropic");
}
