// The cracks of the JSON input of `pnc gimp run` (input_parts.hpp, docs/gimp.md): 2-D
// polylines with their tips (D38), 3-D planar polygons with their fronts (D42), growth (D40,
// D43) and the J-integral domain.
#include "input_parts.hpp"

namespace pnc::gimp::input_detail {

namespace {

/// 3-D: the corners of the planar polygon and its fronts (D42).
void read_crack_corners(const Node& c, Crack& cr, const Solver<3>& s) {
  const std::string& source = c.src;
  // corners: >= 3 points [x, y, z]; points, tips: refused in 3-D (checked_input)
  const json& cj = c.at("corners");
  for (const auto& q : cj)
    cr.corners.emplace_back(q[0].get<double>(), q[1].get<double>(), q[2].get<double>());
  const std::string why = check_planar_crack(cr);
  if (!why.empty()) c.bad("corners", cj, why);
  const std::size_t m = cr.corners.size();
  if (c.has("front")) {
    const json& fj = c.at("front");
    const std::string rule = "must be \"auto\" or an array of edge indices in [0, " +
                             std::to_string(m - 1) +
                             "] (edge k runs from corners[k] to corners[k+1]; a front is "
                             "one straight edge)";
    if (fj.is_string()) { // "auto"
      cr.front.assign(m, -1);
    } else {
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
  const json& pts = c.at("points"); // >= 2 points [x, y] (checked_input)
  for (const auto& q : pts)
    cr.points.emplace_back(q[0].get<double>(), q[1].get<double>());
  for (std::size_t i = 0; i + 1 < cr.points.size(); ++i)
    if ((cr.points[i + 1] - cr.points[i]).norm() <= 0.0)
      c.bad("points", pts, "consecutive points must differ");
  const std::string t = c.str("tips"); // D38; one of the declared values
  if (t == "auto")
    cr.tip = {-1, -1};
  else if (t == "start")
    cr.tip = {1, 0};
  else if (t == "end")
    cr.tip = {0, 1};
  else if (t == "both")
    cr.tip = {1, 1};
  else
    cr.tip = {0, 0}; // none
}

/// D40; 3-D: D43 (the same keys; a 3-D front advances in its plane, normal to itself). And the
/// J-integral domain.
template <int D> void read_crack_growth(const Node& c, Crack& cr, const Solver<D>& s) {
  if (c.has("growth")) {
    const Node gr = c.child("growth"); // types and ranges checked (checked_input)
    cr.growth.Gc = gr.num("Gc");
    if (gr.has("GIIc")) cr.growth.GIIc = gr.num("GIIc");
    cr.growth.increment = gr.has("increment") ? gr.num("increment") : s.grid.h;
    if (gr.has("direction")) { // 2-D only (3-D: refused by checked_input, D43)
      const json& dj = gr.at("direction");
      if (dj.is_string()) { // "hoop"
        cr.growth.prescribed = false;
      } else {
        cr.growth.prescribed = true;
        cr.growth.direction = gr.vec<2>("direction").normalized();
      }
    }
    cr.growth.max_increments = gr.at("max_increments").get<int>();
  }
  if (c.has("j_radius")) {
    const json& r = c.at("j_radius");
    cr.j_inner = r[0].get<double>();
    cr.j_outer = r[1].get<double>();
  }
}

} // namespace

template <int D> void read_cracks(const Node& top, Solver<D>& s) {
  const std::string& source = top.src;
  const json& cs = top.at("cracks"); // each checked against the crack keys of D
  for (std::size_t k = 0; k < cs.size(); ++k) {
    const Node c{cs[k], "cracks[" + std::to_string(k) + "]", source};
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
