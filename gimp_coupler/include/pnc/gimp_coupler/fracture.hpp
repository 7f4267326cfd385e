#pragma once
// pnc/gimp_coupler/fracture.hpp: energy release rates and growth of 2-D cracks (CRAMP), and
// the front-averaged energy release rate of straight fronts of 3-D planar cracks (D42).
//
// Units: SI. Positions, lengths m; energy release rates J/m^2 (= N/m, per unit crack area;
// in 2-D per metre of thickness and metre of crack advance); angles rad.
//
// J-integral (decision D38): the equivalent domain integral on the particles, in the
// reference configuration, quasi-static (no inertia term),
//   J = sum_p V0_p [ (P_p grad q) . (H_p e1) - W_p (e1 . grad q) ],
// P = J sigma F^-T the first Piola-Kirchhoff stress, H = F - I = du/dX, W the stored energy
// per reference volume, e1 the unit crack direction at the tip (ahead), q(X) = 1 for
// |X - tip| <= r_in, 0 for >= r_out, q = (1 + cos(pi s))/2 with s = (r - r_in)/(r_out - r_in)
// in between (a continuous grad q: with a linear ramp the particle quadrature made J depend
// on the radii by 10 % at 16 cells; smooth: 0.7 %). Exact for any hyperelastic law
// (path independent), so the elastic laws of materials.hpp qualify; for the damage law J
// is the domain value, not a crack-driving force.
// Mode split (D39): G_I = J dn^2/(dn^2 + dt^2), G_II = J dt^2/(dn^2 + dt^2) with the crack
// opening (dn) and sliding (dt, upper - lower) of the mass-weighted mean displacements of the
// particles with -r_out <= xi1 <= -r_in, |xi2| <= 0.6 h behind the tip (isotropic linear
// elastic near-tip fields: K_II/K_I = dt/dn), as NairnMPM partitions J. A closed tip
// (dn <= 0) has G_I = 0.
// Growth (D40): see CrackGrowth in solver.hpp; direction by the maximum hoop stress
// criterion theta = 2 atan((1 - sqrt(1 + 8 R^2)) / (4 R)), R = K_II/K_I.
// 3-D (D42): for a straight front edge, the same domain integral with q a function of the
// in-plane distance from the front line only (constant along the front, over the whole body,
// which the front must cross), divided by the front length in the material: the front-averaged
// (plane-strain-equivalent) J per unit front length; the split uses the same faces behind the
// front (its whole length). Mode III (tearing) is reported as a displacement, not split off.
// 3-D growth (D43): the same criterion as in 2-D on the front-averaged values; a front edge
// advances by the increment in the crack plane, normal to itself (no kinking out of plane).
#include "pnc/gimp_coupler/solver.hpp"

#include <string>
#include <vector>

namespace pnc::gimp {

/// One crack tip's fracture quantities.
struct TipResult {
  std::size_t crack = 0;                         ///< index into Solver::cracks
  int end = 1;                                   ///< 0: first point of the polyline, 1: last point
  Eigen::Vector2d tip = Eigen::Vector2d::Zero(); ///< tip position, m
  Eigen::Vector2d e1 = Eigen::Vector2d::UnitX(); ///< unit direction ahead of the tip
  double J = 0.0;                                ///< J-integral = G, J/m^2
  double GI = 0.0;                               ///< mode I part, J/m^2
  double GII = 0.0;                              ///< mode II part, J/m^2
  double opening = 0.0; ///< crack opening displacement behind the tip (dn), m
  double sliding = 0.0; ///< crack sliding displacement behind the tip (dt, upper - lower), m
  double length = 0.0;  ///< polyline length of the crack, m
  int particles = 0;    ///< particles in the J domain (r_in < r < r_out)
  /// "<crack>_start" / "<crack>_end" (history column suffix).
  std::string label(const Solver<2>& s) const;
};

/// J, G_I, G_II of every crack tip (ends with Crack::tip == 1) of an initialised solver.
std::vector<TipResult> crack_tips(const Solver<2>& s);

/// One straight front of a 3-D planar crack (D42): front-averaged quantities.
struct FrontResult {
  std::size_t crack = 0; ///< index into Solver::cracks
  std::size_t edge = 0;  ///< front edge: corners[edge] -> corners[(edge + 1) % n]
  Eigen::Vector3d mid = Eigen::Vector3d::Zero(); ///< midpoint of the front edge, m
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX(); ///< unit direction ahead (in the crack plane)
  Eigen::Vector3d e2 = Eigen::Vector3d::UnitY(); ///< crack normal (upper face: xi2 > 0)
  Eigen::Vector3d e3 = Eigen::Vector3d::UnitZ(); ///< along the front, e1 x e2
  double J = 0.0;                                ///< front-averaged J per unit front length, J/m^2
  double GI = 0.0;                               ///< mode I part, J/m^2
  double GII = 0.0;     ///< mode II part (in-plane sliding normal to the front), J/m^2
  double opening = 0.0; ///< mean opening behind the front (upper - lower, along e2), m
  double sliding = 0.0; ///< mean sliding along e1, m
  double tearing = 0.0; ///< mean sliding along the front (mode III, not split off), m
  double length = 0.0;  ///< front length inside the material (J is divided by it), m
  double depth = 0.0;   ///< crack length normal to the front (polygon extent along -e1), m
  int particles = 0;    ///< particles in the J domain
  /// "<crack>_front<edge>" (history column suffix).
  std::string label(const Solver<3>& s) const;
};

/// Front-averaged J, G_I, G_II of every front edge (Crack::front == 1) of the 3-D cracks of an
/// initialised solver.
std::vector<FrontResult> crack_fronts(const Solver<3>& s);

/// Kink angle (rad, counter-clockwise from e1 toward the upper face normal e2) of the maximum
/// hoop stress criterion for the mode ratio K_II/K_I = sliding/opening. Pure mode I: 0; pure
/// positive mode II (or a closed tip with positive sliding): -70.53 deg.
double hoop_angle(double opening, double sliding);

/// Applies the growth criterion of every tip whose crack has growth.Gc > 0; advances a tip by
/// one increment when the criterion is met (at most once per call), updates the solver's
/// crack geometry, and marks a tip that has left the material (no particle within h ahead of
/// it) as no longer a tip. Returns the number of increments made.
int grow_cracks(Solver<2>& s, const std::vector<TipResult>& tips);

/// 3-D (D43): applies the same criterion (growth_due()) to the front-averaged J, G_I, G_II of
/// every front whose crack has growth.Gc > 0; a front that meets it advances by one increment
/// in the crack plane, normal to itself (both corners of the front edge move by increment *
/// e1; the polygon stays planar, a loss of convexity is an error), at most once per call. A
/// front with no material within h ahead of its midpoint afterwards stops being a front (the
/// 2-D rule). Updates the solver's crack geometry; returns the number of increments made.
int grow_cracks(Solver<3>& s, const std::vector<FrontResult>& fronts);

/// The growth criterion (D40), shared by 2-D tips and 3-D fronts: true when the crack has
/// growth controls (Gc > 0, increment > 0), fewer than max_increments increments, and
/// J >= Gc (GIIc = 0) or G_I/Gc + G_II/GIIc >= 1 (GIIc > 0).
bool growth_due(const Crack& c, double J, double GI, double GII);

} // namespace pnc::gimp
