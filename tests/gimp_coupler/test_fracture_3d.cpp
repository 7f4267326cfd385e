// 3-D planar cracks with straight fronts (fracture.hpp, D42): a through-thickness crack in a
// plane-strain slab against the 2-D model of test_fracture.cpp, face contact, and its growth
// against 2-D growth (D43).
#include "pnc/gimp_coupler/fracture.hpp"

#include "fracture_plate.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

using namespace pnc::gimp;
using gimp_test::Cct;

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
