// Energy release rates and growth of 2-D cracks (fracture.hpp). SI units.
#include "pnc/gimp_coupler/fracture.hpp"

#include <cmath>

namespace pnc::gimp {

namespace {

using V2 = Eigen::Vector2d;
using M2 = Eigen::Matrix2d;
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
      V2 up = V2::Zero(), lo = V2::Zero();
      double mup = 0.0, mlo = 0.0;
      double J = 0.0;
      for (std::size_t p = 0; p < P.size(); ++p) {
        const V2 d = P.x0[p] - r.tip;
        const double rr = d.norm();
        if (rr > rin && rr < rout) {
          // D38: q = (1 + cos(pi s))/2, s = (r - r_in)/(r_out - r_in): grad q continuous.
          const double sr = (rr - rin) / (rout - rin);
          const V2 gq = (-0.5 * kPi * std::sin(kPi * sr) / ((rout - rin) * rr)) * d;
          const M2& F = P.F[p];
          const M2 Pk =
              F.determinant() * P.sigma[p].topLeftCorner<2, 2>() * F.inverse().transpose();
          const V2 du1 = (F - M2::Identity()) * e1;
          J += P.V0[p] * ((Pk * gq).dot(du1) - P.W[p] * e1.dot(gq));
          ++r.particles;
        }
        const double xi1 = d.dot(e1), xi2 = d.dot(e2);
        if (xi1 >= -rout && xi1 <= -rin && std::abs(xi2) <= 0.6 * h) {
          const V2 u = P.x[p] - P.x0[p];
          if (xi2 > 0) {
            up += P.m[p] * u;
            mup += P.m[p];
          } else {
            lo += P.m[p] * u;
            mlo += P.m[p];
          }
        }
      }
      r.J = J;
      if (mup > 0 && mlo > 0) {
        const V2 du = up / mup - lo / mlo;
        r.opening = du.dot(e2);
        r.sliding = du.dot(e1);
      }
      const double n2 = r.opening * r.opening, t2 = r.sliding * r.sliding;
      if (r.opening <= 0.0 && t2 > 0.0) { // closed: no mode I
        r.GI = 0.0;
        r.GII = J;
      } else if (n2 + t2 > 0.0) {
        r.GI = J * n2 / (n2 + t2);
        r.GII = J * t2 / (n2 + t2);
      } else {
        r.GI = J;
      }
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

int grow_cracks(Solver<2>& s, const std::vector<TipResult>& tips) {
  int grown = 0;
  const double h = s.grid.h;
  for (const TipResult& r : tips) {
    Crack& c = s.cracks[r.crack];
    const CrackGrowth& g = c.growth;
    if (!(g.Gc > 0.0) || !(g.increment > 0.0) || c.increments >= g.max_increments) continue;
    if (c.tip[static_cast<std::size_t>(r.end)] != 1) continue;
    const bool go = g.GIIc > 0.0 ? r.GI / g.Gc + r.GII / g.GIIc >= 1.0 : r.J >= g.Gc;
    if (!go) continue;
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

} // namespace pnc::gimp
