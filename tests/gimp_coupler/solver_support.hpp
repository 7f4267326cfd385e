#pragma once
// Shared helpers of the uGIMP solver tests (test_solver.cpp, test_solver_threads.cpp): a box of
// particles, a prescribed Eulerian velocity field, the fixed-free bar in uniaxial strain and the
// largest differences between two runs. SI units. Internal to the tests.
#include "pnc/gimp_coupler/solver.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <memory>

namespace pnc_gimp_test {

using namespace pnc::gimp;

/// Fills the box [lo, hi] with ppc^D particles per cell (the box aligned with cells).
template <int D>
void fill_box(Solver<D>& s, const Eigen::Matrix<double, D, 1>& lo,
              const Eigen::Matrix<double, D, 1>& hi, int ppc, int mat) {
  using Vec = Eigen::Matrix<double, D, 1>;
  const double d = s.grid.h / ppc;
  const double rho = s.materials[static_cast<std::size_t>(mat)]->density();
  std::array<int, D> n{}, k{};
  for (int a = 0; a < D; ++a)
    n[a] = static_cast<int>(std::lround((hi[a] - lo[a]) / d));
  while (true) {
    Vec x;
    for (int a = 0; a < D; ++a)
      x[a] = lo[a] + (k[a] + 0.5) * d;
    s.particles.add(x, Vec::Constant(0.5 * d), rho * std::pow(d, D), std::pow(d, D), mat);
    int a = 0;
    for (; a < D; ++a) {
      if (++k[a] < n[a]) break;
      k[a] = 0;
    }
    if (a == D) break;
  }
}

/// One velocity BC per node, v = v(X), all components: a prescribed Eulerian velocity field.
template <int D, class Fn> void prescribe_field(Solver<D>& s, Fn v) {
  for (std::int64_t i = 0; i < s.grid.nodes(); ++i) {
    NodeBC<D> bc;
    bc.lo = bc.hi = s.grid.position(i);
    bc.mask.fill(true);
    bc.velocity = v(bc.lo);
    s.bcs.push_back(bc);
  }
}

/// Fixed-free bar along x in uniaxial strain (all nodes have v_y = 0): nodes x = x_fix fixed.
inline Solver<2> bar_2d(int cells, int threads, double v0_over_c, bool mode_shape) {
  Solver<2> s;
  const double Lb = 1.0;
  s.grid.h = Lb / cells;
  s.grid.origin = Eigen::Vector2d(-2 * s.grid.h, 0.0);
  s.grid.n = {cells + 5, 4};
  s.materials.push_back(std::make_shared<LinearElastic>(1000, 1e7, 0.3));
  fill_box<2>(s, Eigen::Vector2d(0.0, s.grid.h), Eigen::Vector2d(Lb, 2 * s.grid.h), 2, 0);
  NodeBC<2> fix;
  fix.name = "fixed";
  fix.lo = Eigen::Vector2d(-10.0, -1.0); // the wall: every node at x <= 0 (docs/gimp.md)
  fix.hi = Eigen::Vector2d(0.0, 10.0);
  fix.mask = {true, true};
  NodeBC<2> roll;
  roll.name = "rollers";
  roll.lo = Eigen::Vector2d(-10, -10);
  roll.hi = Eigen::Vector2d(10, 10);
  roll.mask = {false, true};
  s.bcs = {fix, roll};
  s.threads = threads;
  const double c = s.materials[0]->wave_speed();
  for (std::size_t p = 0; p < s.particles.size(); ++p) {
    const double x = s.particles.x[p][0];
    s.particles.v[p][0] = v0_over_c * c * (mode_shape ? std::sin(M_PI * x / (2 * Lb)) : 1.0);
  }
  s.initialize();
  return s;
}
/// Largest position difference (m), largest stress difference (Pa) and largest stress of a
/// (Pa) over the particles of two runs of the same body, matched by index.
struct Differences {
  double dx, ds, smax;
};
template <int D> Differences differences(const Solver<D>& a, const Solver<D>& b) {
  Differences d{0.0, 0.0, 0.0};
  for (std::size_t p = 0; p < a.particles.size(); ++p) {
    d.dx = std::max(d.dx, (a.particles.x[p] - b.particles.x[p]).norm());
    d.ds = std::max(d.ds, (a.particles.sigma[p] - b.particles.sigma[p]).norm());
    d.smax = std::max(d.smax, a.particles.sigma[p].norm());
  }
  return d;
}

} // namespace pnc_gimp_test
