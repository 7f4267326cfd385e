// Energy release rates and growth of cracks (fracture.hpp; 3-D: D42, D43). SI units.
#include "pnc/gimp_coupler/fracture.hpp"
#include "pnc/core/error.hpp"

#include <cmath>
#include <stdexcept>

namespace pnc::gimp {

namespace {

using V2 = Eigen::Vector2d;
constexpr double kPi = 3.14159265358979323846;

double polyline_length(const Crack& c) {
  double L = 0.0;
  for (std::size_t k = 0; k + 1 < c.points.size(); ++k)
    L += (c.points[k + 1] - c.points[k]).norm();
  return L;
}

/// Tip position and unit direction ahead of it for one end of a crack.
void tip_frame(const Crack& c, int end, V2& tip, V2& e1) {
  const std::size_t m = c.points.size();
  tip = end == 0 ? c.points[0] : c.points[m - 1];
  const V2 prev = end == 0 ? c.points[1] : c.points[m - 2];
  e1 = (tip - prev).normalized();
}

/// D38: dq/dr of q = 1 (r <= r_in), (1 + cos(pi s))/2 with s = (r - r_in)/(r_out - r_in), 0
/// (r >= r_out); only called for r_in < r < r_out.
double dq_dr(double r, double rin, double rout) {
  return -0.5 * kPi * std::sin(kPi * (r - rin) / (rout - rin)) / (rout - rin);
}

/// D38: one particle's term V0 [(P grad q) . (H e1) - W (e1 . grad q)], P = J sigma F^-T.
template <int D>
double j_term(const Particles<D>& P, std::size_t p, const Eigen::Matrix<double, D, 1>& gq,
              const Eigen::Matrix<double, D, 1>& e1) {
  using M = Eigen::Matrix<double, D, D>;
  const M& F = P.F[p];
  const M Pk =
      F.determinant() * P.sigma[p].template topLeftCorner<D, D>() * F.inverse().transpose();
  const Eigen::Matrix<double, D, 1> du1 = (F - M::Identity()) * e1;
  return P.V0[p] * ((Pk * gq).dot(du1) - P.W[p] * e1.dot(gq));
}

/// D39: G_I, G_II from J and the opening/sliding behind the tip.
void mode_split(double J, double opening, double sliding, double& GI, double& GII) {
  const double n2 = opening * opening, t2 = sliding * sliding;
  if (opening <= 0.0 && t2 > 0.0) { // closed: no mode I
    GI = 0.0;
    GII = J;
  } else if (n2 + t2 > 0.0) {
    GI = J * n2 / (n2 + t2);
    GII = J * t2 / (n2 + t2);
  } else {
    GI = J;
    GII = 0.0;
  }
}

/// Mass-weighted mean displacements of the two faces (D39).
template <int D> struct Faces {
  using Vec = Eigen::Matrix<double, D, 1>;
  Vec up = Vec::Zero(), lo = Vec::Zero();
  double mup = 0.0, mlo = 0.0;
  void add(const Particles<D>& P, std::size_t p, bool upper) {
    const Vec u = P.x[p] - P.x0[p];
    (upper ? up : lo) += P.m[p] * u;
    (upper ? mup : mlo) += P.m[p];
  }
  bool ok() const { return mup > 0 && mlo > 0; }
  Vec jump() const { return up / mup - lo / mlo; }
};

} // namespace

std::string TipResult::label(const Solver<2>& s) const {
  return s.cracks[crack].name + (end == 0 ? "_start" : "_end");
}

std::vector<TipResult> crack_tips(const Solver<2>& s) {
  std::vector<TipResult> out;
  const auto& P = s.particles;
  const double h = s.grid.h;
  for (std::size_t c = 0; c < s.cracks.size(); ++c) {
    const Crack& cr = s.cracks[c];
    for (int end = 0; end < 2; ++end) {
      if (cr.tip[static_cast<std::size_t>(end)] != 1) continue;
      TipResult r;
      r.crack = c;
      r.end = end;
      tip_frame(cr, end, r.tip, r.e1);
      r.length = polyline_length(cr);
      const V2 e1 = r.e1, e2(-e1[1], e1[0]);
      const double rin = cr.j_outer > 0 ? cr.j_inner : h;
      const double rout = cr.j_outer > 0 ? cr.j_outer : 4.0 * h;
      // D39: faces behind the tip, particles with -r_out <= xi1 <= -r_in, |xi2| <= 0.6 h.
      Faces<2> faces;
      double J = 0.0;
      for (std::size_t p = 0; p < P.size(); ++p) {
        const V2 d = P.x0[p] - r.tip;
        const double rr = d.norm();
        if (rr > rin && rr < rout) {
          J += j_term<2>(P, p, V2(dq_dr(rr, rin, rout) / rr * d), e1);
          ++r.particles;
        }
        const double xi1 = d.dot(e1), xi2 = d.dot(e2);
        if (xi1 >= -rout && xi1 <= -rin && std::abs(xi2) <= 0.6 * h) faces.add(P, p, xi2 > 0);
      }
      r.J = J;
      if (faces.ok()) {
        const V2 du = faces.jump();
        r.opening = du.dot(e2);
        r.sliding = du.dot(e1);
      }
      mode_split(J, r.opening, r.sliding, r.GI, r.GII);
      out.push_back(r);
    }
  }
  return out;
}

std::string FrontResult::label(const Solver<3>& s) const {
  return s.cracks[crack].name + "_front" + std::to_string(edge);
}

std::vector<FrontResult> crack_fronts(const Solver<3>& s) {
  using V3 = Eigen::Vector3d;
  std::vector<FrontResult> out;
  const auto& P = s.particles;
  const double h = s.grid.h;
  for (std::size_t c = 0; c < s.cracks.size(); ++c) {
    const Crack& cr = s.cracks[c];
    const std::size_t m = cr.corners.size();
    for (std::size_t k = 0; k < m && k < cr.front.size(); ++k) {
      if (cr.front[k] != 1) continue;
      FrontResult r;
      r.crack = c;
      r.edge = k;
      const V3 a = cr.corners[k], b = cr.corners[(k + 1) % m];
      r.mid = 0.5 * (a + b);
      r.e1 = edge_outward(cr, k);
      r.e2 = cr.normal;
      r.e3 = r.e1.cross(r.e2);
      for (const V3& q : cr.corners)
        r.depth = std::max(r.depth, (r.mid - q).dot(r.e1));
      const double s0 = std::min((a - r.mid).dot(r.e3), (b - r.mid).dot(r.e3));
      const double s1 = std::max((a - r.mid).dot(r.e3), (b - r.mid).dot(r.e3));
      const double rin = cr.j_outer > 0 ? cr.j_inner : h;
      const double rout = cr.j_outer > 0 ? cr.j_outer : 4.0 * h;
      Faces<3> faces;
      double I = 0.0, lo = 1e300, hi = -1e300;
      for (std::size_t p = 0; p < P.size(); ++p) {
        const V3 d = P.x0[p] - r.mid;
        const double xi1 = d.dot(r.e1), xi2 = d.dot(r.e2), xi3 = d.dot(r.e3);
        if (xi3 < s0 || xi3 > s1) continue; // beyond the front's ends (outside the body)
        const double rr = std::hypot(xi1, xi2);
        if (rr < rout) { // the material along the front: its length
          const double l3 = std::abs(r.e3[0]) * P.l[p][0] + std::abs(r.e3[1]) * P.l[p][1] +
                            std::abs(r.e3[2]) * P.l[p][2];
          lo = std::min(lo, xi3 - l3);
          hi = std::max(hi, xi3 + l3);
        }
        if (rr > rin && rr < rout) {
          // q depends on the in-plane distance from the front line only: grad q has no e3 part.
          const V3 gq = (dq_dr(rr, rin, rout) / rr) * (xi1 * r.e1 + xi2 * r.e2);
          I += j_term<3>(P, p, gq, r.e1);
          ++r.particles;
        }
        if (xi1 >= -rout && xi1 <= -rin && std::abs(xi2) <= 0.6 * h) faces.add(P, p, xi2 > 0);
      }
      r.length = hi > lo ? std::min(hi, s1) - std::max(lo, s0) : 0.0;
      r.J = r.length > 0 ? I / r.length : 0.0;
      if (faces.ok()) {
        const V3 du = faces.jump();
        r.opening = du.dot(r.e2);
        r.sliding = du.dot(r.e1);
        r.tearing = du.dot(r.e3);
      }
      mode_split(r.J, r.opening, r.sliding, r.GI, r.GII);
      out.push_back(r);
    }
  }
  return out;
}

double hoop_angle(double opening, double sliding) {
  if (opening <= 0.0) { // closed tip: pure mode II limit
    if (sliding == 0.0) return 0.0;
    return sliding > 0 ? -std::acos(1.0 / 3.0) : std::acos(1.0 / 3.0);
  }
  const double R = sliding / opening; // K_II / K_I
  if (std::abs(R) < 1e-12) return 0.0;
  return 2.0 * std::atan((1.0 - std::sqrt(1.0 + 8.0 * R * R)) / (4.0 * R));
}

bool growth_due(const Crack& c, double J, double GI, double GII) {
  const CrackGrowth& g = c.growth;
  if (!(g.Gc > 0.0) || !(g.increment > 0.0) || c.increments >= g.max_increments) return false;
  return g.GIIc > 0.0 ? GI / g.Gc + GII / g.GIIc >= 1.0 : J >= g.Gc;
}

int grow_cracks(Solver<2>& s, const std::vector<TipResult>& tips) {
  int grown = 0;
  const double h = s.grid.h;
  for (const TipResult& r : tips) {
    Crack& c = s.cracks[r.crack];
    const CrackGrowth& g = c.growth;
    if (c.tip[static_cast<std::size_t>(r.end)] != 1) continue;
    if (!growth_due(c, r.J, r.GI, r.GII)) continue;
    V2 dir;
    if (g.prescribed) {
      dir = g.direction.normalized();
    } else {
      const double th = hoop_angle(r.opening, r.sliding);
      const V2 e2(-r.e1[1], r.e1[0]);
      dir = std::cos(th) * r.e1 + std::sin(th) * e2;
    }
    const V2 q = r.tip + g.increment * dir;
    if (r.end == 0)
      c.points.insert(c.points.begin(), q);
    else
      c.points.push_back(q);
    ++c.increments;
    ++grown;
    // Still inside the material? (the same probe as the automatic tip detection, D38)
    const V2 probe = q + h * dir;
    bool inside = false;
    for (std::size_t p = 0; p < s.particles.size() && !inside; ++p)
      inside = (s.particles.x0[p] - probe).squaredNorm() <= h * h;
    if (!inside) c.tip[static_cast<std::size_t>(r.end)] = 0;
  }
  if (grown) s.update_crack_geometry();
  return grown;
}

int grow_cracks(Solver<3>& s, const std::vector<FrontResult>& fronts) {
  int grown = 0;
  for (const FrontResult& r : fronts) {
    Crack& c = s.cracks[r.crack];
    if (r.edge >= c.front.size() || c.front[r.edge] != 1) continue;
    if (!growth_due(c, r.J, r.GI, r.GII)) continue;
    // D43: translate the front edge in the crack plane, normal to itself (e1 = the edge's
    // outward in-plane normal of the current polygon).
    const std::size_t m = c.corners.size();
    const Eigen::Vector3d step = c.growth.increment * edge_outward(c, r.edge);
    Crack moved = c;
    moved.corners[r.edge] += step;
    moved.corners[(r.edge + 1) % m] += step;
    const std::string why = check_planar_crack(moved);
    if (!why.empty())
      pnc::fail_simulation(
          "gimp: crack '" + c.name + "'", -1, std::numeric_limits<double>::quiet_NaN(), "",
          "growth of front edge " + std::to_string(r.edge) + " leaves no valid polygon: " + why);
    c.corners = moved.corners;
    c.normal = moved.normal;
    // Still a front? Decided again by the automatic rule (material within h ahead of the
    // midpoint, as the 2-D tip probe) in update_crack_geometry().
    c.front[r.edge] = -1;
    ++c.increments;
    ++grown;
  }
  if (grown) s.update_crack_geometry();
  return grown;
}

} // namespace pnc::gimp
