// Energy release rates and growth of 2-D cracks (fracture.hpp): the J-integral of a centre
// crack in a finite plate against the handbook K_I at two resolutions, the mode split, the
// maximum-hoop-stress kink angle, crack growth at G = Gc. The 3-D planar cracks (D42, D43) are
// in test_fracture_3d.cpp.
#include "pnc/gimp_coupler/fracture.hpp"

#include "fracture_plate.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

using namespace pnc::gimp;
using gimp_test::Cct;
using gimp_test::kPi;

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
