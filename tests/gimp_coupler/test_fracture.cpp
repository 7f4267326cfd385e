// Energy release rates and growth of 2-D cracks (fracture.hpp): the J-integral of a centre
// crack in a finite plate against the handbook K_I at two resolutions, the mode split, the
// maximum-hoop-stress kink angle, crack growth at G = Gc; and 3-D planar cracks (D42): a
// through-thickness crack in a plane-strain slab against the 2-D model, face contact, and its
// growth against 2-D growth (D43).
#include "pnc/gimp_coupler/fracture.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

using namespace pnc::gimp;

namespace {

constexpr double kPi = 3.14159265358979323846;

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

} // namespace

// The tip detection: the end outside the body is the crack mouth, the end at x = a a tip.
TEST(GimpFracture, TipDetectionFindsTheInteriorEnd) {
  Cct p;
  p.cells = 8;
  p.build();
  p.s.initialize();
  EXPECT_EQ(p.s.cracks[0].tip[0], 0);
  EXPECT_EQ(p.s.cracks[0].tip[1], 1);
  const auto tips = crack_tips(p.s);
  ASSERT_EQ(tips.size(), 1u);
  EXPECT_EQ(tips[0].J, 0.0); // unloaded: F = I, sigma = 0, W = 0
  EXPECT_NEAR(tips[0].e1[0], 1.0, 1e-12);
}

// Centre crack in a plate (2a/W = 0.5 + h/(2b), height 2H = 3 W), quasi-static remote tension:
// J against the handbook G = K^2 (1 - nu^2)/E at two resolutions, 16 and 32 cells across the
// half width b, the tip in the middle of a cell.
// Tolerance and why: the discrete crack of the line-crossing field assignment ends at a
// definite place within the cell the geometric tip lies in (D38: measured, a tip anywhere in
// the cell acts like one near 3/4 of it), so the crack length is resolved to within h/2 and
// the error is first order in h, bounded by (d ln G/da) h/2 = (1/a + 2 d ln F/da) h/2 = 5.6 %
// at 32 cells (11 % at 16). We require |error| < 6 % at 32 cells (that bound plus 0.4 % for
// the other sources: the handbook formula, 0.1 %; the finite height H = 3 b, measured shift
// below 0.1 % beyond H = 1.5 b... see docs/gimp.md; residual dynamics KE/SE < 1e-5; the
// domain integral, path independent to 0.1 % for r_out 0.3-0.45 b), and the error to fall
// by at least 1.5x from 16 to 32 cells (first order: 2x). Pure mode I: G_II << G. The energy
// balance including the damping work (D41) closes to 1e-3 of the strain energy.
TEST(GimpFracture, CentreCrackJIntegralMatchesHandbookAndConverges) {
  double err[2] = {0, 0};
  const int cells[2] = {16, 32};
  for (int r = 0; r < 2; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    Cct p;
    p.cells = cells[r];
    p.build();
    p.s.initialize();
    p.run();
    const auto tips = crack_tips(p.s);
    ASSERT_EQ(tips.size(), 1u);
    const double Gref = p.G_reference();
    err[r] = tips[0].J / Gref - 1.0;
    const double ke_ratio = p.s.energy.kinetic / p.s.energy.strain;
    const double bal = p.s.energy.balance() / p.s.energy.strain;
    std::printf("cells %d: particles %zu, steps %ld, J = %.6e, G_ref = %.6e, error %+.2f %%, "
                "G_II/G = %.1e, KE/SE = %.1e, balance/SE = %.1e, %.1f s\n",
                cells[r], p.s.particles.size(), p.s.steps, tips[0].J, Gref, 100 * err[r],
                tips[0].GII / tips[0].J, ke_ratio, bal,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    EXPECT_LT(ke_ratio, 1e-5);
    EXPECT_LT(std::abs(bal), 1e-3);
    EXPECT_LT(tips[0].GII, 1e-6 * tips[0].J); // symmetric: sliding vanishes to round-off
    EXPECT_GT(tips[0].opening, 0.0);
  }
  EXPECT_LT(std::abs(err[1]), 0.06);
  EXPECT_LT(1.5 * std::abs(err[1]), std::abs(err[0]));
}

// Maximum hoop stress kink angle against its closed forms: pure mode I 0; K_II = K_I:
// theta = 2 atan((1 - 3)/4) = -53.13 deg; pure mode II: -acos(1/3) = -70.53 deg (the
// classical Erdogan-Sih values); mirror symmetry theta(-K_II) = -theta(K_II).
TEST(GimpFracture, HoopStressKinkAngle) {
  constexpr double deg = kPi / 180;
  EXPECT_EQ(hoop_angle(1.0, 0.0), 0.0);
  EXPECT_NEAR(hoop_angle(1.0, 1.0), 2 * std::atan(-0.5), 1e-14);
  EXPECT_NEAR(hoop_angle(1.0, 1.0) / deg, -53.130102, 1e-5);
  EXPECT_NEAR(hoop_angle(1e-9, 1.0) / deg, -70.528779, 1e-4); // -> pure mode II
  EXPECT_NEAR(hoop_angle(0.0, 1.0) / deg, -70.528779, 1e-5);  // closed tip, sliding
  EXPECT_NEAR(hoop_angle(1.0, -0.3), -hoop_angle(1.0, 0.3), 1e-15);
  // Small mode II: theta ~ -2 K_II/K_I.
  EXPECT_NEAR(hoop_angle(1.0, 1e-4), -2e-4, 1e-10);
}

// Crack growth at G = Gc under a slowly ramped load (centre-cracked plate, 16 cells across b,
// H = 1.5 b, ramp over 8 periods of the lowest mode; growth checked every 10 steps, increment
// h, maximum hoop stress direction).
// Checks: (1) no growth while J < Gc and growth at the first check with J >= Gc (the
// criterion); (2) the load at initiation against the handbook: sigma_i = sqrt(Gc E /
// ((1 - nu^2) pi a)) / F(a/b), within 8 % (J is +7 % high at 16 cells in the test above, i.e.
// -3.5 % in load, plus the finite height, the 10-step check interval and the first-mode
// estimate of the damped lag behind the ramp, taken out below); (3) in pure mode I
// the crack stays straight (the new points lie on the crack line to round-off: the kink angle
// is 0 because the sliding displacement vanishes by symmetry) and advances by h per event;
// (4) under load control a centre crack is unstable (G grows with a): once started it keeps
// growing, so all max_increments = 3 increments are made before the end of the ramp.
TEST(GimpFracture, CrackGrowsAtCriticalGStraightInModeI) {
  Cct p;
  p.cells = 16;
  p.H = 1.5;
  p.build(8.0, 1.0);
  const double h = p.b / p.cells;
  const double Gc = 0.5 * p.G_reference();
  Crack& cr = p.s.cracks[0];
  cr.growth.Gc = Gc;
  cr.growth.increment = h;
  cr.growth.max_increments = 3;
  const Eigen::Vector2d tip0 = cr.points.back();
  p.s.initialize();
  double t_init = -1.0;
  double J_prev = 0.0;
  while (p.s.time < p.t_end) {
    p.s.step(std::min(p.s.stable_dt(), p.t_end - p.s.time));
    if (p.s.steps % 10 != 0) continue;
    const auto tips = crack_tips(p.s);
    const int before = p.s.cracks[0].increments;
    if (tips.empty()) break;
    const int g = grow_cracks(p.s, tips);
    if (before < 3) {
      EXPECT_EQ(g > 0, tips[0].J >= Gc) << "J = " << tips[0].J << " at t = " << p.s.time;
    }
    if (g > 0 && t_init < 0) {
      t_init = p.s.time;
      EXPECT_LT(J_prev, Gc);
    }
    J_prev = tips[0].J;
  }
  ASSERT_GT(t_init, 0.0) << "the crack never grew";
  // The damped response lags a linear ramp by alpha / omega1^2 = 2 / omega1 (steady state of
  // x'' + alpha x' + omega1^2 x = omega1^2 f(t) for f linear in t): the load felt at t_init.
  const double sigma_i = p.sigma * p.s.tractions[0].ramp(t_init - 2.0 / p.w1);
  const double l = (tip0[0]) / p.b;
  const double F = (1 - 0.025 * l * l + 0.06 * std::pow(l, 4)) / std::sqrt(std::cos(kPi * l / 2));
  const double sigma_ref = std::sqrt(Gc * p.E / ((1 - p.nu * p.nu) * kPi * tip0[0])) / F;
  std::printf("initiation at t = %.4g s (ramp end %.4g s): sigma_i = %.1f Pa, handbook %.1f Pa "
              "(%+.2f %%); increments %d\n",
              t_init, p.t_ramp, sigma_i, sigma_ref, 100 * (sigma_i / sigma_ref - 1),
              p.s.cracks[0].increments);
  EXPECT_NEAR(sigma_i / sigma_ref, 1.0, 0.08);
  const auto& pts = p.s.cracks[0].points;
  ASSERT_EQ(pts.size(), 5u);
  EXPECT_EQ(p.s.cracks[0].increments, 3);
  for (int k = 1; k <= 3; ++k) {
    EXPECT_NEAR(pts[1 + k][1], tip0[1], 1e-12 * h);
    EXPECT_NEAR(pts[1 + k][0], tip0[0] + k * h, 1e-12 * h);
  }
}

namespace {
/// Full centre-cracked plate (no symmetry plane: a mixed load has none), x in [-b, b],
/// y in [-H, H], b = 1, H = 1.5, 16 cells across b, crack from -a to a (a = 0.5 + h/2) on
/// y = 0+, free body under self-equilibrated remote stress sigma_yy = sig, sigma_xy = tau
/// (tractions on all four edges), damped slow ramp. Returns both tips.
std::vector<TipResult> full_plate(double sig, double tau, int cells) {
  Cct p; // for the material, damping and ramp constants
  p.cells = cells;
  p.H = 1.5;
  const double b = p.b, H = p.H, h = b / p.cells, d = h / 2, rho = p.rho;
  Solver<2>& s = p.s;
  s.grid.h = h;
  s.grid.origin = Eigen::Vector2d(-b - 2 * h, -H - 2 * h);
  s.grid.n = {2 * p.cells + 5, static_cast<int>(std::lround(2 * H / h)) + 5};
  s.materials.push_back(std::make_shared<LinearElastic>(rho, p.E, p.nu));
  const int nx = static_cast<int>(std::lround(2 * b / d)),
            ny = static_cast<int>(std::lround(2 * H / d));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      s.particles.add(Eigen::Vector2d(-b + (i + 0.5) * d, -H + (j + 0.5) * d),
                      Eigen::Vector2d::Constant(0.5 * d), rho * d * d, d * d, 0);
  const double cp = std::sqrt(p.E / (rho * (1 - p.nu * p.nu)));
  const double w1 = kPi * cp / (2 * H);
  s.damping = 2.0 * w1;
  const double t_ramp = 2.0 * (2 * kPi / w1), t_end = 2.0 * t_ramp;
  auto add = [&](int axis, int side, const Eigen::Vector2d& t) {
    Traction<2> tr;
    tr.axis = axis;
    tr.traction = t;
    tr.ramp = Ramp{0.0, t_ramp};
    const double edge = axis == 0 ? b : H;
    for (std::size_t q = 0; q < s.particles.size(); ++q)
      if (side * s.particles.x[q][axis] > edge - d) tr.particles.push_back(q);
    s.tractions.push_back(tr);
  };
  add(1, 1, Eigen::Vector2d(tau, sig));    // top, n = +y: t = (sxy, syy)
  add(1, -1, Eigen::Vector2d(-tau, -sig)); // bottom
  if (tau != 0.0) {
    add(0, 1, Eigen::Vector2d(0.0, tau));   // right, n = +x: t = (sxx, sxy)
    add(0, -1, Eigen::Vector2d(0.0, -tau)); // left
  }
  Crack cr;
  cr.name = "c";
  const double a = p.a + 0.5 * h;
  cr.points = {Eigen::Vector2d(-a, 1e-6 * h), Eigen::Vector2d(a, 1e-6 * h)};
  cr.j_inner = 0.1 * b;
  cr.j_outer = 0.4 * b;
  s.cracks = {cr};
  s.initialize();
  while (s.time < t_end)
    s.step(std::min(s.stable_dt(), t_end - s.time));
  return crack_tips(s);
}
} // namespace

// Mixed mode by superposition (linear elasticity: K_I comes from sigma alone, K_II from tau
// alone, and G = G_I + G_II = (K_I^2 + K_II^2)(1 - nu^2)/E). The same plate (16 cells
// across b) is run under tension, under shear and under both; for the right tip:
// J(both) = J(tension) + J(shear) to 2 % (the small-strain St V-K law is linear to 1e-3 at
// these loads; the crack opens under tension, so the shear's face contact plays no part);
// the split of the mixed run (D39: K_II/K_I = sliding/opening of the faces between r_in and
// r_out behind the tip) must give G_I = J(tension) and G_II = J(shear) to 10 %: the split is
// biased at first order in h (measured +4.4 % / -7.6 % at 16 cells, +2.3 % / -4.0 % at 32 in
// a one-off run, D39). Pure runs: the split puts everything into their own mode (symmetry:
// G_II/J < 1e-6 in tension; antisymmetry: G_I/J < 1e-3 in shear, where the faces slide in
// frictionless contact). Both tips agree (point symmetry of the problem).
TEST(GimpFracture, MixedModeSplitMatchesSuperposition) {
  const double sig = 1e4, tau = 0.7e4;
  const auto t1 = full_plate(sig, 0.0, 16), t2 = full_plate(0.0, tau, 16),
             t3 = full_plate(sig, tau, 16);
  ASSERT_EQ(t1.size(), 2u);
  ASSERT_EQ(t3.size(), 2u);
  const TipResult &a = t1[1], &b = t2[1], &c = t3[1];
  std::printf("tension: J %.5e GI %.5e GII %.2e | shear: J %.5e GI %.2e GII %.5e | both: J %.5e "
              "GI %.5e GII %.5e; start tip of both: J %.5e\n",
              a.J, a.GI, a.GII, b.J, b.GI, b.GII, c.J, c.GI, c.GII, t3[0].J);
  EXPECT_LT(a.GII, 1e-6 * a.J);
  EXPECT_LT(b.GI, 1e-3 * b.J);
  EXPECT_GT(b.sliding, 0.0); // positive K_II for positive tau
  EXPECT_NEAR(c.J / (a.J + b.J), 1.0, 0.02);
  EXPECT_NEAR(c.GI / a.J, 1.0, 0.10);
  EXPECT_NEAR(c.GII / b.J, 1.0, 0.10);
  EXPECT_NEAR(t3[0].J / c.J, 1.0, 0.02);
}

// Growth bookkeeping without mechanics: a loaded-looking tip result drives growth along a
// prescribed direction until the tip leaves the material; then the end stops being a tip
// and no further increment is made. Also the mixed-mode criterion G_I/Gc + G_II/GIIc >= 1.
TEST(GimpFracture, GrowthStopsWhenTheTipLeavesTheBody) {
  Cct p;
  p.cells = 8;
  p.H = 1.0;
  p.build();
  const double h = p.b / p.cells;
  Crack& cr = p.s.cracks[0];
  cr.growth.Gc = 1.0;
  cr.growth.GIIc = 2.0;
  cr.growth.increment = h;
  cr.growth.prescribed = true;
  cr.growth.direction = Eigen::Vector2d(1.0, 0.0);
  p.s.initialize();
  TipResult r;
  r.crack = 0;
  r.end = 1;
  r.GI = 0.5;
  r.GII = 0.9; // 0.5/1 + 0.9/2 = 0.95 < 1: no growth although J = 1.4 >= Gc
  r.J = 1.4;
  r.tip = cr.points.back();
  EXPECT_EQ(grow_cracks(p.s, {r}), 0);
  r.GII = 1.1; // 0.5 + 0.55 >= 1
  int total = 0;
  for (int k = 0; k < 20; ++k) {
    r.tip = p.s.cracks[0].points.back();
    total += grow_cracks(p.s, {r});
  }
  // The tip started at a + h/2 = 4.5 h in a body of width b = 8 h (last particle centroid at
  // 7.75 h): it stays a tip while a centroid lies within h of tip + h, i.e. at 5.5, 6.5 and
  // 7.5 h (half a cell of ligament left); the 4th increment to 8.5 h leaves the body.
  EXPECT_EQ(total, 4);
  EXPECT_EQ(p.s.cracks[0].tip[1], 0);
  EXPECT_NEAR(p.s.cracks[0].points.back()[0], 8.5 * h, 1e-12);
  EXPECT_TRUE(crack_tips(p.s).empty());
}

// ---------------------------------------------------------------------------------------------
// 3-D planar cracks with straight fronts (D42).

namespace {
/// The half-model centre-cracked plate of Cct as a 3-D slab of thickness T = `layers` cells
/// (z in [0, T]) under plane-strain conditions: u_z = 0 on every node on or beyond the two
/// faces normal to the front (z <= 0, z >= T). The crack is the rectangle in the plane
/// y = 1e-6 h from the mouth outside the body (x = -1.5 h) to the straight front at
/// x = a + h/2, reaching beyond both faces (z = -h/2 .. T + h/2). Same h, particles per cell,
/// material, damping, ramp and J radii as the 2-D model, so the two are the same plane problem
/// at the same discretisation.
struct Slab {
  Cct p2; // the 2-D twin (constants, reference G)
  Solver<3> s;
  int layers = 2; // two cells: the node plane z = h inside the slab is free in z
  void build(int cells, double ramp_periods = 2.0, double hold_periods = 2.0) {
    p2.cells = cells;
    p2.build(ramp_periods, hold_periods);
    const double b = p2.b, H = p2.H, a = p2.a, rho = p2.rho, h = b / cells, d = h / 2;
    const double T = layers * h;
    using V3 = Eigen::Vector3d;
    s.grid.h = h;
    s.grid.origin = V3(-2 * h, -H - 2 * h, -2 * h);
    s.grid.n = {cells + 5, static_cast<int>(std::lround(2 * H / h)) + 5, layers + 5};
    s.materials.push_back(std::make_shared<LinearElastic>(rho, p2.E, p2.nu));
    const int nx = cells * 2, ny = static_cast<int>(std::lround(2 * H / d)), nz = 2 * layers;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          s.particles.add(V3((i + 0.5) * d, -H + (j + 0.5) * d, (k + 0.5) * d),
                          V3::Constant(0.5 * d), rho * d * d * d, d * d * d, 0);
    NodeBC<3> sym, z0, z1;
    sym.name = "symmetry";
    sym.lo = V3(-10, -10, -10);
    sym.hi = V3(0, 10, 10);
    sym.mask = {true, false, false};
    z0.name = "z0";
    z0.lo = V3(-10, -10, -10);
    z0.hi = V3(10, 10, 0);
    z0.mask = {false, false, true};
    z1 = z0;
    z1.name = "z1";
    z1.lo = V3(-10, -10, T);
    z1.hi = V3(10, 10, 10);
    s.bcs = {sym, z0, z1};
    s.damping = p2.s.damping;
    for (int side = -1; side <= 1; side += 2) {
      Traction<3> tr;
      tr.axis = 1;
      tr.traction = V3(0.0, side * p2.sigma, 0.0);
      tr.ramp = Ramp{0.0, p2.t_ramp};
      for (std::size_t q = 0; q < s.particles.size(); ++q)
        if (side * s.particles.x[q][1] > H - d) tr.particles.push_back(q);
      s.tractions.push_back(tr);
    }
    Crack cr;
    cr.name = "centre";
    const double y = 1e-6 * h, xt = a + p2.tip_shift * h;
    cr.corners = {V3(-1.5 * h, y, -0.5 * h), V3(xt, y, -0.5 * h), V3(xt, y, T + 0.5 * h),
                  V3(-1.5 * h, y, T + 0.5 * h)};
    cr.j_inner = 0.1 * b;
    cr.j_outer = 0.4 * b;
    s.cracks = {cr};
  }
};
} // namespace

// A through-thickness straight crack in a slab under plane strain against the 2-D model of the
// same plane problem (centre crack 2a/W = 0.5 + h/2b, 16 cells across b, the test above).
// Tolerance and why: with u_z = 0 on every node at or beyond the faces the 3-D scheme is
// the 2-D one per unit thickness (the z weights of each particle sum to 1 and every particle
// column is the same in all its layers; the crack polygon cuts the same (particle, node)
// pairs in every layer; the front-averaged J is the sum over layers divided by T), so J3D
// must equal J2D in exact arithmetic: we require 1e-6 (measured 5.1e-8, with out-of-plane
// shear stresses of 7e-7 of the peak stress as the only asymmetry, source not isolated; with
// one cell of thickness, no node plane free in z, 3e-14). Against the handbook: the 2-D error,
// +6.64 % at 16 cells (D38); the bound (d ln G/da) h/2 = 11 % at 16 cells plus 0.4 % for the
// other sources gives the tolerance 11.5 %. Mode I: G_II, tearing vanish by symmetry.
TEST(GimpFracture3D, ThroughCrackSlabMatchesPlaneStrain2D) {
  const auto t0 = std::chrono::steady_clock::now();
  Slab sl;
  sl.build(16);
  sl.p2.s.initialize();
  sl.p2.run();
  const auto t2d = crack_tips(sl.p2.s);
  ASSERT_EQ(t2d.size(), 1u);
  const double t_2d = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  sl.s.initialize();
  ASSERT_EQ(sl.s.cracks[0].front, (std::vector<int>{0, 1, 0, 0})); // auto: the edge x = a
  while (sl.s.time < sl.p2.t_end)
    sl.s.step(std::min(sl.s.stable_dt(), sl.p2.t_end - sl.s.time));
  const auto fr = crack_fronts(sl.s);
  ASSERT_EQ(fr.size(), 1u);
  // Plane strain kept: F_zz = 1 and the out-of-plane shear stresses stay at noise level.
  double fzz = 0, szx = 0, smax = 0;
  for (std::size_t q = 0; q < sl.s.particles.size(); ++q) {
    const auto& P = sl.s.particles;
    fzz = std::max(fzz, std::abs(P.F[q](2, 2) - 1));
    szx = std::max(szx, std::max(std::abs(P.sigma[q](0, 2)), std::abs(P.sigma[q](1, 2))));
    smax = std::max(smax, P.sigma[q].norm());
  }
  std::printf("3-D slab: max |F_zz - 1| = %.1e, max |sigma_xz|, |sigma_yz| = %.1e max |sigma|\n",
              fzz, szx / smax);
  EXPECT_LT(fzz, 1e-12);
  EXPECT_LT(szx, 1e-5 * smax);
  const double Gref = sl.p2.G_reference();
  const double h = sl.p2.b / sl.p2.cells;
  std::printf("2-D: J = %.9e (%.1f s, %ld steps); 3-D slab (%zu particles, %ld steps): J = "
              "%.9e, J3D/J2D - 1 = %.1e; vs handbook %+.2f %%; front length %.4g (T %.4g), "
              "G_II/J = %.1e, tearing/opening = %.1e, %.1f s in total\n",
              t2d[0].J, t_2d, sl.p2.s.steps, sl.s.particles.size(), sl.s.steps, fr[0].J,
              fr[0].J / t2d[0].J - 1, 100 * (fr[0].J / Gref - 1), fr[0].length, sl.layers * h,
              fr[0].GII / fr[0].J, fr[0].tearing / fr[0].opening,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  EXPECT_EQ(sl.s.steps, sl.p2.s.steps);
  EXPECT_NEAR(fr[0].J / t2d[0].J, 1.0, 1e-6);
  EXPECT_NEAR(fr[0].J / Gref, 1.0, 0.115);
  EXPECT_NEAR(fr[0].length, sl.layers * h, 1e-12);
  EXPECT_NEAR(fr[0].depth, sl.p2.a + 2.0 * h, 1e-12);
  EXPECT_NEAR(fr[0].opening / t2d[0].opening, 1.0, 1e-6);
  EXPECT_LT(fr[0].GII, 1e-6 * fr[0].J);
  EXPECT_LT(std::abs(fr[0].tearing), 1e-9 * fr[0].opening);
  EXPECT_NEAR(fr[0].e1[0], 1.0, 1e-15);
}

namespace {
/// A 3-D bar along x (1 m, 40 cells, cross-section one cell), rollers on y and z everywhere
/// (uniaxial strain), halves moving with +-v0 (sign +1 apart, -1 together); optionally cut by
/// a square crack in the plane x = 0.5 + 1e-7 reaching beyond the cross-section.
Solver<3> split_bar3(bool crack, double sign) {
  using V3 = Eigen::Vector3d;
  Solver<3> s;
  const int cells = 40;
  const double h = 1.0 / cells, d = h / 2;
  s.grid.h = h;
  s.grid.origin = V3(-4 * h, 0.0, 0.0);
  s.grid.n = {cells + 9, 4, 4};
  s.materials.push_back(std::make_shared<LinearElastic>(1000, 1e7, 0.3));
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2 * cells; ++i)
        s.particles.add(V3((i + 0.5) * d, h + (j + 0.5) * d, h + (k + 0.5) * d),
                        V3::Constant(0.5 * d), 1000 * d * d * d, d * d * d, 0);
  NodeBC<3> roll;
  roll.lo = V3(-10, -10, -10);
  roll.hi = V3(10, 10, 10);
  roll.mask = {false, true, true};
  s.bcs = {roll};
  const double v0 = 1e-3 * s.materials[0]->wave_speed();
  for (std::size_t p = 0; p < s.particles.size(); ++p)
    s.particles.v[p][0] = sign * (s.particles.x[p][0] < 0.5 ? -v0 : v0);
  if (crack) {
    Crack c;
    c.name = "split";
    const double x = 0.5 + 1e-7;
    c.corners = {V3(x, -1, -1), V3(x, 1, -1), V3(x, 1, 1), V3(x, -1, 1)};
    s.cracks.push_back(c);
  }
  s.initialize();
  return s;
}
} // namespace

// The 3-D twin of GimpCrack.CrackFacesInContactDoNotInterpenetrate (D37, D42): halves pushed
// together across a planar crack transmit the compression as the uncracked bar does (the
// contact velocity is the centre-of-mass velocity of the two fields: 1e-9 of the stress, as
// in 2-D), with no interpenetration; halves pulled apart separate stress-free, keeping their
// kinetic energy (1e-12, as in 2-D).
TEST(GimpFracture3D, PlanarCrackFacesInContactDoNotInterpenetrate) {
  Solver<3> cracked = split_bar3(true, -1.0), whole = split_bar3(false, -1.0);
  EXPECT_EQ(cracked.cracks[0].front, (std::vector<int>{0, 0, 0, 0})); // no material ahead
  const double c = cracked.materials[0]->wave_speed();
  const double dt = 0.4 * cracked.grid.h / c;
  const int n = static_cast<int>(0.45 / c / dt);
  for (int k = 0; k < n; ++k) {
    cracked.step(dt);
    whole.step(dt);
  }
  double smax = 0, dmax = 0;
  for (const auto& sg : whole.particles.sigma)
    smax = std::max(smax, sg.norm());
  EXPECT_GT(smax, 0.0);
  double left = -1e300, right = 1e300;
  for (std::size_t p = 0; p < cracked.particles.size(); ++p) {
    dmax = std::max(dmax, (cracked.particles.sigma[p] - whole.particles.sigma[p]).norm());
    EXPECT_LT(cracked.particles.sigma[p](0, 0), 1e-9 * smax);
    const double lx = cracked.particles.l[p][0] * cracked.particles.F[p](0, 0);
    if (cracked.particles.x0[p][0] < 0.5)
      left = std::max(left, cracked.particles.x[p][0] + lx);
    else
      right = std::min(right, cracked.particles.x[p][0] - lx);
  }
  std::printf("3-D contact: max |sigma - sigma_uncracked| / max |sigma| = %.1e, min gap %.1e m\n",
              dmax / smax, right - left);
  EXPECT_LT(dmax, 1e-9 * smax);
  EXPECT_GE(right - left, -1e-12);

  // Pulled apart: no stress, kinetic energy kept.
  Solver<3> apart = split_bar3(true, +1.0);
  const double E0 = apart.energy.kinetic, v0 = 1e-3 * c;
  for (int k = 0; k < 200; ++k)
    apart.step(dt);
  double amax = 0;
  for (const auto& sg : apart.particles.sigma)
    amax = std::max(amax, sg.norm());
  EXPECT_LT(amax, 1e-9 * 1000 * c * v0);
  EXPECT_NEAR(apart.energy.kinetic, E0, 1e-12 * E0);
}

// The solver checks a polygon set up in code as the input does (non-planar corners), and
// rejects a prescribed growth direction on a 3-D crack (a front advances in its plane, D43).
TEST(GimpFracture3D, SolverRejectsBadPolygonsAndGrowth) {
  Solver<3> s = split_bar3(false, 1.0);
  Crack c;
  c.name = "bent";
  c.corners = {Eigen::Vector3d(0.5, -1, -1), Eigen::Vector3d(0.5, 1, -1),
               Eigen::Vector3d(0.6, 1, 1), Eigen::Vector3d(0.5, -1, 1)};
  s.cracks = {c};
  try {
    s.initialize();
    ADD_FAILURE() << "a non-planar polygon was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("non-planar"), std::string::npos) << e.what();
  }
  c.corners[2] = Eigen::Vector3d(0.5, 1, 1);
  c.growth.Gc = 1.0;
  c.growth.prescribed = true;
  s.cracks = {c};
  try {
    s.initialize();
    ADD_FAILURE() << "a prescribed growth direction in 3-D was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("2-D only"), std::string::npos) << e.what();
  }
  c.growth.prescribed = false; // the default: in the plane, normal to the front (D43)
  s.cracks = {c};
  EXPECT_NO_THROW(s.initialize());
}

// 3-D growth (D43) against 2-D growth (D40) of the same plane problem: the slab above
// (16 cells across b, two cells thick, u_z = 0 faces) under the slow ramp of
// GimpFracture.CrackGrowsAtCriticalGStraightInModeI (H = 1.5 b, 8 ramp periods, 1 hold),
// Gc = G_ref/2, increment h, at most 3 increments, checked every 10 steps in both.
// Per unit thickness the 3-D discrete equations are the 2-D ones (test above: J3D/J2D - 1 =
// 5e-8 at rest); during this ramp the residual of unknown source shows more, |J3D - J2D| up
// to 1.5e-5 Gc (5.4e-5 of J for J >= Gc/10, measured). Tolerance on J at every check, before
// and after growth (the grown polygon cuts the same (particle, node) pairs as the grown
// polyline in every layer): 1e-4, relative for J >= Gc/10 and of Gc for all checks. The growth
// decisions then must be the same at every check where J is farther than that from Gc: we
// check that it is (closest approach measured 1.5e-3 Gc, required > 10 |J3D - J2D|) and
// require the same initiation step, the same increments at every check (exact) and the same
// crack length (2-D polyline length vs 3-D polygon depth, both from the mouth at x = -1.5 h)
// to 1e-12 h. The front edge moves by exactly h per increment in the crack plane (corners to
// 1e-12 h) and stays a front. About 11 s.
TEST(GimpFracture3D, ThroughCrackGrowsAsPlaneStrain2D) {
  const auto t0 = std::chrono::steady_clock::now();
  Slab sl;
  sl.p2.H = 1.5;
  sl.build(16, 8.0, 1.0);
  const double h = sl.p2.b / sl.p2.cells;
  const double Gc = 0.5 * sl.p2.G_reference();
  for (Crack* c : {&sl.p2.s.cracks[0], &sl.s.cracks[0]}) {
    c->growth.Gc = Gc;
    c->growth.increment = h;
    c->growth.max_increments = 3;
  }
  const auto corners0 = sl.s.cracks[0].corners;
  struct Check {
    long step;
    int increments;
    double length, J;
  };
  std::vector<Check> h2, h3;
  Cct& p = sl.p2;
  p.s.initialize();
  while (p.s.time < p.t_end) {
    p.s.step(std::min(p.s.stable_dt(), p.t_end - p.s.time));
    if (p.s.steps % 10 != 0) continue;
    const auto tips = crack_tips(p.s);
    ASSERT_EQ(tips.size(), 1u);
    grow_cracks(p.s, tips);
    h2.push_back({p.s.steps, p.s.cracks[0].increments, tips[0].length, tips[0].J});
  }
  sl.s.initialize();
  while (sl.s.time < p.t_end) {
    sl.s.step(std::min(sl.s.stable_dt(), p.t_end - sl.s.time));
    if (sl.s.steps % 10 != 0) continue;
    const auto fr = crack_fronts(sl.s);
    ASSERT_EQ(fr.size(), 1u);
    grow_cracks(sl.s, fr);
    h3.push_back({sl.s.steps, sl.s.cracks[0].increments, fr[0].depth, fr[0].J});
  }
  ASSERT_EQ(h2.size(), h3.size());
  long init2 = -1, init3 = -1;
  double dj_rel = 0.0, dj_abs = 0.0, margin = 1e300;
  for (std::size_t k = 0; k < h2.size(); ++k) {
    EXPECT_EQ(h2[k].step, h3[k].step);
    EXPECT_EQ(h2[k].increments, h3[k].increments) << "check at step " << h2[k].step;
    EXPECT_NEAR(h3[k].length, h2[k].length, 1e-12 * h) << "check at step " << h2[k].step;
    if (h2[k].increments > 0 && init2 < 0) init2 = h2[k].step;
    if (h3[k].increments > 0 && init3 < 0) init3 = h3[k].step;
    dj_abs = std::max(dj_abs, std::abs(h3[k].J - h2[k].J) / Gc);
    if (h2[k].J >= 0.1 * Gc) dj_rel = std::max(dj_rel, std::abs(h3[k].J / h2[k].J - 1));
    // Distance of J from Gc at the checks that decided (growth still possible).
    if (k == 0 || h2[k - 1].increments < 3) margin = std::min(margin, std::abs(h2[k].J / Gc - 1));
  }
  std::printf("growth 2-D vs 3-D: %zu checks, initiation at step %ld (2-D) and %ld (3-D), "
              "increments %d and %d; max |J3D - J2D| / Gc = %.1e, max |J3D/J2D - 1| (J >= Gc/10) "
              "= %.1e; closest approach of J to Gc at a deciding check %.1e Gc; %.1f s\n",
              h2.size(), init2, init3, p.s.cracks[0].increments, sl.s.cracks[0].increments, dj_abs,
              dj_rel, margin,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  EXPECT_GT(init2, 0) << "the 2-D crack never grew";
  EXPECT_EQ(init2, init3);
  EXPECT_EQ(sl.s.cracks[0].increments, 3);
  // J: 1e-4 (relative for J >= Gc/10, and of Gc at every check); the decisions are implied by
  // it only if J never comes closer to Gc than that at a deciding check: checked too.
  EXPECT_LT(dj_rel, 1e-4);
  EXPECT_LT(dj_abs, 1e-4);
  EXPECT_GT(margin, 10 * dj_abs);
  // The front edge (corners 1, 2) moved by 3 h along +x, the others stayed; still a front.
  const auto& cn = sl.s.cracks[0].corners;
  for (std::size_t k = 0; k < 4; ++k) {
    const double dx = (k == 1 || k == 2) ? 3 * h : 0.0;
    EXPECT_NEAR((cn[k] - corners0[k] - Eigen::Vector3d(dx, 0, 0)).norm(), 0.0, 1e-12 * h);
  }
  EXPECT_EQ(sl.s.cracks[0].front, (std::vector<int>{0, 1, 0, 0}));
}
