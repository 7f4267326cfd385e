// The declared keys of the `pnc gimp run` input (input_parameters.cpp, D290-D292): every kind
// of entry refused with the rule its declaration states, unknown keys refused naming the
// allowed ones and the nearest, the printed template read back gives the reader's defaults,
// and every example of examples/gimp/ is read by the declarations.
#include "pnc/gimp_coupler/input.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

using namespace pnc::gimp;
using json = nlohmann::json;

namespace {

// A complete 2-D input that leaves every key with a default out.
json minimal_input() {
  return json::parse(R"({
    "dimension": 2,
    "grid": {"cells": [24, 8], "cell_size": 0.05},
    "materials": [{"name": "poly", "type": "linear_elastic", "density": 1200,
                   "E": 1.5e9, "nu": 0.33}],
    "bodies": [{"material": "poly", "shape": "box", "min": [0.05, 0.1], "max": [1.05, 0.3]}],
    "boundaries": [{"min": [0.05, 0], "max": [0.05, 0.4], "fix": "all"}],
    "cracks": [{"points": [[0.3, 0.0], [0.3001, 0.2]]}],
    "time": {"end": 4e-4}
  })");
}

pnc::ErrorContext error_of(const json& j) {
  Solver<2> s;
  try {
    load_input_text<2>(j.dump(), "in.json", "", s);
  } catch (const pnc::InputError& e) {
    return e.context();
  }
  ADD_FAILURE() << "accepted: " << j.dump();
  return {};
}

} // namespace

TEST(GimpInputParameters, EveryKindOfEntryIsRefusedWithItsDeclaredRule) {
  const auto decl = input_parameters(2);
  struct Case {
    json patch;        // merged into the minimal input
    std::string field; // the field named in the error
    std::string rule;  // the declared rule
  };
  const std::vector<Case> cases = {
      // integer, real, string of a list, real list, integer list, required
      {{{"particles_per_cell", 5}}, "particles_per_cell", decl.at("particles_per_cell").rule()},
      {{{"time", {{"cfl", 1.5}}}}, "time.cfl", decl.at("time.cfl").rule()},
      {{{"output", {{"vtu", "hex"}}}}, "output.vtu", decl.at("output.vtu").rule()},
      {{{"grid", {{"origin", {0.0}}}}}, "grid.origin", decl.at("grid.origin").rule()},
      {{{"grid", {{"cells", {8}}}}}, "grid.cells", decl.at("grid.cells").rule()},
      {{{"units", "cgs"}}, "units", decl.at("units").rule()},
      {{{"damping", -1}}, "damping", decl.at("damping").rule()},
      {{{"boundaries", "left"}}, "boundaries", decl.at("boundaries").rule()},
      // custom entries and the keys of tables
      {{{"loads", {{"gravity_ramp", {2, 1}}}}},
       "loads.gravity_ramp",
       decl.at("loads.gravity_ramp").rule()},
      {{{"materials",
         {{{"name", "poly"},
           {"type", "linear_elastic"},
           {"density", 1200},
           {"E", 1.5e9},
           {"nu", 0.5}}}}},
       "materials[0].nu",
       decl.at("materials[].nu").rule()},
      {{{"materials", {{{"name", "poly"}, {"type", "rubber"}, {"density", 1200}}}}},
       "materials[0].type",
       decl.at("materials[].type").rule()},
      {{{"boundaries", {{{"min", {0.05, 0}}, {"max", {0.05, 0.4}}, {"fix", {"x", "q"}}}}}},
       "boundaries[0].fix",
       decl.at("boundaries[].fix").rule()},
      {{{"cracks", {{{"points", {{0.3, 0.0}}}}}}},
       "cracks[0].points",
       decl.at("cracks[].points").rule()},
      {{{"cracks", {{{"points", {{0.3, 0.0}, {0.3001, 0.2}}}, {"growth", {{"Gc", 0}}}}}}},
       "cracks[0].growth.Gc",
       decl.at("cracks[].growth.Gc").rule()},
      {{{"cracks", {{{"points", {{0.3, 0.0}, {0.3001, 0.2}}}, {"tips", "middle"}}}}},
       "cracks[0].tips",
       decl.at("cracks[].tips").rule()},
  };
  for (const auto& c : cases) {
    json j = minimal_input();
    j.merge_patch(c.patch);
    const auto e = error_of(j);
    EXPECT_EQ(e.source, "in.json");
    EXPECT_EQ(e.field, c.field) << c.patch.dump();
    EXPECT_EQ(e.rule, c.rule) << c.patch.dump();
  }
  // The rules as stated to the user, derived from the declared ranges and units.
  EXPECT_EQ(decl.at("particles_per_cell").rule(), "must be an integer in [1, 4]");
  EXPECT_EQ(decl.at("time.cfl").rule(), "must be a number in (0, 1]");
  EXPECT_EQ(decl.at("time.end").rule(), "must be a number in (0, 1000000] s");
  EXPECT_EQ(decl.at("output.vtu").rule(), "must be \"ascii\" or \"binary\" (base64)");
  EXPECT_EQ(decl.at("grid.cells").rule(), "must be an array of exactly 2 integers in [2, 100000]");
  EXPECT_EQ(decl.at("materials[].nu").rule(), "must be a number in (-1, 0.5)");
  EXPECT_EQ(decl.at("loads.gravity_ramp").rule(),
            "must be [t_start, t_end] in s with 0 <= t_start <= t_end");
  EXPECT_EQ(input_parameters(3).at("grid.origin").rule(),
            "must be an array of exactly 3 finite numbers m");
  // A required key left out: "is required" and its rule.
  json j = minimal_input();
  j["time"].erase("end");
  const auto e = error_of(j);
  EXPECT_EQ(e.field, "time.end");
  EXPECT_EQ(e.rule, "is required: " + decl.at("time.end").rule());
}

TEST(GimpInputParameters, UnknownKeysAreRefusedNamingTheAllowedOnesAndTheNearest) {
  json j = minimal_input();
  j["grid"]["celsize"] = 1;
  auto e = error_of(j);
  EXPECT_EQ(e.field, "grid.celsize");
  EXPECT_EQ(e.rule, "unknown key; allowed: origin, cells, cell_size (did you mean \"cell_size\"?)");
  j = minimal_input();
  j["materials"][0]["densty"] = 1000; // in a table: the keys of its type
  e = error_of(j);
  EXPECT_EQ(e.field, "materials[0].densty");
  EXPECT_EQ(e.rule, "unknown key; allowed: name, type, density, E, nu (did you mean \"density\"?)");
  j = minimal_input();
  j["cracks"][0]["growth"] = {{"Gc", 1}, {"speed", 1}}; // nothing near
  e = error_of(j);
  EXPECT_EQ(e.field, "cracks[0].growth.speed");
  EXPECT_EQ(e.rule, "unknown key; allowed: Gc, GIIc, increment, direction, max_increments");
  j = minimal_input();
  j["bodies"][0]["center"] = {0.5, 0.2}; // allowed (as before): a box ignores it
  Solver<2> s;
  EXPECT_NO_THROW(load_input_text<2>(j.dump(), "in.json", "", s));
}

// The TOML template (`pnc gimp parameters --format toml`) lists every default; read back into
// an input it changes nothing: the run controls and the solver are those of the input without.
TEST(GimpInputParameters, PrintedTemplateReadBackGivesTheDefaults) {
  for (const int dim : {2, 3}) {
    const json tmpl = pnc::parse_toml(input_parameters(dim, false).to_toml(), "template.toml");
    EXPECT_FALSE(tmpl.contains("dimension")); // required: commented out
    EXPECT_EQ(tmpl.at("time").at("cfl"), 0.5);
    EXPECT_EQ(tmpl.at("particles_per_cell"), 2);
    EXPECT_EQ(tmpl.at("output").at("vtu"), "ascii");
    if (dim == 3) continue; // the reading below is the 2-D one
    json with = tmpl;
    with.merge_patch(minimal_input());
    Solver<2> a, b;
    const RunConfig ra = load_input_text<2>(minimal_input().dump(), "in.json", "", a);
    const RunConfig rb = load_input_text<2>(with.dump(), "in.json", "", b);
    EXPECT_EQ(ra.cfl, rb.cfl);
    EXPECT_EQ(ra.dt, rb.dt);
    EXPECT_EQ(ra.max_steps, rb.max_steps);
    EXPECT_EQ(ra.threads, rb.threads);
    EXPECT_EQ(ra.output_interval, rb.output_interval);
    EXPECT_EQ(ra.vtu_binary, rb.vtu_binary);
    EXPECT_EQ(ra.history_every, rb.history_every);
    EXPECT_EQ(ra.checkpoint_every, rb.checkpoint_every);
    EXPECT_EQ(ra.fracture_every, rb.fracture_every);
    EXPECT_EQ(a.damping, b.damping);
    EXPECT_EQ(a.particles.size(), b.particles.size());
    ASSERT_EQ(a.cracks.size(), 1u);
    EXPECT_EQ(a.cracks[0].tip, b.cracks[0].tip);
    // The defaults the solver documents (RunConfig, Solver, Crack) are the declared ones.
    const RunConfig def;
    EXPECT_EQ(ra.cfl, def.cfl);
    EXPECT_EQ(ra.history_every, def.history_every);
    EXPECT_EQ(ra.checkpoint_every, def.checkpoint_every);
    EXPECT_EQ(ra.fracture_every, def.fracture_every);
    EXPECT_EQ(ra.threads, def.threads);
    EXPECT_EQ(a.cracks[0].tip, (Crack{}.tip));
  }
}

// Every example reads (examples/gimp/, the damage-card one when its card is there), and the
// declarations of each dimension hold every key the examples use.
TEST(GimpInputParameters, ExamplesAreReadByTheDeclarations) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(PNC_SOURCE_DIR) / "examples" / "gimp";
  int read = 0;
  for (const auto& f : fs::directory_iterator(dir)) {
    if (f.path().extension() != ".json") continue;
    const json j = pnc::parse_json(pnc::read_text_file(f.path().string()), f.path().string());
    bool card = false;
    for (const auto& m : j.at("materials"))
      card = card || m.at("type") == "damage_card";
    if (card) continue; // needs a card written by `pnc card tables` first
    const int dim = input_dimension(f.path().string());
    if (dim == 2) {
      Solver<2> s;
      EXPECT_NO_THROW(load_input<2>(f.path().string(), s)) << f.path();
    } else {
      Solver<3> s;
      EXPECT_NO_THROW(load_input<3>(f.path().string(), s)) << f.path();
    }
    ++read;
  }
  EXPECT_GE(read, 5);
}

// Rules between keys are checked after the declarations are read: a shape needs its keys,
// c1 comes with c2 and not with (E, nu).
TEST(GimpInputParameters, RulesBetweenKeysAreCheckedAfterRead) {
  json j = minimal_input();
  j["bodies"][0] = {{"material", "poly"}, {"shape", "circle"}, {"center", {0.5, 0.2}}};
  auto e = error_of(j);
  EXPECT_EQ(e.field, "bodies[0].radius");
  EXPECT_EQ(e.rule, "required by shape \"circle\"");
  j = minimal_input();
  j["bodies"][0].erase("max");
  e = error_of(j);
  EXPECT_EQ(e.field, "bodies[0].max");
  EXPECT_EQ(e.rule, "required by shape \"box\"");
  j = minimal_input();
  j["materials"][0] = {
      {"name", "poly"}, {"type", "hyperelastic_polymer"}, {"density", 1200}, {"c1", 1e8}};
  e = error_of(j);
  EXPECT_EQ(e.field, "materials[0].c2");
  EXPECT_EQ(e.rule, "give c1 and c2 together");
  j["materials"][0]["c2"] = 1e7;
  j["materials"][0]["E"] = 1e9;
  e = error_of(j);
  EXPECT_EQ(e.field, "materials[0].E");
  EXPECT_EQ(e.rule, "give either (c1, c2) or (E, nu)");
}
