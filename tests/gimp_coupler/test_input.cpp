// The GIMP input (errors name key, value, rule): 2-D keys, 3-D planar cracks, hardening.
#include "test_input_util.hpp"

#include "pnc/gimp_coupler/input.hpp"
#include "pnc/gimp_coupler/output.hpp"
#include "pnc/gimp_coupler/run.hpp"

#include "pnc/core/error.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/reference.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace pnc::gimp;
using namespace pnc::gimp::test;

TEST(GimpInput, BuildsBodiesWithHolesBoundariesAndTractions) {
  Solver<2> s;
  const RunConfig rc = load_input_text<2>(base_input().dump(), "in.json", "", s);
  EXPECT_EQ(rc.threads, 2);
  EXPECT_TRUE(rc.vtu_binary);
  // 20 x 4 cells of 4 particles minus the hole and the notch.
  const std::size_t full = 20 * 4 * 4;
  EXPECT_LT(s.particles.size(), full);
  EXPECT_GT(s.particles.size(), full - 40);
  for (std::size_t p = 0; p < s.particles.size(); ++p) {
    EXPECT_GT((s.particles.x[p] - Eigen::Vector2d(0.5, 0.2)).norm(), 0.04);
    EXPECT_NEAR(s.particles.m[p], 1200 * 0.025 * 0.025, 1e-12);
  }
  ASSERT_EQ(s.bcs.size(), 1u);
  EXPECT_TRUE(s.bcs[0].mask[0] && s.bcs[0].mask[1]);
  ASSERT_EQ(s.tractions.size(), 1u);
  EXPECT_EQ(s.tractions[0].particles.size(), 16u); // the last two particle columns
  {
    json j = base_input();
    j["cracks"] = json::array(
        {{{"name", "edge"},
          {"points", json::array({json::array({0.3, 0.0}), json::array({0.3001, 0.2})})}}});
    Solver<2> c;
    load_input_text<2>(j.dump(), "in.json", "", c);
    ASSERT_EQ(c.cracks.size(), 1u);
    EXPECT_EQ(c.cracks[0].name, "edge");
    c.initialize();
    c.step(1e-7);
  }
  const auto* hp = dynamic_cast<const HyperelasticPolymer*>(s.materials[0].get());
  ASSERT_NE(hp, nullptr);
  EXPECT_NEAR(hp->youngs_modulus(), 1.5e9, 1.0);
}

TEST(GimpInput, ErrorsNameKeyValueAndRule) {
  auto expect_error = [](json j, const std::string& key, const std::string& rule) {
    const std::string msg = error_of(j);
    EXPECT_NE(msg.find("in.json"), std::string::npos) << key << ": " << msg;
    EXPECT_NE(msg.find(key), std::string::npos) << msg;
    EXPECT_NE(msg.find(rule), std::string::npos) << msg;
  };
  json j = base_input();
  j["grid"]["cell_size"] = -1;
  expect_error(j, "grid.cell_size", "must be a number > 0 m");
  j = base_input();
  j["materials"][0]["nu"] = 0.5;
  expect_error(j, "materials[0].nu", "(-1, 0.5)");
  j = base_input();
  j["bodies"][0]["material"] = "steel";
  expect_error(j, "bodies[0].material", "not the name");
  j = base_input();
  j["bodies"][0]["holes"][0]["radius"] = 0;
  expect_error(j, "bodies[0].holes[0].radius", "must be a number > 0 m");
  j = base_input();
  j["boundaries"][0]["fix"] = json::array({"q"});
  expect_error(j, "boundaries[0].fix", "\"x\" or \"y\"");
  j = base_input();
  j["loads"]["tractions"][0]["ramp"] = json::array({2, 1});
  expect_error(j, "loads.tractions[0].ramp", "t_start <= t_end");
  j = base_input();
  j["time"]["cfl"] = 2;
  expect_error(j, "time.cfl", "(0, 1]");
  j = base_input();
  j["grid"]["celsize"] = 1;
  expect_error(j, "grid.celsize", "unknown key");
  j = base_input();
  j["grid"]["cells"] = json::array({1, 8});
  expect_error(j, "grid.cells", "integer in [2, 100000]");
  j = base_input();
  j["materials"][0]["type"] = "rubber";
  expect_error(j, "materials[0].type", "must be");
  j = base_input();
  j["materials"][0] = {{"name", "d"}, {"type", "damage_card"}, {"density", 1}, {"card", "nope.h5"}};
  j["bodies"][0]["material"] = "d";
  expect_error(j, "materials[0].card", "file not found");
  j = base_input();
  j.erase("time");
  expect_error(j, "time.end", "is required: must be a number in (0, 1000000] s");
  j = base_input();
  j["cracks"] = json::array({{{"name", "c"}, {"points", json::array({json::array({0.5, 0.1})})}}});
  expect_error(j, "cracks[0].points", ">= 2 points");
  const json crack = {
      {"name", "c"},
      {"points", json::array({json::array({0.0, 0.2001}), json::array({0.5, 0.2001})})}};
  j = base_input();
  j["cracks"] = json::array({crack});
  j["cracks"][0]["tips"] = "middle";
  expect_error(j, "cracks[0].tips", "\"start\", \"end\", \"both\" or \"none\"");
  j = base_input();
  j["cracks"] = json::array({crack});
  j["cracks"][0]["j_radius"] = json::array({0.2, 0.1});
  expect_error(j, "cracks[0].j_radius", "r_inner < r_outer");
  j = base_input();
  j["cracks"] = json::array({crack});
  j["cracks"][0]["growth"] = {{"Gc", -1}};
  expect_error(j, "cracks[0].growth.Gc", "must be a number > 0 J/m^2");
  j = base_input();
  j["cracks"] = json::array({crack});
  j["cracks"][0]["growth"] = {{"Gc", 1}, {"direction", json::array({0, 0})}};
  expect_error(j, "cracks[0].growth.direction", "non-zero");
  j = base_input();
  j["cracks"] = json::array({crack});
  j["cracks"][0]["growth"] = {{"Gc", 1}, {"speed", 1}};
  expect_error(j, "cracks[0].growth.speed", "unknown key");
  j = base_input();
  j["damping"] = -1;
  expect_error(j, "damping", "must be a number >= 0 1/s");
  j = base_input();
  j["fracture_every"] = 0;
  expect_error(j, "fracture_every", "integer in [1,");
}

// The crack keys reach the solver: tips, J radii, growth controls, damping.
TEST(GimpInput, CrackGrowthKeys) {
  json j = base_input();
  j["cracks"] = json::array(
      {{{"name", "c"},
        {"points", json::array({json::array({0.0, 0.2001}), json::array({0.5, 0.2001})})},
        {"tips", "end"},
        {"j_radius", json::array({0.0, 0.1})},
        {"growth",
         {{"Gc", 100.0},
          {"GIIc", 300.0},
          {"increment", 0.01},
          {"direction", json::array({0, 2})},
          {"max_increments", 7}}}}});
  j["damping"] = 50.0;
  j["fracture_every"] = 3;
  Solver<2> s;
  const RunConfig rc = load_input_text<2>(j.dump(), "in.json", "", s);
  ASSERT_EQ(s.cracks.size(), 1u);
  const Crack& c = s.cracks[0];
  EXPECT_EQ(c.tip[0], 0);
  EXPECT_EQ(c.tip[1], 1);
  EXPECT_EQ(c.j_inner, 0.0);
  EXPECT_EQ(c.j_outer, 0.1);
  EXPECT_EQ(c.growth.Gc, 100.0);
  EXPECT_EQ(c.growth.GIIc, 300.0);
  EXPECT_EQ(c.growth.increment, 0.01);
  EXPECT_TRUE(c.growth.prescribed);
  EXPECT_EQ(c.growth.direction, Eigen::Vector2d(0, 1));
  EXPECT_EQ(c.growth.max_increments, 7);
  EXPECT_EQ(s.damping, 50.0);
  EXPECT_EQ(rc.fracture_every, 3);
}

TEST(GimpInput, ParticleCsvAndDamageCard) {
  const fs::path d = tmpdir("csv");
  {
    std::ofstream f(d / "p.csv");
    f << "x,y,volume,vx,vy\n0.2,0.2,0.0004,1,0\n0.22,0.2,0.0004,1,0\n";
  }
  pnc::damage::write_card((d / "card.h5").string(),
                          pnc::damage::card_from_parameters(
                              pnc::damage::dissertation_parameters(pnc::damage::Model::pp), "test"),
                          "test");
  json j = base_input();
  j["materials"][0] = {
      {"name", "ndm"}, {"type", "damage_card"}, {"density", 1200}, {"card", "card.h5"}};
  j["bodies"] = json::array({{{"material", "ndm"}, {"shape", "particles"}, {"file", "p.csv"}}});
  j["boundaries"] = json::array();
  j.erase("loads");
  Solver<2> s;
  load_input_text<2>(j.dump(), "in.json", d.string(), s);
  ASSERT_EQ(s.particles.size(), 2u);
  EXPECT_NEAR(s.particles.l[0][0], 0.01, 1e-12);
  EXPECT_NEAR(s.particles.v[1][0], 1.0, 0);
  EXPECT_EQ(s.materials[0]->type(), "damage_card");
  EXPECT_EQ(s.materials[0]->n_state(), 2);
}

// ---------------------------------------------------------------------------------------------
// 3-D planar cracks (D42): input and errors.

// The crack keys of 3-D: corners, automatic and explicit fronts, J radii; every rule broken
// is an input error naming the key and the rule.
TEST(GimpInput, PlanarCrack3DKeysAndErrors) {
  {
    Solver<3> s;
    load_input_text<3>(slab3d().dump(), "in.json", "", s);
    ASSERT_EQ(s.cracks.size(), 1u);
    EXPECT_EQ(s.cracks[0].corners.size(), 4u);
    EXPECT_EQ(s.cracks[0].front, (std::vector<int>{0, 1, 0, 0})); // auto: material ahead
    EXPECT_NEAR(std::abs(s.cracks[0].normal[1]), 1.0, 1e-15);
    json j = slab3d();
    j["cracks"][0]["front"] = json::array({1});
    j["cracks"][0]["j_radius"] = json::array({0.1, 0.3});
    Solver<3> s2;
    load_input_text<3>(j.dump(), "in.json", "", s2);
    EXPECT_EQ(s2.cracks[0].front, (std::vector<int>{0, 1, 0, 0}));
    EXPECT_EQ(s2.cracks[0].j_outer, 0.3);
  }
  auto expect_error = [](const json& j, const std::string& key, const std::string& rule) {
    Solver<3> s;
    std::string msg;
    try {
      load_input_text<3>(j.dump(), "in.json", "", s);
    } catch (const pnc::InputError& e) {
      msg = e.what();
    }
    EXPECT_NE(msg.find("in.json"), std::string::npos) << key << ": " << msg;
    EXPECT_NE(msg.find("'" + key + "'"), std::string::npos) << msg;
    EXPECT_NE(msg.find(rule), std::string::npos) << msg;
  };
  json j = slab3d();
  j["cracks"][0]["corners"][2][1] = 0.01; // one corner off the plane
  expect_error(j, "cracks[0].corners", "non-planar: corner");
  j = slab3d();
  j["cracks"][0]["corners"] = json::array({json::array({0, 0, 0}), json::array({1, 0, 0})});
  expect_error(j, "cracks[0].corners", ">= 3 corners");
  j = slab3d();
  j["cracks"][0]["corners"][1] = json::array({0.2, 1e-7, -0.1}); // collinear with 0 and ...
  j["cracks"][0]["corners"].insert(j["cracks"][0]["corners"].begin() + 2,
                                   json::array({0.5625, 1e-7, -0.1}));
  expect_error(j, "cracks[0].corners", "collinear");
  j = slab3d();
  j["cracks"][0]["corners"][1] = j["cracks"][0]["corners"][0];
  expect_error(j, "cracks[0].corners", "degenerate");
  j = slab3d();
  std::swap(j["cracks"][0]["corners"][1], j["cracks"][0]["corners"][2]); // a bow tie
  expect_error(j, "cracks[0].corners", "crosses itself");
  j = slab3d();
  j["cracks"][0]["corners"].insert(j["cracks"][0]["corners"].begin() + 2,
                                   json::array({0.2, 1e-7, 0.1})); // a dent in the front
  expect_error(j, "cracks[0].corners", "not convex: the polygon turns the other way at corner 2");
  j = slab3d();
  j["cracks"][0]["corners"][2][2] = 0.1; // the front ends inside the slab
  j["cracks"][0]["corners"][3][2] = 0.1;
  expect_error(j, "cracks[0].corners", "front edge 1");
  j = slab3d();
  j["cracks"][0]["front"] = json::array({4});
  expect_error(j, "cracks[0].front", "edge indices in [0, 3]");
  j = slab3d();
  j["cracks"][0]["front"] = "left";
  expect_error(j, "cracks[0].front", "\"auto\" or an array");
  j = slab3d();
  j["cracks"][0]["front"] = json::array({0}); // a front outside the body: allowed (J = 0)
  {
    Solver<3> s;
    EXPECT_NO_THROW(load_input_text<3>(j.dump(), "in.json", "", s));
  }
  // Growth (D43): the 2-D keys; the front advances in the crack plane, normal to itself, so
  // "direction" (hoop, i.e. kinking out of the plane by the mode mix, or prescribed) is an
  // error in 3-D.
  j = slab3d();
  j["cracks"][0]["growth"] = {
      {"Gc", 100.0}, {"GIIc", 300.0}, {"increment", 0.01}, {"max_increments", 7}};
  {
    Solver<3> s;
    load_input_text<3>(j.dump(), "in.json", "", s);
    const CrackGrowth& g = s.cracks[0].growth;
    EXPECT_EQ(g.Gc, 100.0);
    EXPECT_EQ(g.GIIc, 300.0);
    EXPECT_EQ(g.increment, 0.01);
    EXPECT_EQ(g.max_increments, 7);
    EXPECT_FALSE(g.prescribed);
    j["cracks"][0]["growth"].erase("increment");
    Solver<3> s2;
    load_input_text<3>(j.dump(), "in.json", "", s2);
    EXPECT_EQ(s2.cracks[0].growth.increment, 0.125); // default h
  }
  j = slab3d();
  j["cracks"][0]["growth"] = {{"Gc", 1}, {"direction", "hoop"}};
  expect_error(j, "cracks[0].growth.direction", "kinking out of the plane");
  j["cracks"][0]["growth"]["direction"] = json::array({1, 0, 0});
  expect_error(j, "cracks[0].growth.direction", "in 3-D a front advances in the crack plane");
  j["cracks"][0]["growth"] = {{"Gc", -1}};
  expect_error(j, "cracks[0].growth.Gc", "must be a number > 0 J/m^2");
  j = slab3d();
  j["cracks"][0]["points"] = json::array({json::array({0, 0, 0}), json::array({1, 0, 0})});
  expect_error(j, "cracks[0].points", "planar polygon");
  j = slab3d();
  j["cracks"][0]["tips"] = "end";
  expect_error(j, "cracks[0].tips", "front");
  j = slab3d();
  j["cracks"][0]["normal"] = json::array({0, 1, 0});
  expect_error(j, "cracks[0].normal", "unknown key");
}

// ------------------------------------------------------------------ hardening of the input
// time.end has a stated range; a fixed dt may not exceed the CFL step the solver computes for
// the input (Solver::stable_dt, cfl h / (c + |v|max)); the message names both steps.
TEST(GimpInput, TimeEndRangeAndFixedDtAboveTheCflStepAreRefused) {
  Solver<2> probe;
  load_input_text<2>(base_input().dump(), "in.json", "", probe);
  const double cfl_dt = probe.stable_dt();
  ASSERT_GT(cfl_dt, 0.0);
  json j = base_input();
  j["time"]["end"] = 1e300;
  std::string m = error_of(j);
  EXPECT_NE(m.find("in.json: field 'time.end': value '1e+300'"), std::string::npos) << m;
  EXPECT_NE(m.find("must be a number in (0, 1000000] s"), std::string::npos) << m;
  j = base_input();
  j["time"]["dt"] = 3 * cfl_dt;
  m = error_of(j);
  EXPECT_NE(m.find("field 'time.dt'"), std::string::npos) << m;
  EXPECT_NE(m.find("exceeds the CFL step"), std::string::npos) << m;
  std::ostringstream both;
  both.precision(6);
  both << 3 * cfl_dt << " s exceeds the CFL step " << cfl_dt << " s";
  EXPECT_NE(m.find(both.str()), std::string::npos) << m;
  j["time"]["dt"] = 0.5 * cfl_dt; // below the CFL step: accepted
  EXPECT_EQ(error_of(j), "");
  // Without max_steps the run must end in at most 1e10 steps; with max_steps it is bounded.
  j = base_input();
  j["time"]["end"] = 1e6;
  EXPECT_NE(error_of(j).find("more than 1e10"), std::string::npos);
  j["time"]["max_steps"] = 10;
  EXPECT_EQ(error_of(j), "");
}

// Deeply nested input is an InputError naming the file (not a crash while printing it); a
// number that does not fit a double is an InputError, not an internal error.
TEST(GimpInput, DeepNestingAndNumberOverflowAreInputErrors) {
  Solver<2> s;
  const std::string deep =
      "{\"dimension\": 2, \"title\": " + std::string(60000, '[') + std::string(60000, ']') + "}";
  try {
    load_input_text<2>(deep, "deep.json", "", s);
    ADD_FAILURE() << "accepted";
  } catch (const pnc::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("deep.json"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("nest deeper than 64"), std::string::npos) << e.what();
  }
  std::string big = base_input().dump();
  big.replace(big.find("1200"), 4, "1e400");
  try {
    load_input_text<2>(big, "big.json", "", s);
    ADD_FAILURE() << "accepted";
  } catch (const pnc::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("big.json: not valid JSON"), std::string::npos)
        << e.what();
  }
  // A wrong value deep inside a large array is shown capped, not dumped whole.
  json j = base_input();
  j["materials"][0]["E"] = json::array();
  for (int i = 0; i < 10000; ++i)
    j["materials"][0]["E"].push_back(i);
  const std::string m = error_of(j);
  EXPECT_NE(m.find("materials[0].E"), std::string::npos) << m.substr(0, 300);
  EXPECT_LT(m.size(), 400u);
}
