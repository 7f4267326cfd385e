// The GIMP run driver: outputs, checkpoint and bit-for-bit resume (2-D, growing cracks, 3-D).
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
#include <functional>
#include <sstream>

using namespace pnc::gimp;
using namespace pnc::gimp::test;

namespace {

// The solvers of the uninterrupted run (d/straight) and of the interrupted and resumed one
// (d/split) as their checkpoints restore them: the input d/in.json loaded and initialised, then
// `before_split` (e.g. clearing what must come back from the checkpoint), then each checkpoint.
template <int Dim>
void restore_both(const fs::path& d, Solver<Dim>& sa, Solver<Dim>& sb, CheckpointExtra& xa,
                  CheckpointExtra& xb, const std::function<void(Solver<Dim>&)>& before_split = {}) {
  load_input<Dim>((d / "in.json").string(), sa);
  load_input<Dim>((d / "in.json").string(), sb);
  sa.initialize();
  sb.initialize();
  if (before_split) before_split(sb);
  read_checkpoint<Dim>((d / "straight/checkpoint.h5").string(), sa, xa);
  read_checkpoint<Dim>((d / "split/checkpoint.h5").string(), sb, xb);
}

} // namespace

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
  CheckpointExtra xa, xb;
  restore_both(d, sa, sb, xa, xb);
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
  CheckpointExtra xa, xb;
  restore_both(d, sa, sb, xa, xb);
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
  CheckpointExtra xa, xb;
  restore_both<3>(d, sa, sb, xa, xb, [](Solver<3>& s) {
    s.cracks[0].corners.clear(); // must come back from the checkpoint
    s.cracks[0].front.clear();
  });
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
