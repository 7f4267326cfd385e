// Cell sort of the GIMP particles (Solver::sort_particles, sort_every; D354): a sorted run
// agrees with the unsorted run of the same particles within the round-off of the changed
// summation order, and a run is reproducible bit for bit; a large problem's arrays are backed
// by huge pages before and after a sort (D430).
#include "pnc/gimp_coupler/solver.hpp"

#include "common/huge_pages_probe.hpp"
#include "solver_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

using namespace pnc::gimp;

namespace {

/// A 2-D block 16 x 8 cells (h = 1 mm), 2 x 2 particles per cell, added in a shuffled order
/// (a fixed linear congruential sequence), a sinusoidal initial velocity, a fixed left wall, a
/// traction on the right strip and optionally an edge crack from the top to mid-height.
std::unique_ptr<Solver<2>> make_block(int threads, bool crack) {
  auto s = std::make_unique<Solver<2>>();
  s->grid.h = 1e-3;
  s->grid.origin = Eigen::Vector2d(-2e-3, -2e-3);
  s->grid.n = {21, 13};
  s->materials.push_back(std::make_shared<HyperelasticPolymer>(1200, 1.8e8, 1.48e7));
  const double d = 0.5e-3, V = d * d;
  std::vector<Eigen::Vector2d> xs;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 32; ++i)
      xs.emplace_back((i + 0.5) * d, (j + 0.5) * d);
  std::uint64_t r = 12345;
  for (std::size_t k = xs.size() - 1; k > 0; --k) { // Fisher-Yates with a fixed LCG
    r = r * 6364136223846793005ULL + 1442695040888963407ULL;
    std::swap(xs[k], xs[static_cast<std::size_t>((r >> 33) % (k + 1))]);
  }
  Traction<2> tr;
  tr.axis = 0;
  tr.traction = Eigen::Vector2d(2e6, 0.0); // Pa
  for (const auto& x : xs) {
    const Eigen::Vector2d v(std::sin(3.0 * x[0] / 16e-3), 0.3 * std::cos(2.0 * x[1] / 8e-3));
    if (x[0] > 15.5e-3) tr.particles.push_back(s->particles.size());
    s->particles.add(x, Eigen::Vector2d::Constant(0.5 * d), 1200 * V, V, 0, v);
  }
  s->tractions.push_back(tr);
  NodeBC<2> wall;
  wall.lo = Eigen::Vector2d(-1.0, -1.0);
  wall.hi = Eigen::Vector2d(0.0, 1.0);
  wall.mask.fill(true);
  s->bcs.push_back(wall);
  if (crack) {
    Crack c;
    c.points = {Eigen::Vector2d(6.4e-3 + 1e-7, 9e-3), Eigen::Vector2d(6.4e-3 + 1e-7, 4e-3 + 1e-7)};
    s->cracks.push_back(c);
  }
  s->threads = threads;
  s->initialize();
  return s;
}

/// A 3-D block 6 x 4 x 4 cells (h = 1 mm), 2 x 2 x 2 particles per cell in a shuffled order,
/// a sinusoidal initial velocity, a fixed face x <= 0.
std::unique_ptr<Solver<3>> make_block3(int threads) {
  auto s = std::make_unique<Solver<3>>();
  s->grid.h = 1e-3;
  s->grid.origin = Eigen::Vector3d::Constant(-2e-3);
  s->grid.n = {11, 9, 9};
  s->materials.push_back(std::make_shared<HyperelasticPolymer>(1200, 1.8e8, 1.48e7));
  const double d = 0.5e-3, V = d * d * d;
  std::vector<Eigen::Vector3d> xs;
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 12; ++i)
        xs.emplace_back((i + 0.5) * d, (j + 0.5) * d, (k + 0.5) * d);
  std::uint64_t r = 54321;
  for (std::size_t k = xs.size() - 1; k > 0; --k) { // Fisher-Yates with a fixed LCG
    r = r * 6364136223846793005ULL + 1442695040888963407ULL;
    std::swap(xs[k], xs[static_cast<std::size_t>((r >> 33) % (k + 1))]);
  }
  for (const auto& x : xs) {
    const Eigen::Vector3d v(std::sin(3.0 * x[0] / 6e-3), 0.3 * std::cos(2.0 * x[1] / 4e-3),
                            0.2 * std::sin(2.0 * x[2] / 4e-3));
    s->particles.add(x, Eigen::Vector3d::Constant(0.5 * d), 1200 * V, V, 0, v);
  }
  NodeBC<3> wall;
  wall.lo = Eigen::Vector3d::Constant(-1.0);
  wall.hi = Eigen::Vector3d(0.0, 1.0, 1.0);
  wall.mask.fill(true);
  s->bcs.push_back(wall);
  s->threads = threads;
  s->initialize();
  return s;
}

constexpr int kSteps = 40;

template <int D> struct SortRun {
  std::unique_ptr<Solver<D>> s;
  double dt = 0.0;    // time step, s
  double vmax = 0.0;  // largest particle speed over the run, m/s
  double dvmax = 0.0; // largest change of a particle velocity in one step, m/s
};

/// kSteps steps of the solver `make()` builds; with sort_every > 0 the sorting starts after 10
/// steps (the first sort at step 12), so that it permutes particles whose F, sigma, V and
/// states already differ.
template <int D, class Make> SortRun<D> run_with(Make make, int sort_every) {
  using Vec = Eigen::Matrix<double, D, 1>;
  SortRun<D> r{make()};
  r.dt = 0.5 * r.s->stable_dt();
  for (int k = 0; k < kSteps; ++k) {
    if (k == 10) r.s->sort_every = sort_every;
    const std::vector<Vec> v0 = r.s->particles.v;
    const std::vector<std::size_t> o0 = r.s->particle_order();
    r.s->step(r.dt);
    // v0 is in the order before the step's sort: match by initial index
    std::vector<Vec> by_id(v0.size());
    for (std::size_t p = 0; p < v0.size(); ++p)
      by_id[o0[p]] = v0[p];
    const auto& P = r.s->particles;
    for (std::size_t p = 0; p < P.size(); ++p) {
      r.vmax = std::max(r.vmax, P.v[p].norm());
      r.dvmax = std::max(r.dvmax, (P.v[p] - by_id[r.s->particle_order()[p]]).norm());
    }
  }
  return r;
}

SortRun<2> run(int threads, bool crack, int sort_every) {
  return run_with<2>([&] { return make_block(threads, crack); }, sort_every);
}

/// Sorted run vs the unsorted one, particles matched by their initial index. The two runs
/// differ only in the order of the nodal sums of P2G and of the internal forces: each node
/// sums K = 4^D particle terms (2 x 2 particles per cell: 4 per axis within h + l of a node),
/// recursive summation errs by at most (K - 1) u of the sum of |terms| (u = 2^-53), twice per
/// step (momentum, forces). An explicit step within its CFL limit does not amplify a velocity
/// perturbation (S >= 0, sum S = 1 in G2P; the elastic feedback scales with CFL^2 < 1), so the
/// errors add over the N steps; each particle update y += dy of the two runs may also round
/// differently once their inputs differ, 2 u |y| per step. Hence
///   |dv| <= N (2 (K - 1) u (vmax + dvmax) + 2 u vmax),
///   |dx| <= N (dt |dv|max + 2 u xmax)              (x moves by dt v*),
///   |dF| <= N (3^D dt / h |dv|max + 2 u |F|max)    (dt v* (x) grad S, |grad S| <= 1/h).
template <int D> void expect_agree(const SortRun<D>& a, const SortRun<D>& b) {
  const double u = std::numeric_limits<double>::epsilon() / 2;
  const double K = std::pow(4.0, D), nodes = std::pow(3.0, D);
  const double dv = kSteps * (2.0 * (K - 1) * u * (a.vmax + a.dvmax) + 2.0 * u * a.vmax);
  const double dt = a.dt, h = a.s->grid.h;
  ASSERT_EQ(a.dt, b.dt);
  double xmax = 0.0, Fmax = 0.0;
  for (std::size_t p = 0; p < a.s->particles.size(); ++p) {
    xmax = std::max(xmax, a.s->particles.x[p].norm());
    Fmax = std::max(Fmax, a.s->particles.F[p].norm());
  }
  const double dx = kSteps * (dt * dv + 2.0 * u * xmax);
  const double dF = kSteps * (nodes * dt / h * dv + 2.0 * u * Fmax);
  const auto& A = a.s->particles;
  const auto& B = b.s->particles;
  ASSERT_EQ(A.size(), B.size());
  double ex = 0.0, ev = 0.0, eF = 0.0;
  for (std::size_t q = 0; q < B.size(); ++q) {
    const std::size_t p = b.s->particle_order()[q]; // a is never sorted: index = initial index
    ASSERT_EQ(a.s->particle_order()[p], p);
    ex = std::max(ex, (A.x[p] - B.x[q]).norm());
    ev = std::max(ev, (A.v[p] - B.v[q]).norm());
    eF = std::max(eF, (A.F[p] - B.F[q]).norm());
    EXPECT_EQ(A.x0[p], B.x0[q]);
  }
  std::printf("sorted vs unsorted: |dv| %.2e of bound %.2e m/s, |dx| %.2e of %.2e m, |dF| %.2e "
              "of %.2e\n",
              ev, dv, ex, dx, eF, dF);
  EXPECT_LE(ev, dv) << "vmax " << a.vmax << " m/s";
  EXPECT_LE(ex, dx);
  EXPECT_LE(eF, dF);
  // Kinetic energy: |d(m v^2 / 2)| <= m vmax |dv| per particle (to first order), plus the
  // reordered sum over the n particles, (n - 1) u of the total.
  double mass = 0.0;
  for (double m : A.m)
    mass += m;
  const auto n = static_cast<double>(A.size());
  EXPECT_NEAR(a.s->energy.kinetic, b.s->energy.kinetic,
              mass * a.vmax * dv + (n - 1) * u * a.s->energy.kinetic);
}

template <int D> void expect_identical(const Solver<D>& a, const Solver<D>& b) {
  const auto& A = a.particles;
  const auto& B = b.particles;
  ASSERT_EQ(A.size(), B.size());
  EXPECT_EQ(a.particle_order(), b.particle_order());
  for (std::size_t p = 0; p < A.size(); ++p) {
    ASSERT_EQ(A.x[p], B.x[p]) << p;
    ASSERT_EQ(A.v[p], B.v[p]) << p;
    ASSERT_EQ(A.F[p], B.F[p]) << p;
    ASSERT_EQ(A.sigma[p], B.sigma[p]) << p;
  }
  EXPECT_EQ(a.energy.kinetic, b.energy.kinetic);
  EXPECT_EQ(a.energy.strain, b.energy.strain);
  EXPECT_EQ(a.energy.external_work, b.energy.external_work);
}

} // namespace

TEST(GimpSort, SortOrdersParticlesByCellAndCarriesTheirData) {
  auto s = make_block(1, false);
  const auto x = s->particles.x;
  const auto tr = s->tractions[0].particles;
  s->sort_particles();
  const auto& P = s->particles;
  auto cell = [&](const Eigen::Vector2d& p) {
    return std::floor((p[1] + 2e-3) / 1e-3) * 20 + std::floor((p[0] + 2e-3) / 1e-3);
  };
  bool moved = false;
  for (std::size_t q = 0; q < P.size(); ++q) {
    const std::size_t o = s->particle_order()[q];
    moved = moved || o != q;
    EXPECT_EQ(P.x[q], x[o]);
    if (q > 0) {
      EXPECT_LE(cell(P.x[q - 1]), cell(P.x[q])) << q;
      if (cell(P.x[q - 1]) == cell(P.x[q])) {
        EXPECT_LT(s->particle_order()[q - 1], o); // stable
      }
    }
  }
  EXPECT_TRUE(moved); // the shuffled input was not in cell order
  // the traction strip names the same particles after the sort
  std::vector<std::size_t> a = tr, b;
  for (std::size_t q : s->tractions[0].particles)
    b.push_back(s->particle_order()[q]);
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
}

TEST(GimpSort, SortedRunAgreesWithUnsortedToSummationRoundOff) {
  expect_agree(run(1, false, 0), run(1, false, 4));
}

TEST(GimpSort, SortedCrackedRunAgreesWithUnsortedToSummationRoundOff) {
  expect_agree(run(1, true, 0), run(1, true, 4));
}

TEST(GimpSort, Sorted3DRunAgreesWithUnsortedToSummationRoundOff) {
  auto make = [] { return make_block3(1); };
  expect_agree(run_with<3>(make, 0), run_with<3>(make, 4));
}

TEST(GimpSort, SortedRunIsReproducibleBitForBit) {
  for (int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    const SortRun<2> a = run(threads, true, 4), b = run(threads, true, 4);
    expect_identical(*a.s, *b.s);
  }
}

// D430: a problem whose arrays exceed 16 MiB (160,000 particles in 2-D) has them backed by huge
// pages once initialised, and again after a cell sort, whose permuted arrays are new
// allocations (σ, 72 bytes a particle, 11.5 MB, taken as the sample: its aligned interior).
// Where the kernel cannot collapse, or PNC_HUGE_PAGES=0, none is asked for; the run goes on.
TEST(GimpSort, ALargeProblemsArraysAreBackedByHugePagesBeforeAndAfterASort) {
  Solver<2> s;
  s.grid.h = 1e-3;
  s.grid.origin = Eigen::Vector2d(-2e-3, -2e-3);
  s.grid.n = {405, 105};
  s.materials.push_back(std::make_shared<HyperelasticPolymer>(1200, 1.8e8, 1.48e7));
  pnc_gimp_test::fill_box<2>(s, Eigen::Vector2d(0, 0), Eigen::Vector2d(0.4, 0.1), 2, 0);
  ASSERT_EQ(s.particles.size(), 160000u);
  for (auto& v : s.particles.v)
    v = Eigen::Vector2d(1.0, 0.0);
  s.initialize();
  const bool expect = pnc::test::kernel_can_collapse() && !pnc::test::huge_pages_switched_off();
  const auto sigma_kb = [&] { return pnc::test::huge_kb_of(s.particles.sigma); };
  const long interior_kb = static_cast<long>(s.particles.sigma.size() * sizeof(Mat3)) / 1024 -
                           4 * 1024; // less at most 2 MiB at each end
  const double dt = 0.1 * s.grid.h / 500.0;
  s.step(dt);
  if (expect) EXPECT_GE(sigma_kb(), interior_kb);
  if (!expect && pnc::test::thp_mode() == "madvise") EXPECT_EQ(sigma_kb(), 0);
  s.sort_every = 1;
  s.step(dt); // sorted before this step: new arrays
  if (expect) EXPECT_GE(sigma_kb(), interior_kb);
  EXPECT_TRUE(std::isfinite(s.energy.kinetic));
}
