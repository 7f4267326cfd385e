// The declared keys of the `pnc gimp couple` input (couple_parameters.cpp, D293-D296): every
// example of examples/escm/ is read to the values its JSON states (the others the declared
// defaults), with and without its "short" overrides; unknown keys at every level, wrong types
// and out-of-range values are refused naming the file, the field, the value and the rule.
#include "couple_input.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"
#include "pnc/gimp_coupler/escm_run.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>
#include <vector>

using namespace pnc::gimp::escm;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

// The values a level of the input (the top level or "short") states, over `e`: the key -> field
// map of docs/escm.md "Input file", written out independently of the reader.
void expect_level(const json& j, CoupleInput& e) {
  auto num = [&](const char* k, double& x) {
    if (j.contains(k)) x = j.at(k).get<double>();
  };
  auto integer = [&](const char* k, int& x) {
    if (j.contains(k)) x = j.at(k).get<int>();
  };
  auto text = [&](const char* k, std::string& x) {
    if (j.contains(k)) x = j.at(k).get<std::string>();
  };
  if (j.contains("cells")) e.ncx = j["cells"][0].get<int>(), e.ncy = j["cells"][1].get<int>();
  if (j.contains("block_cells"))
    e.nbx = j["block_cells"][0].get<int>(), e.nby = j["block_cells"][1].get<int>();
  integer("slab_cells", e.nz);
  integer("svc_rings", e.svc);
  integer("ivc_rings", e.ivc);
  integer("substeps", e.substeps);
  num("md_timestep_fs", e.dtau_fs);
  text("mode", e.mode);
  num("interior_temperature", e.temperature);
  num("strain", e.strain);
  num("settle_ps", e.settle_ps);
  num("load_ps", e.load_ps);
  num("hold_ps", e.hold_ps);
  num("damping_fraction", e.damping_fraction);
  integer("frames", e.frames);
  num("gradient_spacing_cells", e.gradient_cells);
  text("load", e.load);
  num("checkpoint_every_ps", e.checkpoint_ps);
  if (j.contains("crack")) {
    const json& c = j["crack"];
    e.crack = c.is_object();
    if (e.crack) {
      if (c.contains("length_cells")) e.crack_cells = c["length_cells"].get<int>();
      if (c.contains("Gc")) e.crack_Gc = c["Gc"].get<double>();
      if (c.contains("interface_fraction")) e.crack_f = c["interface_fraction"].get<double>();
      if (c.contains("every")) e.crack_every = c["every"].get<int>();
    }
  }
  if (j.contains("md")) {
    const json& m = j["md"];
    if (m.contains("type")) e.md_type = m["type"].get<std::string>();
    if (m.contains("cell_A")) e.cell_A = m["cell_A"].get<double>();
    if (m.contains("slab_A")) e.slab_A = m["slab_A"].get<double>();
    if (m.contains("density")) e.density = m["density"].get<double>();
    if (m.contains("beads_per_chain")) e.beads_per_chain = m["beads_per_chain"].get<int>();
    if (m.contains("seed")) e.md_seed = m["seed"].get<long>();
    if (m.contains("temperature")) e.poly_T = m["temperature"].get<double>();
    if (m.contains("anneal_ps")) e.anneal_ps = m["anneal_ps"].get<double>();
    if (m.contains("min_beads_per_cell")) e.min_beads = m["min_beads_per_cell"].get<int>();
    if (m.contains("strain_probe")) e.strain_probe = m["strain_probe"].get<double>();
    if (m.contains("forcefield")) {
      const json& f = m["forcefield"];
      if (f.contains("sigma")) e.ff_sigma = f["sigma"].get<double>();
      if (f.contains("epsilon")) e.ff_epsilon = f["epsilon"].get<double>();
      if (f.contains("cutoff_sigma")) e.ff_cutoff_sigma = f["cutoff_sigma"].get<double>();
    }
    if (m.contains("elastic")) {
      const json& el = m["elastic"];
      e.elastic_given = el.is_object();
      if (el.contains("E_Pa")) { // Lame constants of an isotropic solid
        const double E = el["E_Pa"].get<double>(), nu = el["nu"].get<double>();
        e.elastic_lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
        e.elastic_mu = E / (2 * (1 + nu));
      } else if (el.contains("lambda_Pa")) {
        e.elastic_lambda = el["lambda_Pa"].get<double>();
        e.elastic_mu = el["mu_Pa"].get<double>();
      }
    }
  }
}

CoupleInput expected(const json& j, bool short_mode) {
  CoupleInput e; // the defaults of the declarations are the struct's initialisers
  if (j.contains("lj")) {
    const json& l = j["lj"];
    e.lj_given = true;
    e.eps = l.value("epsilon", e.eps);
    e.sig = l.value("sigma", e.sig);
    e.mass = l.value("mass", e.mass);
    e.rc = l.value("cutoff", 2.5 * e.sig);
  }
  expect_level(j, e);
  if (short_mode && j.contains("short")) expect_level(j["short"], e);
  return e;
}

// Field by field; reals to 1e-12 relative (the Lame constants are computed from E, nu).
void expect_same(const CoupleInput& a, const CoupleInput& e, const std::string& what) {
  SCOPED_TRACE(what);
  auto near = [](double x, double y) { EXPECT_NEAR(x, y, 1e-12 * std::max(1.0, std::abs(y))); };
  near(a.eps, e.eps);
  near(a.sig, e.sig);
  near(a.rc, e.rc);
  near(a.mass, e.mass);
  EXPECT_EQ(a.lj_given, e.lj_given);
  EXPECT_EQ(a.ncx, e.ncx);
  EXPECT_EQ(a.ncy, e.ncy);
  EXPECT_EQ(a.nbx, e.nbx);
  EXPECT_EQ(a.nby, e.nby);
  EXPECT_EQ(a.nz, e.nz);
  EXPECT_EQ(a.svc, e.svc);
  EXPECT_EQ(a.ivc, e.ivc);
  EXPECT_EQ(a.substeps, e.substeps);
  near(a.dtau_fs, e.dtau_fs);
  EXPECT_EQ(a.mode, e.mode);
  near(a.temperature, e.temperature);
  near(a.strain, e.strain);
  near(a.settle_ps, e.settle_ps);
  near(a.load_ps, e.load_ps);
  near(a.hold_ps, e.hold_ps);
  near(a.damping_fraction, e.damping_fraction);
  EXPECT_EQ(a.frames, e.frames);
  near(a.gradient_cells, e.gradient_cells);
  EXPECT_EQ(a.load, e.load);
  EXPECT_EQ(a.crack, e.crack);
  EXPECT_EQ(a.crack_cells, e.crack_cells);
  near(a.crack_Gc, e.crack_Gc);
  near(a.crack_f, e.crack_f);
  EXPECT_EQ(a.crack_every, e.crack_every);
  near(a.checkpoint_ps, e.checkpoint_ps);
  EXPECT_EQ(a.md_type, e.md_type);
  near(a.cell_A, e.cell_A);
  near(a.slab_A, e.slab_A);
  near(a.density, e.density);
  near(a.poly_T, e.poly_T);
  near(a.anneal_ps, e.anneal_ps);
  near(a.strain_probe, e.strain_probe);
  EXPECT_EQ(a.beads_per_chain, e.beads_per_chain);
  EXPECT_EQ(a.min_beads, e.min_beads);
  EXPECT_EQ(a.md_seed, e.md_seed);
  near(a.ff_sigma, e.ff_sigma);
  near(a.ff_epsilon, e.ff_epsilon);
  near(a.ff_cutoff_sigma, e.ff_cutoff_sigma);
  EXPECT_EQ(a.elastic_given, e.elastic_given);
  near(a.elastic_lambda, e.elastic_lambda);
  near(a.elastic_mu, e.elastic_mu);
}

json read_json(const fs::path& p) {
  std::ifstream f(p);
  return json::parse(f);
}

// A directory of its own for the inputs of one test (created exclusively).
class CoupleInputFile {
public:
  CoupleInputFile() : dir_(pnc::test::fresh_dir("couple_params")) {}
  ~CoupleInputFile() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string write(const json& j) const {
    const std::string p = (dir_ / "in.json").string();
    std::ofstream(p) << j.dump();
    return p;
  }

private:
  fs::path dir_;
};

struct Refusal {
  std::string path;
  pnc::ErrorContext ctx;
};

Refusal error_of(const json& j, bool short_mode = false) {
  CoupleInputFile f;
  const std::string p = f.write(j);
  try {
    (void)read_couple_input(p, short_mode);
  } catch (const pnc::InputError& e) {
    return {p, e.context()};
  }
  ADD_FAILURE() << "accepted: " << j.dump();
  return {p, {}};
}

CoupleInput read_ok(const json& j, bool short_mode = false) {
  CoupleInputFile f;
  return read_couple_input(f.write(j), short_mode);
}

} // namespace

TEST(CoupleParameters, ExamplesAreReadToTheValuesTheirJsonStates) {
  const fs::path dir = fs::path(PNC_SOURCE_DIR) / "examples" / "escm";
  int n = 0;
  for (const auto& f : fs::directory_iterator(dir)) {
    if (f.path().extension() != ".json") continue;
    const json j = read_json(f.path());
    for (const bool short_mode : {false, true}) {
      const CoupleInput got = read_couple_input(f.path().string(), short_mode);
      expect_same(got, expected(j, short_mode),
                  f.path().filename().string() + (short_mode ? " --short" : ""));
    }
    ++n;
  }
  EXPECT_GE(n, 6); // case1..3, LJ and polymer
}

TEST(CoupleParameters, UnknownKeysAreRefusedNamingTheAllowedOnes) {
  struct Case {
    json in;
    bool short_mode;
    std::string field, nearest;
  };
  const std::vector<Case> cases = {
      {{{"cels", {40, 20}}}, false, "cels", "cells"},
      {{{"lj", {{"epsilonn", 0.2}}}}, false, "lj.epsilonn", "epsilon"},
      {{{"load", "tension_y"}, {"crack", {{"lenght_cells", 3}}}},
       false,
       "crack.lenght_cells",
       "length_cells"},
      {{{"md", {{"slab", 16}}}}, false, "md.slab", "slab_A"},
      {{{"md", {{"forcefield", {{"sigmaa", 4.0}}}}}}, false, "md.forcefield.sigmaa", "sigma"},
      {{{"short", {{"framse", 3}}}}, true, "short.framse", "frames"},
      // lj and short are top-level only
      {{{"short", {{"lj", json::object()}}}}, true, "short.lj", ""},
  };
  for (const auto& c : cases) {
    const Refusal r = error_of(c.in, c.short_mode);
    SCOPED_TRACE(c.in.dump());
    EXPECT_EQ(r.ctx.source, r.path);
    EXPECT_EQ(r.ctx.field, c.field);
    EXPECT_NE(r.ctx.rule.find("unknown key; allowed: "), std::string::npos) << r.ctx.rule;
    if (!c.nearest.empty()) {
      EXPECT_NE(r.ctx.rule.find("did you mean \"" + c.nearest + "\""), std::string::npos)
          << r.ctx.rule;
    }
  }
  // "short" is read only with --short (as before: its keys are not checked without it)
  EXPECT_EQ(read_ok({{"short", {{"framse", 3}}}}).frames, CoupleInput{}.frames);
}

TEST(CoupleParameters, WrongTypesAndRangesAreRefusedWithTheDeclaredRule) {
  const pnc::Parameters decl = couple_input_parameters();
  struct Case {
    json in;
    bool short_mode;
    std::string field, value, rule;
  };
  const std::vector<Case> cases = {
      // wrong types
      {{{"frames", "8"}}, false, "frames", "\"8\"", decl.at("frames").rule()},
      {{{"md", {{"cell_A", "6"}}}}, false, "md.cell_A", "\"6\"", "must be a number"},
      {{{"mode", 3}}, false, "mode", "3", "must be a string"},
      {{{"mode", "dirichlet"}}, false, "mode", "\"dirichlet\"", decl.at("mode").rule()},
      {{{"cells", {40}}}, false, "cells", "[40]", decl.at("cells").rule()},
      {{{"crack", true}}, false, "crack", "true", "must be an object (or false)"},
      {{{"lj", 1}}, false, "lj", "1", "must be a JSON object"},
      // out of range: bounds as the former reader had them
      {{{"substeps", 0}}, false, "substeps", "0", decl.at("substeps").rule()},
      {{{"cells", {40, 7}}}, false, "cells", "7", "must be an integer in [8, 2000]"},
      {{{"load_ps", 0.0}}, false, "load_ps", "0", decl.at("load_ps").rule()},
      {{{"load", "tension_y"}, {"crack", {{"Gc", 1e3}}}},
       false,
       "crack.Gc",
       "1000",
       decl.at("crack.Gc").rule()},
      {{{"load", "tension_y"}, {"crack", {{"interface_fraction", 0}}}},
       false,
       "crack.interface_fraction",
       "0",
       decl.at("crack.interface_fraction").rule()},
      {{{"md", {{"seed", 0}}}}, false, "md.seed", "0", decl.at("md.seed").rule()},
      {{{"lj", {{"mass", -1}}}}, false, "lj.mass", "-1", decl.at("lj.mass").rule()},
      {{{"md", {{"elastic", {{"E_Pa", 1e9}, {"nu", 0.5}}}}}},
       false,
       "md.elastic",
       "{\"E_Pa\":1000000000.0,\"nu\":0.5}",
       "E_Pa > 0 and nu in (-1, 0.5)"},
      {{{"md", {{"type", "crystal"}}}}, false, "md.type", "\"crystal\"", decl.at("md.type").rule()},
      {{{"short", {{"strain", 0.2}}}}, true, "short.strain", "0.2", decl.at("strain").rule()},
  };
  for (const auto& c : cases) {
    const Refusal r = error_of(c.in, c.short_mode);
    SCOPED_TRACE(c.in.dump());
    EXPECT_EQ(r.ctx.source, r.path);
    EXPECT_EQ(r.ctx.field, c.field);
    EXPECT_NE(r.ctx.value.find(c.value), std::string::npos) << r.ctx.value;
    EXPECT_NE(r.ctx.rule.find(c.rule), std::string::npos) << r.ctx.rule;
  }
  // the rules state the unit and the range of the declaration
  EXPECT_EQ(decl.at("load_ps").rule(), "must be a number in [0.001, 100000] ps");
  EXPECT_EQ(decl.at("substeps").rule(), "must be an integer in [1, 10000]");
  // the bounds themselves, where closed, are accepted
  const CoupleInput edge = read_ok({{"load_ps", 1e-3},
                                    {"strain", -0.1},
                                    {"md", {{"strain_probe", 0.05}}},
                                    {"load", "tension_y"},
                                    {"crack", {{"interface_fraction", 1}}}});
  EXPECT_EQ(edge.load_ps, 1e-3);
  EXPECT_EQ(edge.crack_f, 1.0);
  EXPECT_TRUE(edge.crack);
  // "crack": false is no crack, also over a crack of the top level
  EXPECT_FALSE(read_ok({{"crack", false}}).crack);
  EXPECT_FALSE(read_ok({{"load", "tension_y"},
                        {"crack", json::object()},
                        {"short", {{"crack", false}, {"load", "tension_x"}}}},
                       true)
                   .crack);
}

TEST(CoupleParameters, RulesBetweenKeysAreCheckedAfterRead) {
  Refusal r = error_of({{"lj", {{"sigma", 3.4}, {"cutoff", 3.0}}}});
  EXPECT_EQ(r.ctx.field, "lj.cutoff");
  EXPECT_NE(r.ctx.rule.find("[1.2, 6] sigma"), std::string::npos);
  // the default cut-off is 2.5 sigma of the given sigma
  EXPECT_DOUBLE_EQ(read_ok({{"lj", {{"sigma", 3.0}}}}).rc, 7.5);
  r = error_of({{"crack", json::object()}}); // a crack needs tension_y or shear
  EXPECT_EQ(r.ctx.field, "load");
  r = error_of({{"block_cells", {14, 4}}});
  EXPECT_EQ(r.ctx.field, "block_cells");
}

TEST(CoupleParameters, PrintedTemplateReadBackGivesTheDefaults) {
  const std::string toml = couple_input_parameters().to_toml();
  const json in = pnc::parse_toml(toml, "<template>");
  expect_same(read_ok(in), expected(json::object(), false), "template");
  expect_same(read_ok(json::object()), CoupleInput{}, "empty input");
}

// ------------------------------------------------------------ the input as TOML (D357)
// Every example converted to TOML (to_toml) is read to the same values as its JSON file, with
// and without "short"; the printed template, written as a .toml file, is read to the defaults.
TEST(CoupleParameters, TomlInputsReadAsTheirJsonTwins) {
  CoupleInputFile tmp;
  const fs::path dir = fs::path(PNC_SOURCE_DIR) / "examples" / "escm";
  const fs::path t = fs::path(tmp.write(json::object())).parent_path() / "in.toml";
  int n = 0;
  for (const auto& f : fs::directory_iterator(dir)) {
    if (f.path().extension() != ".json") continue;
    const json j = read_json(f.path());
    std::ofstream(t) << pnc::to_toml(j);
    for (const bool short_mode : {false, true})
      expect_same(read_couple_input(t.string(), short_mode), expected(j, short_mode),
                  f.path().filename().string() + " as TOML" + (short_mode ? " --short" : ""));
    ++n;
  }
  EXPECT_GE(n, 6);
  std::ofstream(t) << couple_input_parameters().to_toml();
  expect_same(read_couple_input(t.string(), false), expected(json::object(), false),
              "template.toml");
}

// --resume compares the input as values (D339): a run started from the JSON file (its bytes
// stored, as checkpoints before D357 hold) or from TOML resumes from the other syntax; a changed
// value is refused naming its key; a TOML syntax error names the file and the line; another
// extension is refused.
TEST(CoupleParameters, TomlInputResumesFromItsJsonTwinAndErrorsNameLineAndKey) {
  CoupleInputFile tmp;
  const fs::path src = fs::path(PNC_SOURCE_DIR) / "examples" / "escm" / "case1_lj_tension.json";
  const json j = read_json(src);
  const fs::path t = fs::path(tmp.write(json::object())).parent_path() / "in.toml";
  std::ofstream(t) << pnc::to_toml(j);
  std::ifstream js(src);
  const std::string json_bytes{std::istreambuf_iterator<char>(js), {}};
  EXPECT_NO_THROW(
      check_same_input(t.string(), json_bytes, read_input_as_json_text(t.string()), "ckpt.h5"));
  EXPECT_NO_THROW(check_same_input(src.string(), read_input_as_json_text(t.string()),
                                   read_input_as_json_text(src.string()), "ckpt.h5"));
  json changed = j;
  changed["cells"][0] = j.at("cells")[0].get<int>() + 2;
  std::ofstream(t) << pnc::to_toml(changed);
  try {
    check_same_input(t.string(), json_bytes, read_input_as_json_text(t.string()), "ckpt.h5");
    ADD_FAILURE() << "a changed cells was accepted";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().source, t.string());
    EXPECT_EQ(e.context().field.rfind("cells", 0), 0u) << e.what();
  }
  std::ofstream(t) << "cells = [30, 20]\ntemperature = \n";
  try {
    (void)read_couple_input(t.string(), false);
    ADD_FAILURE() << "invalid TOML was accepted";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().source, t.string());
    EXPECT_NE(e.context().rule.find("not valid TOML"), std::string::npos) << e.what();
    EXPECT_NE(e.context().rule.find(" 2 | temperature ="), std::string::npos)
        << "no line: " << e.what();
  }
  const fs::path y = t.parent_path() / "in.yaml";
  std::ofstream(y) << j.dump();
  try {
    (void)read_couple_input(y.string(), false);
    ADD_FAILURE() << "in.yaml was accepted";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().field, "input");
    EXPECT_EQ(e.context().value, ".yaml");
    EXPECT_EQ(e.context().rule, "a couple input file ends in .json or .toml");
  }
}
