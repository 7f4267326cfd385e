// The parameter layer (pnc/core/parameters.hpp): every type accepts what its declaration allows
// and refuses the rest with an InputError naming the file, the dotted field, the value and the
// rule derived from the declaration; unknown keys are refused with the allowed ones; defaults
// fill what is not given; the JSON, TOML and Markdown printouts carry the declarations back.
#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/params.hpp"

#include <gtest/gtest.h>

#include <sstream>

using json = nlohmann::json;
using pnc::Choice;
using pnc::Parameters;
using pnc::RealRange;

namespace {

// A small input with one entry of each type, bound to the fields of V.
struct V {
  std::string name = "x";
  bool flag = false;
  int count = 4;
  long steps = 1000;
  double dt = 1.0, alpha = 0, ratio = 0.5, strain = 0.1;
  std::string ensemble = "npt";
  std::vector<int> cases = {2, 6};
  std::vector<double> weights = {1.0, 2.0};
  int odd = 1;
};

Parameters declare(V& v) {
  Parameters p("test input");
  p.string("name", v.name, {}, "a name");
  p.section("run", "how to run");
  p.boolean("flag", v.flag, "a switch");
  p.integer("count", v.count, 1, 64, "", "how many");
  p.integer("steps", v.steps, 0, 2000000000, "", "MD steps");
  p.real("dt", v.dt, RealRange::open_closed(0, 50), "fs", "time step");
  p.real("alpha", v.alpha, RealRange::closed(0.5, 1.5), "1", "start value")
      .no_default("the built-in value");
  p.real("ratio", v.ratio, RealRange::open(0.05, 3), "g/cm^3", "a density");
  p.real("strain", v.strain, RealRange::above(0), "1", "a strain");
  p.string("ensemble", v.ensemble, {{"npt", "set pressure"}, {"nvt", "set density"}},
           "the ensemble");
  p.section("run.cases", "what to deform");
  p.integers("ids", v.cases, 1, 6, 1, 6, "", "case ids");
  p.reals("weights", v.weights, RealRange::at_least(0), 2, 2, "1", "two weights");
  p.integer("odd", v.odd, 1, 1001, "", "points")
      .also("odd", [](const json& j, const std::string& src, const std::string& field) {
        if (j.get<long>() % 2 == 0) pnc::fail(src, field, j.dump(), "must be odd");
      });
  return p;
}

pnc::ErrorContext error_of(const json& in) {
  V v;
  try {
    declare(v).read(in, "in.json");
  } catch (const pnc::InputError& e) {
    return e.context();
  }
  ADD_FAILURE() << "accepted " << in.dump();
  return {};
}

json at(const std::string& ptr, json v) {
  json j = json::object();
  j[json::json_pointer(ptr)] = std::move(v);
  return j;
}

} // namespace

TEST(Parameters, EachTypeAcceptsItsRangeAndStoresTheValue) {
  V v;
  const Parameters p = declare(v);
  const json in = json::parse(R"({"name": "y", "run": {"flag": true, "count": 64, "steps": 0,
      "dt": 50, "alpha": 0.5, "ratio": 2.5, "strain": 1e-9, "ensemble": "nvt",
      "cases": {"ids": [1, 3, 5], "weights": [0, 3.5], "odd": 7}}})");
  const json out = p.read(in, "in.json");
  EXPECT_EQ(out, in); // everything given: read returns it as given
  EXPECT_EQ(v.name, "y");
  EXPECT_TRUE(v.flag);
  EXPECT_EQ(v.count, 64);
  EXPECT_EQ(v.steps, 0);
  EXPECT_EQ(v.dt, 50.0); // closed upper bound
  EXPECT_EQ(v.alpha, 0.5);
  EXPECT_EQ(v.ratio, 2.5);
  EXPECT_EQ(v.ensemble, "nvt");
  EXPECT_EQ(v.cases, (std::vector<int>{1, 3, 5}));
  EXPECT_EQ(v.weights, (std::vector<double>{0, 3.5}));
  EXPECT_EQ(v.odd, 7);
}

TEST(Parameters, EachTypeRefusesWithFileFieldValueAndTheDeclaredRule) {
  struct Bad {
    json in;
    std::string field, value, rule;
  };
  const std::vector<Bad> bad = {
      {at("/run/flag", "yes"), "run.flag", "\"yes\"", "must be true or false"},
      {at("/run/flag", 1), "run.flag", "1", "must be true or false"},
      {at("/run/count", 65), "run.count", "65", "must be an integer in [1, 64]"},
      {at("/run/count", 0), "run.count", "0", "must be an integer in [1, 64]"},
      {at("/run/count", 2.5), "run.count", "2.5", "must be an integer in [1, 64]"},
      {at("/run/count", 3.0), "run.count", "3.0", "must be an integer in [1, 64]"},
      {json::parse(R"({"run": {"steps": 18446744073709551615}})"), "run.steps",
       "18446744073709551615", "must be an integer in [0, 2000000000]"},
      {at("/run/dt", 0.0), "run.dt", "0", "must be a number in (0, 50] fs"},
      {at("/run/dt", 50.5), "run.dt", "50.5", "must be a number in (0, 50] fs"},
      {at("/run/dt", "1"), "run.dt", "\"1\"", "must be a number"},
      {at("/run/alpha", 0.3), "run.alpha", "0.3", "must be a number in [0.5, 1.5]"},
      {at("/run/ratio", 0.05), "run.ratio", "0.05", "must be a number in (0.05, 3) g/cm^3"},
      {at("/run/ratio", 3), "run.ratio", "3", "must be a number in (0.05, 3) g/cm^3"},
      {at("/run/strain", -1.0), "run.strain", "-1", "must be a number > 0"},
      {at("/run/ensemble", "nph"), "run.ensemble", "\"nph\"",
       "must be \"npt\" (set pressure) or \"nvt\" (set density)"},
      {at("/run/ensemble", 3), "run.ensemble", "3", "must be a string"},
      {at("/name", true), "name", "true", "must be a string"},
      {at("/run/cases/ids", json::array({2, 9})), "run.cases.ids", "9",
       "must be an integer in [1, 6]"},
      {at("/run/cases/ids", json::array()), "run.cases.ids", "[]",
       "must be an array of 1 to 6 integers in [1, 6]"},
      {at("/run/cases/ids", json::array({1, 2, 3, 4, 5, 6, 1})), "run.cases.ids", "[1,2,3,4,5,6,1]",
       "must be an array of 1 to 6 integers in [1, 6]"},
      {at("/run/cases/ids", 2), "run.cases.ids", "2",
       "must be an array of 1 to 6 integers in [1, 6]"},
      {at("/run/cases/weights", json::array({1.0})), "run.cases.weights", "[1.0]",
       "must be an array of exactly 2 finite numbers >= 0"},
      {at("/run/cases/weights", json::array({1.0, -0.5})), "run.cases.weights", "-0.5",
       "must be a number >= 0"},
      {at("/run/cases/odd", 4), "run.cases.odd", "4", "must be odd"},
      {at("/run", 4), "run", "4", "must be a JSON object"},
      {json::array(), "", "[]", "must be a JSON object"},
  };
  for (const auto& b : bad) {
    const auto e = error_of(b.in);
    EXPECT_EQ(e.source, "in.json") << b.in.dump();
    EXPECT_EQ(e.field, b.field) << b.in.dump();
    EXPECT_EQ(e.value, b.value) << b.in.dump();
    EXPECT_EQ(e.rule, b.rule) << b.in.dump();
  }
}

TEST(Parameters, UnknownKeysAreRefusedWithTheAllowedOnesAndTheNearest) {
  auto e = error_of(at("/run/stepz", 10));
  EXPECT_EQ(e.field, "run.stepz");
  EXPECT_EQ(e.value, "10");
  EXPECT_EQ(e.rule, "unknown key; allowed: flag, count, steps, dt, alpha, ratio, strain, "
                    "ensemble, cases (did you mean \"steps\"?)");
  e = error_of(at("/colour", "red"));
  EXPECT_EQ(e.field, "colour");
  EXPECT_EQ(e.rule, "unknown key; allowed: name, run"); // nothing near
  e = error_of(at("/run/cases/idz", 1));
  EXPECT_NE(e.rule.find("did you mean \"ids\""), std::string::npos) << e.rule;
  EXPECT_EQ(pnc::nearest_name("strain_mx", {"steps", "strain_max"}), "strain_max");
  EXPECT_EQ(pnc::nearest_name("xyz", {"steps", "strain_max"}), "");
}

TEST(Parameters, DefaultsFillWhatIsNotGivenAndTheVariablesKeepThem) {
  V v;
  const Parameters p = declare(v);
  const json d = p.defaults();
  EXPECT_EQ(d, json::parse(R"({"name": "x", "run": {"flag": false, "count": 4, "steps": 1000,
      "dt": 1.0, "ratio": 0.5, "strain": 0.1, "ensemble": "npt",
      "cases": {"ids": [2, 6], "weights": [1.0, 2.0], "odd": 1}}})"));
  EXPECT_FALSE(d["run"].contains("alpha")); // no default: absent unless given
  const json out = p.read(at("/run/count", 8), "in.json");
  EXPECT_EQ(out["run"]["count"], 8);
  EXPECT_EQ(out["run"]["steps"], 1000);
  EXPECT_EQ(v.count, 8);
  EXPECT_EQ(v.steps, 1000);
  EXPECT_EQ(v.alpha, 0.0); // untouched: its meaning when absent is the caller's
  EXPECT_EQ(p.at("run.alpha").absent, "the built-in value");
}

TEST(Parameters, JsonPrintoutCarriesEveryDeclaration) {
  V v;
  const Parameters p = declare(v);
  const json j = json::parse(p.to_json().dump()); // through text
  EXPECT_EQ(j["title"], "test input");
  std::size_t n = 0;
  for (const auto& s : j["sections"])
    for (const auto& e : s["parameters"]) {
      const auto& d = p.at(e["name"].get<std::string>());
      EXPECT_EQ(e["type"], d.type_name());
      EXPECT_EQ(e["default"], d.default_value);
      EXPECT_EQ(e["unit"], d.unit);
      EXPECT_EQ(e["rule"], d.rule());
      ++n;
    }
  EXPECT_EQ(n, p.parameters().size());
  const json& dt = j["sections"][1]["parameters"][3];
  EXPECT_EQ(dt["name"], "run.dt");
  EXPECT_EQ(dt["range"], json::parse(R"({"min": 0, "min_open": true, "max": 50,
                                         "max_open": false})"));
}

TEST(Parameters, TomlTemplateReadBackGivesTheDefaults) {
  V v;
  const Parameters p = declare(v);
  const std::string t = p.to_toml();
  EXPECT_NE(t.find("[run.cases]"), std::string::npos) << t;
  EXPECT_NE(t.find("# alpha ="), std::string::npos) << t; // no default: commented out
  EXPECT_NE(t.find("dt = 1.0"), std::string::npos) << t;  // a float stays a float
  const json back = pnc::parse_toml(t, "template.toml");
  EXPECT_EQ(p.read(back, "template.toml"), p.defaults());
  EXPECT_EQ(back, p.defaults()); // the template holds exactly the defaults, types included
}

TEST(Parameters, MarkdownTablesListEveryEntryWithItsDefault) {
  V v;
  const Parameters p = declare(v);
  const std::string md = p.to_markdown(3);
  EXPECT_NE(md.find("### `run.cases`\n"), std::string::npos) << md;
  std::istringstream in(md);
  std::string line;
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    if (line.rfind("| `", 0) != 0) continue;
    // | `path` | type | `default` | range | unit | meaning |
    std::vector<std::string> cells;
    std::string c;
    for (std::size_t i = 1; i < line.size(); ++i) {
      if (line[i] == '|' && line[i - 1] != '\\') {
        cells.push_back(c.substr(1, c.size() - 2));
        c.clear();
      } else {
        c += line[i];
      }
    }
    ASSERT_EQ(cells.size(), 6u) << line;
    const auto& d = p.at(cells[0].substr(1, cells[0].size() - 2));
    EXPECT_EQ(cells[1], d.type_name());
    if (d.default_value.is_null())
      EXPECT_EQ(cells[2], "–");
    else
      EXPECT_EQ(json::parse(cells[2].substr(1, cells[2].size() - 2)), d.default_value) << line;
    EXPECT_EQ(cells[3], d.range_text());
    EXPECT_EQ(cells[4], d.unit);
    EXPECT_EQ(cells[5].rfind(d.text, 0), 0u) << line;
    ++rows;
  }
  EXPECT_EQ(rows, p.parameters().size());
  EXPECT_EQ(p.at("run.cases.ids").range_text(), "1 to 6 elements, each [1, 6]");
  EXPECT_EQ(p.at("run.cases.odd").range_text(), "[1, 1001]; odd");
}

TEST(Parameters, SectionsDeclaredTwiceAreForDocumentationOnly) {
  bool a = false, b = false;
  Parameters p("doc");
  p.section("ff", "force field", "model A");
  p.boolean("x", a, "x");
  p.section("ff", "force field", "model B");
  p.boolean("y", b, "y");
  EXPECT_NE(p.to_markdown().find("`ff` (model B)"), std::string::npos);
  EXPECT_THROW(p.read(json::object(), "in.json"), std::logic_error);
  EXPECT_THROW(p.to_toml(), std::logic_error);
  EXPECT_THROW(p.boolean("y", b, "again"), std::logic_error);
}

TEST(Parameters, OpaqueSectionsArePassedThroughAsObjects) {
  bool a = false;
  Parameters p("input");
  p.boolean("a", a, "a");
  p.opaque_section("system", "your own system");
  p.boolean("b", a, "b, back at the top level");
  json in = json::parse(R"({"system": {"anything": [1, 2]}, "b": true})");
  EXPECT_EQ(p.read(in, "in.json")["system"], in["system"]);
  in["system"] = 3;
  try {
    p.read(in, "in.json");
    ADD_FAILURE() << "accepted";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().field, "system");
    EXPECT_EQ(e.context().rule, "must be a JSON object");
  }
}

// An optional section: whether the input has it is a value of its own (a recipe's "slurm").
TEST(Parameters, OptionalSectionsAreKeptOnlyWhenGiven) {
  bool given = true; // read() sets it either way
  int ranks = 0;
  std::string mpi = "pmix";
  Parameters p("input");
  p.optional_section("slurm", given, "the cluster");
  p.integer("ranks", ranks, 1, 4096, "", "ranks").no_default("one");
  p.string("mpi", mpi, {}, "plugin").omit_when_default();
  EXPECT_FALSE(p.read(json::object(), "in.json").contains("slurm"));
  EXPECT_FALSE(given);
  EXPECT_FALSE(p.values().contains("slurm"));
  EXPECT_EQ(p.read(json::parse(R"({"slurm": {}})"), "in.json")["slurm"],
            json::parse(R"({"mpi": "pmix"})"));
  EXPECT_TRUE(given);
  EXPECT_EQ(p.values()["slurm"], json::object()); // given, every entry left out
  p.read(json::parse(R"({"slurm": {"ranks": 4}})"), "in.json");
  EXPECT_EQ(p.values()["slurm"], json::parse(R"({"ranks": 4})"));
  try {
    p.read(json::parse(R"({"slurm": {"ranks": 0}})"), "in.json");
    ADD_FAILURE() << "accepted";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().field, "slurm.ranks");
  }
  // the template leaves it out (commented): read back, the section is not given
  const std::string t = p.to_toml();
  EXPECT_NE(t.find("# [slurm]"), std::string::npos) << t;
  EXPECT_NE(t.find("# mpi = \"pmix\""), std::string::npos) << t;
  given = true;
  EXPECT_EQ(p.read(pnc::parse_toml(t, "t.toml"), "t.toml"), p.defaults());
  EXPECT_FALSE(given);
  EXPECT_TRUE(p.to_json()["sections"][1]["optional"].get<bool>());
}

TEST(Parameters, ValuesAreTheVariablesNowWithUnsetEntriesLeftOut) {
  V v;
  Parameters p = declare(v);
  bool quiet = false;
  p.section("extra", "quiet entries");
  p.boolean("quiet", quiet, "left out at its default").omit_when_default();
  json want = p.defaults();
  want["extra"].erase("quiet"); // at its default
  EXPECT_EQ(p.values(), want);  // nothing read yet: the defaults, alpha left out
  p.read(json::parse(R"({"run": {"alpha": 1.25, "count": 9}, "extra": {"quiet": true}})"),
         "in.json");
  const json now = p.values();
  EXPECT_EQ(now["run"]["alpha"], 1.25);
  EXPECT_EQ(now["run"]["count"], 9);
  EXPECT_EQ(now["extra"]["quiet"], true);
  v.alpha = 0; // back to "not given"
  v.cases = {4};
  EXPECT_FALSE(p.values()["run"].contains("alpha"));
  EXPECT_EQ(p.values()["run"]["cases"]["ids"], json::array({4}));
}

// Lists of strings and of tables, required keys, and an input read as one element of a larger
// one (the field prefix): a table list's elements are read by its check with their own
// declarations, and errors name the element's key under the prefix.
TEST(Parameters, StringAndTableListsRequiredKeysAndFieldPrefixes) {
  std::vector<std::string> lines;
  std::string units;
  std::vector<double> temps;
  Parameters p("input");
  p.section("system", "a system");
  p.string("units", units, {{"real", "A, fs"}}, "units").require();
  p.strings("lines", lines, 1, 3, "commands").require();
  pnc::Parameter st;
  st.path = "stages";
  st.type = pnc::ParamType::table_list;
  st.default_value = json::array();
  st.max_size = 2;
  st.text = "stages";
  st.check = [&temps](const json& v, const std::string& source, const std::string& field) {
    temps.clear();
    for (std::size_t i = 0; i < v.size(); ++i) {
      double t = 0;
      Parameters s("stage");
      s.real("temperature", t, RealRange::above(0), "K", "temperature").require();
      s.read(v[i], source, field + "[" + std::to_string(i) + "]");
      temps.push_back(t);
    }
  };
  p.add(std::move(st));
  const json ok = json::parse(R"({"system": {"units": "real", "lines": ["a", "b"],
                                  "stages": [{"temperature": 10}, {"temperature": 20.5}]}})");
  p.read(ok, "in.json");
  EXPECT_EQ(lines, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(temps, (std::vector<double>{10, 20.5}));
  struct Bad {
    const char* ptr;
    json v;
    std::string field, value, rule;
  };
  const std::vector<Bad> bad = {
      {"/system/lines", json::array({"a", 3}), "system.lines[1]", "3", "must be a string"},
      {"/system/lines", json::array(), "system.lines", "[]", "must be an array of 1 to 3 strings"},
      {"/system/stages", json::array({json::object(), 1}), "system.stages[1]", "1",
       "must be a JSON object"},
      {"/system/stages", json::array({json::object(), json::object(), json::object()}),
       "system.stages", "[{},{},{}]", "must be an array of 0 to 2 tables (JSON objects)"},
      {"/system/stages/1", json::parse(R"({"temperature": -1.0})"), "system.stages[1].temperature",
       "-1", "must be a number > 0 K"},
      {"/system/stages/0", json::parse(R"({"temp": 1})"), "system.stages[0].temp", "1",
       "unknown key; allowed: temperature (did you mean \"temperature\"?)"},
      {"/system/stages/0", json::object(), "system.stages[0].temperature", "<missing>",
       "is required: must be a number > 0 K"},
  };
  for (const auto& b : bad) {
    json in = ok;
    in[json::json_pointer(b.ptr)] = b.v;
    try {
      p.read(in, "in.json");
      ADD_FAILURE() << "accepted " << in.dump();
    } catch (const pnc::InputError& e) {
      EXPECT_EQ(e.context().field, b.field) << in.dump();
      EXPECT_EQ(e.context().value, b.value) << in.dump();
      EXPECT_EQ(e.context().rule, b.rule) << in.dump();
    }
  }
  json missing = ok;
  missing["system"].erase("units");
  try {
    p.read(missing, "in.json");
    ADD_FAILURE() << "accepted";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().field, "system.units");
    EXPECT_EQ(e.context().rule, "is required: must be \"real\" (A, fs)");
  }
  EXPECT_NE(p.to_markdown().find("| `system.units` | string | required |"), std::string::npos);
}
