// The uGIMP solver on one and two threads and with empty grid around the body: the same numbers
// to round-off (thread copies of the grid, D406-D411), and no bit changed by empty nodes.
#include "solver_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace pnc::gimp;
using namespace pnc_gimp_test;

TEST(GimpSolver, OneAndTwoThreadsAgreeToRoundOff) {
  Solver<2> a = bar_2d(40, 1, 1e-2, true), b = bar_2d(40, 2, 1e-2, true);
  const double dt = a.stable_dt();
  for (int k = 0; k < 300; ++k) {
    a.step(dt);
    b.step(dt);
  }
  const auto [dx, ds, smax] = differences(a, b);
  EXPECT_LT(dx, 1e-14);
  EXPECT_LT(ds, 1e-10 * smax);
  EXPECT_GT(smax, 0.0);
  EXPECT_NEAR(a.energy.kinetic, b.energy.kinetic, 1e-12 * a.energy.kinetic);
}

namespace {
/// A block of `cells`^D cells (2 particles per cell per axis) that translates diagonally across the
/// grid (several cells over the run) with a sinusoidal velocity on top (stresses), sorted by
/// cell every 4 steps: every thread's particles, and so the nodes its grid copy touches,
/// change from step to step (D410's ranges).
template <int D> Solver<D> moving_block(int threads, int cells, int extra_nodes = 0) {
  using Vec = Eigen::Matrix<double, D, 1>;
  Solver<D> s;
  s.grid.h = 0.1;
  for (int a = 0; a < D; ++a) {
    s.grid.origin[a] = 0.0;
    s.grid.n[a] = cells + 12 + extra_nodes;
  }
  s.materials.push_back(std::make_shared<LinearElastic>(1000, 1e7, 0.3));
  fill_box<D>(s, Vec::Constant(0.4), Vec::Constant(0.4 + 0.1 * cells), 2, 0);
  const double c = s.materials[0]->wave_speed();
  for (std::size_t p = 0; p < s.particles.size(); ++p)
    for (int a = 0; a < D; ++a) {
      const double x = s.particles.x[p][(a + 1) % D];
      s.particles.v[p][a] =
          c * (0.05 / (a + 1) + 0.01 * std::sin(M_PI * (x - 0.4) / (0.1 * cells)));
    }
  s.threads = threads;
  s.sort_every = 4;
  s.initialize();
  return s;
}
template <int D> void expect_threads_agree(int cells, int steps) {
  Solver<D> one = moving_block<D>(1, cells);
  const double dt = one.stable_dt();
  const Eigen::Matrix<double, D, 1> start = one.particles.x[0];
  for (int k = 0; k < steps; ++k)
    one.step(dt);
  // the block moved by more than two cells (so the copies' nodes moved with it)
  double moved = 1e300;
  for (std::size_t p = 0; p < one.particles.size(); ++p)
    moved = std::min(moved, (one.particles.x[p] - one.particles.x0[p]).norm());
  EXPECT_GT(moved, 2 * one.grid.h) << "start " << start.transpose();
  for (int threads : {2, 3}) {
    Solver<D> b = moving_block<D>(threads, cells);
    for (int k = 0; k < steps; ++k)
      b.step(dt);
    // the same particles by identity (the sort reorders both runs alike: same positions)
    const auto [dx, ds, smax] = differences(one, b);
    // round-off of reassociated node sums over the steps (positions ~1 m, u = 1.1e-16)
    EXPECT_LT(dx, 1e-12) << threads << " threads";
    EXPECT_LT(ds, 1e-8 * smax) << threads << " threads";
    EXPECT_GT(smax, 0.0);
    EXPECT_NEAR(one.energy.kinetic, b.energy.kinetic, 1e-10 * one.energy.kinetic);
  }
}
} // namespace

namespace {
/// moving_block() with the nodes below the block's start (y <= 0.45) moving with the block's
/// mean y velocity (a boundary condition the block leaves: its reaction is non-zero while
/// the block's stencils reach those nodes), and those above y = 0.95 likewise (one the block
/// enters: nodes that held a boundary velocity before any particle reached them).
template <int D> Solver<D> moving_block_with_bc(int threads, int extra_nodes) {
  Solver<D> s = moving_block<D>(threads, 4, extra_nodes);
  NodeBC<D> bc;
  bc.name = "carrier";
  bc.lo = Eigen::Matrix<double, D, 1>::Constant(-1.0);
  bc.hi = Eigen::Matrix<double, D, 1>::Constant(10.0);
  bc.hi[1] = 0.45;
  bc.mask[1] = true;
  bc.velocity[1] = 0.025 * s.materials[0]->wave_speed();
  // and the nodes at y >= 0.95, which the block's top reaches during the run, moving alike
  NodeBC<D> top = bc;
  top.name = "ceiling";
  top.lo[1] = 0.95;
  top.hi[1] = 10.0;
  s.bcs = {bc, top};
  s.initialize();
  return s;
}
template <int D> void expect_same_bits(const Solver<D>& a, const Solver<D>& b) {
  ASSERT_EQ(a.particles.size(), b.particles.size());
  int differ = 0;
  for (std::size_t p = 0; p < a.particles.size(); ++p)
    differ += (a.particles.x[p] != b.particles.x[p]) + (a.particles.v[p] != b.particles.v[p]) +
              (a.particles.sigma[p] != b.particles.sigma[p]);
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(a.energy.kinetic, b.energy.kinetic);
  EXPECT_EQ(a.energy.strain, b.energy.strain);
  EXPECT_EQ(a.energy.boundary_work, b.energy.boundary_work);
  EXPECT_TRUE(a.bcs[0].reaction == b.bcs[0].reaction);
}
template <int D> void expect_wide_grid_same_bits(int steps) {
  std::vector<Solver<D>> tight_runs;
  for (int threads : {1, 2}) {
    Solver<D> tight = moving_block_with_bc<D>(threads, 0),
              wide = moving_block_with_bc<D>(threads, 23);
    const double dt = tight.stable_dt();
    double reaction = 0.0; // the boundary condition acted on the block (not a vacuous test)
    for (int k = 0; k < steps; ++k) {
      tight.step(dt);
      wide.step(dt);
      reaction = std::max(reaction, std::abs(tight.bcs[0].reaction[1]));
    }
    EXPECT_GT(reaction, 0.0);
    EXPECT_NE(tight.bcs[1].reaction[1], 0.0) << "the block has reached the ceiling's nodes";
    EXPECT_TRUE(tight.bcs[1].reaction == wide.bcs[1].reaction);
    EXPECT_EQ(tight.bcs[0].reaction[1], 0.0) << "the block has left the boundary's nodes";
    expect_same_bits(tight, wide);
    tight_runs.push_back(std::move(tight));
  }
  // 1 thread (the global arrays zeroed where written, velocities of the boundary's nodes
  // included) against 2 (thread copies): the same to round-off of reassociated node sums
  const Solver<D>&one = tight_runs[0], &two = tight_runs[1];
  const auto [dx, ds, smax] = differences(one, two);
  EXPECT_LT(dx, 1e-12);
  EXPECT_LT(ds, 1e-8 * smax);
  EXPECT_NE(one.energy.boundary_work, 0.0);
  EXPECT_NEAR(one.energy.boundary_work, two.energy.boundary_work,
              1e-8 * std::abs(one.energy.boundary_work));
}
} // namespace

// The node passes run over the nodes the particles touch now or touched in the last step
// (D411): empty grid around the body changes no bit, with a boundary condition whose nodes
// the body leaves (their reaction must drop to zero), on 1 and 2 threads.
TEST(GimpSolver, EmptyGridAroundTheBodyChangesNoBit2D) {
  expect_wide_grid_same_bits<2>(200);
}
TEST(GimpSolver, EmptyGridAroundTheBodyChangesNoBit3D) {
  expect_wide_grid_same_bits<3>(120);
}

// The thread copies are zeroed and summed only over the nodes they touched (D410): particles
// that cross the grid and are re-sorted give the 1-thread answer with 2 and 3 threads.
TEST(GimpSolver, ThreadCopiesFollowParticlesAcrossTheGrid2D) {
  expect_threads_agree<2>(8, 240);
}
TEST(GimpSolver, ThreadCopiesFollowParticlesAcrossTheGrid3D) {
  expect_threads_agree<3>(4, 120);
}
