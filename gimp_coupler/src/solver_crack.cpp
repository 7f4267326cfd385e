// Cracks in the GIMP solver (solver.hpp; D37, D38, D42): which particle-node segments a crack
// cuts, the crack normal at a node, the second velocity field, frictionless contact of the
// faces, and the checks of 3-D planar cracks. SI units.
#include "pnc/gimp_coupler/solver.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pnc::gimp {

template <int D> bool Solver<D>::crosses(const Vec& a, const Vec& b) const {
  if constexpr (D == 2) {
    auto orient = [](const Vec& p, const Vec& q, const Vec& r) {
      return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
    };
    for (const auto& c : cracks)
      for (std::size_t k = 0; k + 1 < c.points.size(); ++k) {
        const Vec& p = c.points[k];
        const Vec& q = c.points[k + 1];
        const double o1 = orient(a, b, p), o2 = orient(a, b, q);
        const double o3 = orient(p, q, a), o4 = orient(p, q, b);
        if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) &&
            ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
          return true;
      }
    return false;
  } else {
    // D42: a and b strictly on opposite sides of the plane, and the piercing point strictly
    // inside the convex polygon (ties count as no crossing, as in 2-D).
    for (const auto& c : cracks) {
      const Vec& n = c.normal;
      const double da = n.dot(a - c.corners[0]), db = n.dot(b - c.corners[0]);
      if (!((da > 0 && db < 0) || (da < 0 && db > 0))) continue;
      const Vec x = a + (da / (da - db)) * (b - a);
      const std::size_t m = c.corners.size();
      bool in = true;
      for (std::size_t k = 0; k < m && in; ++k) {
        const Vec& p = c.corners[k];
        in = (c.corners[(k + 1) % m] - p).cross(x - p).dot(n) > 0.0;
      }
      if (in) return true;
    }
    return false;
  }
}

template <int D> typename Solver<D>::Vec Solver<D>::crack_normal(const Vec& X) const {
  double best = 1e300;
  Vec n = Vec::Zero();
  // Squared distance from X to segment p-q and the closest point.
  auto seg = [&](const Vec& p, const Vec& q, Vec& cp) {
    const Vec d = q - p;
    const double tt = std::clamp((X - p).dot(d) / d.squaredNorm(), 0.0, 1.0);
    cp = p + tt * d;
    return (X - cp).squaredNorm();
  };
  for (const auto& c : cracks) {
    if constexpr (D == 2) {
      for (std::size_t k = 0; k + 1 < c.points.size(); ++k) {
        Vec cp;
        const double dist = seg(c.points[k], c.points[k + 1], cp);
        if (dist < best) {
          best = dist;
          const Vec d = c.points[k + 1] - c.points[k];
          n = Vec(-d[1], d[0]).normalized();
          if ((X - cp).dot(n) > 0) n = -n;
        }
      }
    } else {
      // Distance to the polygon: to its plane if X projects inside, else to the nearest edge.
      const double dn = c.normal.dot(X - c.corners[0]);
      const Vec xp = X - dn * c.normal;
      const std::size_t m = c.corners.size();
      bool in = true;
      double dist = 1e300;
      for (std::size_t k = 0; k < m; ++k) {
        const Vec& p = c.corners[k];
        const Vec& q = c.corners[(k + 1) % m];
        in = in && (q - p).cross(xp - p).dot(c.normal) >= 0.0;
        Vec cp;
        dist = std::min(dist, seg(p, q, cp));
      }
      if (in) dist = dn * dn;
      if (dist < best) {
        best = dist;
        n = dn > 0 ? Vec(-c.normal) : Vec(c.normal);
      }
    }
  }
  return n;
}

// With cracks: node indices of the stencil entries that use field 1 are shifted by nnodes_.
template <int D> void Solver<D>::apply_fields(std::size_t p, Stencil<D>& st) const {
  const std::uint32_t mask = fmask_[p];
  if (!mask) return;
  for (int k = 0; k < Stencil<D>::size; ++k)
    if (mask & (1u << k)) st.node[k] += static_cast<std::int64_t>(nnodes_);
}

// Frictionless contact of crack faces at nodes with two active fields: if the faces touch or
// overlap ((u0 - u1) . n >= 0 within 1e-6 h) and approach ((v0 - v1) . n > 0), both fields
// get the normal velocity of their centre of mass; tangential velocities are left free.
// n: unit normal of the nearest crack segment, pointing from the node's side across it.
template <int D> void Solver<D>::contact(std::vector<Vec>& vel) const {
  for (std::size_t i : crack_nodes_) {
    const std::size_t j = i + nnodes_;
    if (!active_[i] || !active_[j]) continue;
    const Vec n = crack_normal(grid.position(static_cast<std::int64_t>(i)));
    const Vec u0 = gu_[i] / gm_[i], u1 = gu_[j] / gm_[j];
    if ((u0 - u1).dot(n) < -1e-6 * grid.h) continue; // open
    const double rel = (vel[i] - vel[j]).dot(n);
    if (rel <= 0.0) continue; // separating
    const double vn = (gm_[i] * vel[i].dot(n) + gm_[j] * vel[j].dot(n)) / (gm_[i] + gm_[j]);
    vel[i] += (vn - vel[i].dot(n)) * n;
    vel[j] += (vn - vel[j].dot(n)) * n;
  }
}

std::string check_planar_crack(Crack& c) {
  using V3 = Eigen::Vector3d;
  const std::size_t m = c.corners.size();
  if (m < 3) return "needs >= 3 corners [x, y, z] (a planar polygon)";
  double size = 0.0;
  for (std::size_t k = 0; k < m; ++k)
    for (std::size_t l = k + 1; l < m; ++l)
      size = std::max(size, (c.corners[k] - c.corners[l]).norm());
  for (std::size_t k = 0; k < m; ++k)
    if (!((c.corners[(k + 1) % m] - c.corners[k]).norm() > 1e-12 * size))
      return "degenerate: corners " + std::to_string(k) + " and " + std::to_string((k + 1) % m) +
             " coincide (consecutive corners must differ)";
  // Newell's normal: twice the vector area.
  V3 a = V3::Zero();
  V3 ctr = V3::Zero();
  for (std::size_t k = 0; k < m; ++k) {
    a += c.corners[k].cross(c.corners[(k + 1) % m]);
    ctr += c.corners[k] / static_cast<double>(m);
  }
  if (!(a.norm() > 1e-12 * size * size))
    return "degenerate: the polygon has zero area (or crosses itself)";
  const V3 n = a.normalized();
  for (std::size_t k = 0; k < m; ++k) {
    const double off = std::abs(n.dot(c.corners[k] - ctr));
    if (off > 1e-9 * size) {
      std::ostringstream o;
      o << "non-planar: corner " << k << " is " << off
        << " m off the polygon's mean plane (a crack must be planar, to 1e-9 of its size)";
      return o.str();
    }
  }
  double turn = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const V3 e0 = c.corners[k] - c.corners[(k + m - 1) % m];
    const V3 e1 = c.corners[(k + 1) % m] - c.corners[k];
    const double s = e0.cross(e1).dot(n);
    if (std::abs(s) <= 1e-9 * e0.norm() * e1.norm())
      return "degenerate: corner " + std::to_string(k) +
             " is collinear with its neighbours (a straight edge or front is one edge: give "
             "its two end corners only)";
    if (s < 0)
      return "not convex: the polygon turns the other way at corner " + std::to_string(k) +
             " (give a convex polygon, corners in order)";
    turn += std::atan2(s, e0.dot(e1));
  }
  if (std::abs(turn - 2.0 * 3.14159265358979323846) > 1e-6)
    return "self-intersecting: the corners must go once around a convex polygon";
  c.normal = n;
  if (c.front.size() != m) c.front.assign(m, -1);
  return "";
}

Eigen::Vector3d edge_outward(const Crack& c, std::size_t k) {
  const std::size_t m = c.corners.size();
  const Eigen::Vector3d e = c.corners[(k + 1) % m] - c.corners[k];
  return e.cross(c.normal).normalized(); // counter-clockwise corners about n: e x n points out
}

std::string resolve_fronts(Crack& c, const Particles<3>& P, double h) {
  const std::size_t m = c.corners.size();
  auto material_near = [&](const Eigen::Vector3d& probe) {
    for (std::size_t p = 0; p < P.size(); ++p)
      if ((P.x0[p] - probe).squaredNorm() <= h * h) return true;
    return false;
  };
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector3d a = c.corners[k], b = c.corners[(k + 1) % m];
    if (c.front[k] < 0) c.front[k] = material_near(0.5 * (a + b) + h * edge_outward(c, k)) ? 1 : 0;
    if (c.front[k] != 1) continue;
    const Eigen::Vector3d e = (b - a).normalized();
    for (const Eigen::Vector3d& end : {Eigen::Vector3d(a - h * e), Eigen::Vector3d(b + h * e)})
      if (material_near(end)) {
        std::ostringstream o;
        o << "front edge " << k << " (corners " << k << " to " << (k + 1) % m
          << ") ends inside the material near (" << end[0] << ", " << end[1] << ", " << end[2]
          << ") m: only straight fronts that cross the whole body are supported (extend the "
             "polygon beyond the body's faces; D42)";
        return o.str();
      }
  }
  return "";
}

template bool Solver<2>::crosses(const Vec&, const Vec&) const;
template bool Solver<3>::crosses(const Vec&, const Vec&) const;
template Solver<2>::Vec Solver<2>::crack_normal(const Vec&) const;
template Solver<3>::Vec Solver<3>::crack_normal(const Vec&) const;
template void Solver<2>::apply_fields(std::size_t, Stencil<2>&) const;
template void Solver<3>::apply_fields(std::size_t, Stencil<3>&) const;
template void Solver<2>::contact(std::vector<Vec>&) const;
template void Solver<3>::contact(std::vector<Vec>&) const;

} // namespace pnc::gimp
