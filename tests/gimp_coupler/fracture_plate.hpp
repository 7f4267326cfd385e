#pragma once
// The centre-cracked plate of the fracture tests (test_fracture.cpp, 2-D; test_fracture_3d.cpp,
// the 3-D slab compared with it). SI units.
#include "pnc/gimp_coupler/fracture.hpp"

#include <cmath>

namespace gimp_test {

using namespace pnc::gimp;

inline constexpr double kPi = 3.14159265358979323846;

/// Centre-cracked plate under remote tension sigma, half model: material x in [0, b],
/// y in [-H, H], symmetry plane x = 0 (u_x = 0 on every node x <= 0), crack along y = 0+ from
/// outside the body to the tip at x = a, tractions +-sigma on the top/bottom particle rows,
/// ramped over t_ramp, grid damping alpha (D41). `cells`: cells across b.
struct Cct {
  double b = 1.0, H = 3.0, a = 0.5, sigma = 1e4, E = 1e7, nu = 0.3, rho = 1000.0;
  int cells = 16;
  Solver<2> s;
  double c = 0.0, t_ramp = 0.0, t_end = 0.0, w1 = 0.0;
  /// The tip lies at a + tip_shift h; 0.5: mid-cell, a generic position (D38: the discrete
  /// tip is resolved to a cell).
  double tip_shift = 0.5;

  void build(double ramp_periods = 2.0, double hold_periods = 2.0) {
    const double h = b / cells;
    s.grid.h = h;
    s.grid.origin = Eigen::Vector2d(-2 * h, -H - 2 * h);
    s.grid.n = {cells + 5, static_cast<int>(std::lround(2 * H / h)) + 5};
    s.materials.push_back(std::make_shared<LinearElastic>(rho, E, nu));
    const int ppc = 2;
    const double d = h / ppc;
    const int nx = cells * ppc, ny = static_cast<int>(std::lround(2 * H / d));
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Eigen::Vector2d x((i + 0.5) * d, -H + (j + 0.5) * d);
        s.particles.add(x, Eigen::Vector2d::Constant(0.5 * d), rho * d * d, d * d, 0);
      }
    NodeBC<2> sym;
    sym.name = "symmetry";
    sym.lo = Eigen::Vector2d(-10, -10);
    sym.hi = Eigen::Vector2d(0, 10);
    sym.mask = {true, false};
    s.bcs = {sym};
    c = s.materials[0]->wave_speed();
    // Lowest symmetric mode: free-free stretching of the 2H-long plate, omega1 ~ pi c' / (2H)
    // with c' = sqrt(E/(rho (1 - nu^2))) the plate wave speed; critical damping 2 omega1 for
    // that mode, the ramp over two of its periods (a smooth, nearly quasi-static load).
    const double cp = std::sqrt(E / (rho * (1 - nu * nu)));
    w1 = kPi * cp / (2 * H);
    s.damping = 2.0 * w1;
    t_ramp = ramp_periods * (2 * kPi / w1);
    t_end = t_ramp + hold_periods * (2 * kPi / w1);
    for (int side = -1; side <= 1; side += 2) {
      Traction<2> tr;
      tr.name = side > 0 ? "top" : "bottom";
      tr.axis = 1;
      tr.traction = Eigen::Vector2d(0.0, side * sigma);
      tr.ramp = Ramp{0.0, t_ramp};
      for (std::size_t p = 0; p < s.particles.size(); ++p)
        if (side * s.particles.x[p][1] > H - d) tr.particles.push_back(p);
      s.tractions.push_back(tr);
    }
    Crack cr;
    cr.name = "centre";
    // Off the node line y = 0 by 1e-6 h (a tie counts as no crossing, D37).
    cr.points = {Eigen::Vector2d(-1.5 * h, 1e-6 * h), Eigen::Vector2d(a + tip_shift * h, 1e-6 * h)};
    // J domain scaled with the geometry: q ramps from 0.1 b to 0.4 b around the tip (inside
    // the body, clear of the symmetry plane at a - 0.4 b = 0.1 b and of the edge at b - a).
    cr.j_inner = 0.1 * b;
    cr.j_outer = 0.4 * b;
    s.cracks = {cr};
  }
  void run() {
    while (s.time < t_end) {
      s.step(std::min(s.stable_dt(), t_end - s.time));
    }
  }
  /// Tada's handbook formula for a centre crack, infinite height (accurate to 0.1 %):
  /// K = sigma sqrt(pi a) (1 - 0.025 l^2 + 0.06 l^4) sqrt(sec(pi l / 2)), l = a / b; plane
  /// strain G = K^2 (1 - nu^2) / E.
  double G_reference() const {
    const double at = a + tip_shift * b / cells, l = at / b;
    const double F = (1 - 0.025 * l * l + 0.06 * std::pow(l, 4)) / std::sqrt(std::cos(kPi * l / 2));
    const double K = sigma * std::sqrt(kPi * at) * F;
    return K * K * (1 - nu * nu) / E;
  }
};

} // namespace gimp_test
