// The cracks of the JSON input of `pnc gimp run` (input_parts.hpp, docs/gimp.md): 2-D
// polylines with their tips (D38), 3-D planar polygons with their fronts (D42), growth (D40,
// D43) and the J-integral domain.
#include "input_parts.hpp"

namespace pnc::gimp::input_detail {

namespace {

using Vec2 = Eigen::Vector2d;

/// 3-D: the corners of the planar polygon and its fronts (D42).
void read_crack_corners(const Node& c, Crack& cr, const Solver<3>& s) {
  const std::string& source = c.src;
  if (c.has("points"))
    c.bad("points", c.at("points"),
          "in 3-D a crack is a planar polygon: give \"corners\" [[x, y, z], ...]");
  if (c.has("tips")) c.bad("tips", c.at("tips"), "in 3-D the fronts are edges: give \"front\"");
  c.allow({"name", "corners", "front", "j_radius", "growth"});
  const json& cj = c.at("corners");
  if (!cj.is_array() || cj.size() < 3)
    c.bad("corners", cj, "must be an array of >= 3 corners [x, y, z] (m)");
  for (const auto& q : cj) {
    if (!q.is_array() || q.size() != 3 || !q[0].is_number() || !q[1].is_number() ||
        !q[2].is_number())
      c.bad("corners", cj, "every corner must be [x, y, z] (m)");
    cr.corners.emplace_back(q[0].get<double>(), q[1].get<double>(), q[2].get<double>());
  }
  const std::string why = check_planar_crack(cr);
  if (!why.empty()) c.bad("corners", cj, why);
  const std::size_t m = cr.corners.size();
  if (c.has("front")) {
    const json& fj = c.at("front");
    const std::string rule = "must be \"auto\" or an array of edge indices in [0, " +
                             std::to_string(m - 1) +
                             "] (edge k runs from corners[k] to corners[k+1]; a front is "
                             "one straight edge)";
    if (fj.is_string() && fj.get<std::string>() == "auto") {
      cr.front.assign(m, -1);
    } else if (fj.is_array()) {
      cr.front.assign(m, 0);
      for (const auto& e : fj) {
        std::size_t edge = 0;
        try { // checked, never narrowed; the error keeps the rule about edges
          edge = get_integer_as<std::size_t>(e, source, c.key("front"), 0,
                                             static_cast<std::int64_t>(m) - 1);
        } catch (const InputError&) {
          c.bad("front", fj, rule);
        }
        cr.front[edge] = 1;
      }
    } else {
      c.bad("front", fj, rule);
    }
  }
  const std::string w = resolve_fronts(cr, s.particles, s.grid.h);
  if (!w.empty()) {
    const std::string key = c.has("front") ? "front" : "corners";
    c.bad(key, c.at(key), w);
  }
}

/// 2-D: the polyline and its tips (D38).
void read_crack_points(const Node& c, Crack& cr) {
  c.allow({"name", "points", "tips", "j_radius", "growth"});
  const json& pts = c.at("points");
  if (!pts.is_array() || pts.size() < 2)
    c.bad("points", pts, "must be an array of >= 2 points [x, y]");
  for (const auto& q : pts) {
    if (!q.is_array() || q.size() != 2 || !q[0].is_number() || !q[1].is_number())
      c.bad("points", pts, "every point must be [x, y] (m)");
    cr.points.emplace_back(q[0].get<double>(), q[1].get<double>());
  }
  for (std::size_t i = 0; i + 1 < cr.points.size(); ++i)
    if ((cr.points[i + 1] - cr.points[i]).norm() <= 0.0)
      c.bad("points", pts, "consecutive points must differ");
  if (c.has("tips")) { // D38
    const std::string t = c.str("tips");
    if (t == "auto")
      cr.tip = {-1, -1};
    else if (t == "start")
      cr.tip = {1, 0};
    else if (t == "end")
      cr.tip = {0, 1};
    else if (t == "both")
      cr.tip = {1, 1};
    else if (t == "none")
      cr.tip = {0, 0};
    else
      c.bad("tips", c.at("tips"), "must be \"auto\", \"start\", \"end\", \"both\" or \"none\"");
  }
}

/// D40; 3-D: D43 (the same keys; a 3-D front advances in its plane, normal to itself). And the
/// J-integral domain.
template <int D> void read_crack_growth(const Node& c, Crack& cr, const Solver<D>& s) {
  if (c.has("growth")) {
    const Node gr = c.child("growth");
    gr.allow({"Gc", "GIIc", "increment", "direction", "max_increments"});
    cr.growth.Gc = gr.positive("Gc");
    if (gr.has("GIIc")) cr.growth.GIIc = gr.positive("GIIc");
    cr.growth.increment = gr.has("increment") ? gr.positive("increment") : s.grid.h;
    if (gr.has("direction")) {
      const json& dj = gr.at("direction");
      if constexpr (D == 3) {
        gr.bad("direction", dj,
               "in 3-D a front advances in the crack plane, normal to itself (D43): "
               "kinking out of the plane (\"hoop\", the mode-mix direction) and prescribed "
               "directions are 2-D only; omit \"direction\"");
      } else if (dj.is_string() && dj.get<std::string>() == "hoop") {
        cr.growth.prescribed = false;
      } else {
        const Vec2 v = gr.vec<2>("direction");
        if (!(v.norm() > 0)) gr.bad("direction", dj, "must be \"hoop\" or a non-zero [dx, dy]");
        cr.growth.prescribed = true;
        cr.growth.direction = v.normalized();
      }
    }
    cr.growth.max_increments =
        static_cast<int>(gr.integer("max_increments", 1000000, 0, 1000000000L));
  }
  if (c.has("j_radius")) {
    const json& r = c.at("j_radius");
    if (!r.is_array() || r.size() != 2 || !r[0].is_number() || !r[1].is_number() ||
        !(r[0].get<double>() >= 0) || !(r[1].get<double>() > r[0].get<double>()))
      c.bad("j_radius", r, "must be [r_inner, r_outer] in m with 0 <= r_inner < r_outer");
    cr.j_inner = r[0].get<double>();
    cr.j_outer = r[1].get<double>();
  }
}

} // namespace

template <int D> void read_cracks(const Node& top, Solver<D>& s) {
  const std::string& source = top.src;
  const json& cs = top.at("cracks");
  if (!cs.is_array()) top.bad("cracks", cs, "must be an array");
  for (std::size_t k = 0; k < cs.size(); ++k) {
    const Node c{cs[k], "cracks[" + std::to_string(k) + "]", source};
    if (!c.j.is_object()) fail(source, c.path, show(c.j), "must be a JSON object");
    Crack cr;
    cr.name = c.has("name") ? c.str("name") : "crack" + std::to_string(k);
    if constexpr (D == 3)
      read_crack_corners(c, cr, s);
    else
      read_crack_points(c, cr);
    read_crack_growth<D>(c, cr, s);
    s.cracks.push_back(cr);
  }
}

template void read_cracks<2>(const Node&, Solver<2>&);
template void read_cracks<3>(const Node&, Solver<3>&);

} // namespace pnc::gimp::input_detail
