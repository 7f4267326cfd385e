#pragma once
// Shared by the tests of the GIMP input and run driver (test_input*.cpp): small inputs, the
// error text of an input, a fresh temporary folder, a run straight and interrupted + resumed.
#include "pnc/gimp_coupler/input.hpp"
#include "pnc/gimp_coupler/run.hpp"

#include "pnc/core/error.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace pnc::gimp::test {

namespace fs = std::filesystem;
using json = nlohmann::json;

/// A 2-D plate with two holes, a fixed edge and a ramped traction (SI units).
inline json base_input() {
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

/// The InputError text of reading `j` in 2-D ("" when accepted).
inline std::string error_of(const json& j) {
  Solver<2> s;
  try {
    load_input_text<2>(j.dump(), "in.json", "", s);
  } catch (const pnc::InputError& e) {
    return e.what();
  }
  return "";
}

/// A new, empty, private folder pnc_gimp_test_NAME_XXXXXX under the system temporary folder.
inline fs::path tmpdir(const std::string& name) {
  return pnc::test::fresh_dir("gimp_test_" + name);
}

/// The same input run straight through (DIR/straight) and interrupted after `stop` steps
/// then resumed (DIR/split): the three summaries of the resume tests.
struct StraightAndSplit {
  RunSummary straight, interrupted, resumed;
};
inline StraightAndSplit run_straight_and_split(const std::filesystem::path& d, long stop) {
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
inline void expect_history_units(const std::vector<std::string>& cols, const std::string& energy,
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

/// A slab x in [0, 1], y in [-1, 1], z in [0, 0.25] (two cells thick) with a through-thickness
/// edge crack in the plane y = 1e-7 from outside the body to the straight front x = 0.5625,
/// plane strain (u_z = 0 on and beyond both z faces), x-symmetry at x = 0, tension in y.
inline json slab3d() {
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

} // namespace pnc::gimp::test
