// The JSON input (errors name key, value, rule) and the run driver (outputs, resume).
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
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

json base_input() {
  return json::parse(R"({
    "dimension": 2,
    "grid": {"origin": [0, 0], "cells": [24, 8], "cell_size": 0.05},
    "particles_per_cell": 2,
    "materials": [{"name": "poly", "type": "hyperelastic_polymer", "density": 1200,
                   "E": 1.5e9, "nu": 0.33}],
    "bodies": [{"material": "poly", "shape": "box", "min": [0.05, 0.1], "max": [1.05, 0.3],
                "holes": [{"shape": "circle", "center": [0.5, 0.2], "radius": 0.04},
                          {"shape": "box", "min": [0.8, 0.1], "max": [0.82, 0.15]}]}],
    "boundaries": [{"name": "left", "min": [0.05, 0], "max": [0.05, 0.4], "fix": "all"}],
    "loads": {"tractions": [{"name": "pull", "min": [1.0, 0.1], "max": [1.05, 0.3],
                             "axis": "x", "traction": [1e6, 0], "ramp": [0, 2e-4]}]},
    "time": {"end": 4e-4, "cfl": 0.4},
    "output": {"interval": 1e-4, "vtu": "binary", "history_every": 5},
    "threads": 2
  })");
}

std::string error_of(const json& j) {
  Solver<2> s;
  try {
    load_input_text<2>(j.dump(), "in.json", "", s);
  } catch (const pnc::InputError& e) {
    return e.what();
  }
  return "";
}

fs::path tmpdir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("pnc_gimp_test_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// The same input run straight through (DIR/straight) and interrupted after `stop` steps
/// then resumed (DIR/split): the three summaries of the resume tests.
struct StraightAndSplit {
  RunSummary straight, interrupted, resumed;
};
StraightAndSplit run_straight_and_split(const std::filesystem::path& d, long stop) {
  RunOptions o;
  o.input = (d / "in.json").string();
  o.progress = false;
  o.plot = false;
  o.out_dir = (d / "straight").string();
  StraightAndSplit r;
  r.straight = run(o);
  o.out_dir = (d / "split").string();
  o.stop_after_steps = stop;
  r.interrupted = run(o);
  o.stop_after_steps = 0;
  o.resume = true;
  r.resumed = run(o);
  return r;
}

/// D335: the history's energy columns end in `energy` (_J_per_m in 2-D, _J in 3-D), its
/// reactions in `force` (_N_per_m, _N), time and step size in _s.
void expect_history_units(const std::vector<std::string>& cols, const std::string& energy,
                          const std::string& force) {
  const std::vector<std::string> head = {"step",
                                         "time_s",
                                         "dt_s",
                                         "kinetic" + energy,
                                         "strain" + energy,
                                         "external_work" + energy,
                                         "boundary_work" + energy,
                                         "balance" + energy};
  ASSERT_GE(cols.size(), head.size());
  EXPECT_EQ(std::vector<std::string>(cols.begin(), cols.begin() + 8), head);
  int reactions = 0;
  for (const auto& c : cols)
    if (c.rfind("reaction_", 0) == 0) {
      ++reactions;
      EXPECT_EQ(c.substr(c.size() - force.size()), force) << c;
    }
  EXPECT_GT(reactions, 0);
  EXPECT_NE(std::find(cols.begin(), cols.end(), "damping_work" + energy), cols.end());
}
} // namespace

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

TEST(GimpRun, WritesFramesHistoryCheckpointAndResumes) {
  const fs::path d = tmpdir("run");
  {
    std::ofstream f(d / "in.json");
    f << base_input().dump(2);
  }
  RunOptions o;
  o.input = (d / "in.json").string();
  o.out_dir = (d / "out").string();
  o.progress = false;
  o.plot = false;
  const RunSummary a = run(o);
  EXPECT_NEAR(a.time, 4e-4, 1e-15);
  EXPECT_EQ(a.frames, 5);
  EXPECT_TRUE(fs::exists(d / "out/particles.pvd"));
  EXPECT_TRUE(fs::exists(d / "out/frames/particles_000004.vtu"));
  EXPECT_TRUE(fs::exists(d / "out/history.csv"));
  EXPECT_GT(a.energy.external_work, 0.0);
  // Traction work goes into kinetic + strain energy (fixed wall: no boundary work).
  EXPECT_LT(std::abs(a.energy.balance()), 0.02 * a.energy.external_work);
  EXPECT_NEAR(a.energy.boundary_work, 0.0, 1e-12 * a.energy.external_work);
  // The reaction at the wall: the wall carries a force opposite to the traction
  // (dynamic, so not equal yet).
  ASSERT_EQ(a.reactions.size(), 1u);

  // A resume with a changed input file is refused.
  {
    json j = base_input();
    j["time"]["end"] = 5e-4;
    std::ofstream f(d / "in.json");
    f << j.dump(2);
  }
  o.resume = true;
  std::string msg;
  try {
    run(o);
  } catch (const pnc::InputError& e) {
    msg = e.what();
  }
  // naming the input file, the key that differs and both values (D339)
  EXPECT_NE(msg.find((d / "in.json").string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("time.end"), std::string::npos) << msg;
  EXPECT_NE(msg.find("0.0005"), std::string::npos) << msg;
  EXPECT_NE(msg.find("differs from the input this run was started with"), std::string::npos) << msg;
}

TEST(GimpRun, ResumeContinuesBitForBit) {
  const fs::path d = tmpdir("resume");
  json j = base_input();
  j["time"]["max_steps"] = 40;
  j["output"]["interval"] = 0.5e-4;
  {
    std::ofstream f(d / "in.json");
    f << j.dump(2);
  }
  // 40 steps in one go, and interrupted after 17 steps then resumed
  const auto [a, b1, b] = run_straight_and_split(d, 17);
  EXPECT_EQ(b1.steps, 17);
  EXPECT_TRUE(b.resumed);
  EXPECT_GT(a.steps, 17);
  EXPECT_EQ(b.steps, a.steps);
  EXPECT_EQ(b.steps_this_run, a.steps - 17);
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.energy.kinetic, b.energy.kinetic);
  EXPECT_EQ(a.energy.external_work, b.energy.external_work);
  Solver<2> sa, sb;
  load_input<2>((d / "in.json").string(), sa);
  load_input<2>((d / "in.json").string(), sb);
  sa.initialize();
  sb.initialize();
  CheckpointExtra xa, xb;
  read_checkpoint<2>((d / "straight/checkpoint.h5").string(), sa, xa);
  read_checkpoint<2>((d / "split/checkpoint.h5").string(), sb, xb);
  for (std::size_t p = 0; p < sa.particles.size(); ++p) {
    EXPECT_EQ(sa.particles.x[p], sb.particles.x[p]);
    EXPECT_EQ(sa.particles.sigma[p], sb.particles.sigma[p]);
  }
  EXPECT_EQ(xa.history.rows, xb.history.rows);
  EXPECT_EQ(xa.frame_times, xb.frame_times);
}

// A crack that grows before and after the interruption: the grown crack (points, tip flags,
// increments), the damping work and the J columns of the history are restored, and the
// resumed run matches the uninterrupted one bit for bit.
TEST(GimpRun, ResumeWithGrowingCrackContinuesBitForBit) {
  const fs::path d = tmpdir("resume_crack");
  const json j = json::parse(R"({
    "dimension": 2,
    "grid": {"origin": [-0.25, -1.25], "cells": [10, 20], "cell_size": 0.125},
    "materials": [{"name": "m", "type": "linear_elastic", "density": 1000, "E": 1e7, "nu": 0.3}],
    "bodies": [{"material": "m", "shape": "box", "min": [0, -1], "max": [1, 1]}],
    "cracks": [{"name": "c", "points": [[-0.1, 1e-7], [0.5625, 1e-7]],
                "growth": {"Gc": 1e-12, "increment": 0.0625, "max_increments": 3}}],
    "boundaries": [{"name": "sym", "min": [-1, -2], "max": [0, 2], "symmetry": "x"}],
    "loads": {"tractions": [
      {"name": "top", "min": [0, 0.95], "max": [1, 1], "axis": "y", "traction": [0, 1e4]},
      {"name": "bottom", "min": [0, -1], "max": [1, -0.95], "axis": "y", "traction": [0, -1e4]}]},
    "damping": 100,
    "fracture_every": 5,
    "time": {"end": 1, "max_steps": 40},
    "output": {"interval": 0, "history_every": 4}
  })");
  {
    std::ofstream f(d / "in.json");
    f << j.dump(2);
  }
  const auto [a, b1, b] = run_straight_and_split(d, 12);
  EXPECT_EQ(a.crack_increments, 3);
  EXPECT_GT(b1.crack_increments, 0); // grew before the interruption ...
  EXPECT_GT(b.crack_increments, 0);  // ... and after it
  EXPECT_EQ(b1.crack_increments + b.crack_increments, 3);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.energy.kinetic, b.energy.kinetic);
  EXPECT_EQ(a.energy.damping_work, b.energy.damping_work);
  EXPECT_LT(a.energy.damping_work, 0.0);
  Solver<2> sa, sb;
  load_input<2>((d / "in.json").string(), sa);
  load_input<2>((d / "in.json").string(), sb);
  sa.initialize();
  sb.initialize();
  CheckpointExtra xa, xb;
  read_checkpoint<2>((d / "straight/checkpoint.h5").string(), sa, xa);
  read_checkpoint<2>((d / "split/checkpoint.h5").string(), sb, xb);
  ASSERT_EQ(sa.cracks[0].points.size(), 5u);
  EXPECT_EQ(sa.cracks[0].points, sb.cracks[0].points);
  EXPECT_EQ(sb.cracks[0].increments, 3);
  for (std::size_t p = 0; p < sa.particles.size(); ++p)
    EXPECT_EQ(sa.particles.x[p], sb.particles.x[p]);
  EXPECT_EQ(xa.history.columns, xb.history.columns);
  EXPECT_NE(std::find(xa.history.columns.begin(), xa.history.columns.end(), "J_c_end_J_per_m2"),
            xa.history.columns.end());
  expect_history_units(xa.history.columns, "_J_per_m", "_N_per_m"); // 2-D: per thickness
  for (const char* c : {"length_c_end_m", "tipx_c_end_m", "tipy_c_end_m", "GII_c_end_J_per_m2"})
    EXPECT_NE(std::find(xa.history.columns.begin(), xa.history.columns.end(), c),
              xa.history.columns.end())
        << c;
  EXPECT_EQ(xa.history.rows, xb.history.rows);
}

namespace {
std::vector<unsigned char> unbase64(const std::string& s) {
  auto val = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<unsigned char> out;
  unsigned buf = 0;
  int bits = 0;
  for (char c : s) {
    const int v = val(c);
    if (v < 0) continue;
    buf = (buf << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((buf >> bits) & 0xFF));
    }
  }
  return out;
}
/// The text between <DataArray ... Name="name" ...> and </DataArray>.
std::string data_array(const std::string& xml, const std::string& name) {
  const auto a = xml.find("Name=\"" + name + "\"");
  const auto b = xml.find('>', a) + 1;
  const auto e = xml.find("</DataArray>", b);
  return xml.substr(b, e - b);
}
} // namespace

TEST(GimpOutput, Base64MatchesRfc4648) {
  const std::string t = "Many hands make light work.";
  EXPECT_EQ(base64(reinterpret_cast<const unsigned char*>(t.data()), t.size()),
            "TWFueSBoYW5kcyBtYWtlIGxpZ2h0IHdvcmsu");
  EXPECT_EQ(base64(reinterpret_cast<const unsigned char*>("ab"), 2), "YWI=");
  EXPECT_EQ(base64(reinterpret_cast<const unsigned char*>("a"), 1), "YQ==");
}

TEST(GimpOutput, VtuAsciiAndBinaryHoldTheParticleData) {
  Solver<2> s;
  load_input_text<2>(base_input().dump(), "in.json", "", s);
  s.initialize();
  s.step(1e-7);
  const fs::path d = tmpdir("vtu");
  for (bool binary : {false, true}) {
    const std::string path = (d / (binary ? "b.vtu" : "a.vtu")).string();
    write_vtu<2>(path, s, binary, {"poly"});
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string xml = ss.str();
    EXPECT_NE(xml.find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
    EXPECT_NE(xml.find("NumberOfPoints=\"" + std::to_string(s.particles.size()) + "\""),
              std::string::npos);
    for (const char* name : {"displacement_m", "velocity_m_per_s", "stress_Pa", "strain_1",
                             "density_kg_per_m3", "volume_m3", "mass_kg",
                             "strain_energy_density_J_per_m3", "material_index", "types", "time_s"})
      EXPECT_NE(xml.find(std::string("Name=\"") + name + "\""), std::string::npos) << name;
    // the symmetric tensors as one 6-component array each (D236)
    for (const char* name : {"stress_Pa", "strain_1"})
      EXPECT_NE(xml.find(std::string("Name=\"") + name + "\" NumberOfTuples=\"" +
                         std::to_string(s.particles.size()) + "\" NumberOfComponents=\"6\""),
                std::string::npos)
          << name;
    std::vector<double> pts;
    const std::string body = data_array(xml, "Points");
    if (binary) {
      const auto bytes = unbase64(body);
      std::uint32_t nb;
      std::memcpy(&nb, bytes.data(), 4);
      ASSERT_EQ(nb, 3 * s.particles.size() * sizeof(double));
      ASSERT_EQ(bytes.size(), 4 + nb);
      pts.resize(nb / sizeof(double));
      std::memcpy(pts.data(), bytes.data() + 4, nb);
    } else {
      std::istringstream in(body);
      double v;
      while (in >> v)
        pts.push_back(v);
    }
    ASSERT_EQ(pts.size(), 3 * s.particles.size());
    for (std::size_t p = 0; p < s.particles.size(); ++p) {
      EXPECT_NEAR(pts[3 * p], s.particles.x[p][0], binary ? 0.0 : 1e-10);
      EXPECT_NEAR(pts[3 * p + 1], s.particles.x[p][1], binary ? 0.0 : 1e-10);
      EXPECT_EQ(pts[3 * p + 2], 0.0);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 3-D planar cracks (D42): input, errors, checkpoint/resume.

namespace {
/// A slab x in [0, 1], y in [-1, 1], z in [0, 0.25] (two cells thick) with a through-thickness
/// edge crack in the plane y = 1e-7 from outside the body to the straight front x = 0.5625,
/// plane strain (u_z = 0 on and beyond both z faces), x-symmetry at x = 0, tension in y.
json slab3d() {
  return json::parse(R"({
    "dimension": 3,
    "grid": {"origin": [-0.25, -1.25, -0.25], "cells": [10, 20, 6], "cell_size": 0.125},
    "materials": [{"name": "m", "type": "linear_elastic", "density": 1000, "E": 1e7, "nu": 0.3}],
    "bodies": [{"material": "m", "shape": "box", "min": [0, -1, 0], "max": [1, 1, 0.25]}],
    "cracks": [{"name": "c", "corners": [[-0.1, 1e-7, -0.1], [0.5625, 1e-7, -0.1],
                                         [0.5625, 1e-7, 0.35], [-0.1, 1e-7, 0.35]]}],
    "boundaries": [{"name": "sym", "min": [-1, -2, -1], "max": [0, 2, 1], "symmetry": "x"},
                   {"name": "z0", "min": [-1, -2, -1], "max": [2, 2, 0], "symmetry": "z"},
                   {"name": "z1", "min": [-1, -2, 0.25], "max": [2, 2, 1], "symmetry": "z"}],
    "loads": {"tractions": [
      {"name": "top", "min": [0, 0.95, 0], "max": [1, 1, 1], "axis": "y", "traction": [0, 1e4, 0]},
      {"name": "bottom", "min": [0, -1, 0], "max": [1, -0.95, 1], "axis": "y",
       "traction": [0, -1e4, 0]}]},
    "damping": 100,
    "time": {"end": 1, "max_steps": 30},
    "output": {"interval": 0, "history_every": 4}
  })");
}
} // namespace

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

// A 3-D run with a growing planar crack (D43; the 3-D twin of
// ResumeWithGrowingCrackContinuesBitForBit): the front-averaged J columns are in the history,
// the grown crack is saved in and restored from the checkpoint, it grows before and after the
// interruption, and the resumed run matches the uninterrupted one bit for bit.
TEST(GimpRun, ResumeWith3DCrackContinuesBitForBit) {
  const fs::path d = tmpdir("resume_crack3d");
  {
    json j = slab3d();
    j["cracks"][0]["growth"] = {{"Gc", 1e-12}, {"increment", 0.0625}, {"max_increments", 3}};
    j["fracture_every"] = 5;
    j["time"]["max_steps"] = 40;
    std::ofstream f(d / "in.json");
    f << j.dump(2);
  }
  const auto [a, b1, b] = run_straight_and_split(d, 12);
  EXPECT_TRUE(b.resumed);
  EXPECT_EQ(a.crack_increments, 3);
  EXPECT_GT(b1.crack_increments, 0); // grew before the interruption ...
  EXPECT_GT(b.crack_increments, 0);  // ... and after it
  EXPECT_EQ(b1.crack_increments + b.crack_increments, 3);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.energy.kinetic, b.energy.kinetic);
  EXPECT_EQ(a.energy.damping_work, b.energy.damping_work);
  Solver<3> sa, sb;
  load_input<3>((d / "in.json").string(), sa);
  load_input<3>((d / "in.json").string(), sb);
  sa.initialize();
  sb.initialize();
  sb.cracks[0].corners.clear(); // must come back from the checkpoint
  sb.cracks[0].front.clear();
  CheckpointExtra xa, xb;
  read_checkpoint<3>((d / "straight/checkpoint.h5").string(), sa, xa);
  read_checkpoint<3>((d / "split/checkpoint.h5").string(), sb, xb);
  EXPECT_EQ(sa.cracks[0].corners, sb.cracks[0].corners);
  ASSERT_EQ(sb.cracks[0].corners.size(), 4u);
  EXPECT_EQ(sb.cracks[0].increments, 3);
  EXPECT_NEAR((sb.cracks[0].corners[1] - Eigen::Vector3d(0.75, 1e-7, -0.1)).norm(), 0, 1e-12);
  EXPECT_NEAR((sb.cracks[0].corners[2] - Eigen::Vector3d(0.75, 1e-7, 0.35)).norm(), 0, 1e-12);
  EXPECT_EQ(sb.cracks[0].front, (std::vector<int>{0, 1, 0, 0}));
  for (std::size_t p = 0; p < sa.particles.size(); ++p)
    EXPECT_EQ(sa.particles.x[p], sb.particles.x[p]);
  EXPECT_EQ(xa.history.columns, xb.history.columns);
  expect_history_units(xa.history.columns, "_J", "_N"); // 3-D: whole body
  const auto col =
      std::find(xa.history.columns.begin(), xa.history.columns.end(), "J_c_front1_J_per_m2");
  ASSERT_NE(col, xa.history.columns.end());
  EXPECT_EQ(xa.history.rows, xb.history.rows);
  const auto k = static_cast<std::size_t>(col - xa.history.columns.begin());
  EXPECT_GT(xa.history.rows.back()[k], 0.0); // loaded: J > 0
  std::ifstream sj(d / "straight/summary.json");
  const json summary = json::parse(sj);
  EXPECT_EQ(summary["cracks"][0]["fronts"][0]["edge"], 1);
  EXPECT_EQ(summary["cracks"][0]["increments"], 3);
  const auto len =
      std::find(xa.history.columns.begin(), xa.history.columns.end(), "length_c_front1_m");
  ASSERT_NE(len, xa.history.columns.end());
  const auto kl = static_cast<std::size_t>(len - xa.history.columns.begin());
  EXPECT_NEAR(xa.history.rows.front()[kl], 0.6625, 1e-12);
  EXPECT_NEAR(xa.history.rows.back()[kl], 0.6625 + 3 * 0.0625, 1e-12);
  EXPECT_NEAR(summary["cracks"][0]["fronts"][0]["front_length_m"].get<double>(), 0.25, 1e-12);
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
