// The JSON input of `pnc gimp run` (input.hpp, docs/gimp.md).
#include "pnc/gimp_coupler/input.hpp"

#include "pnc/core/csv.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"
#include "pnc/fe_material/material.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace pnc::gimp {

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;
using Vec2 = Eigen::Vector2d;

std::string show(const json& v) {
  return show_json(v);
}

/// Access to one JSON object with the key path and the source for errors.
struct Node {
  const json& j;
  std::string path; // "bodies[0]" ("" at the top)
  const std::string& src;

  std::string key(const std::string& k) const { return path.empty() ? k : path + "." + k; }
  [[noreturn]] void bad(const std::string& k, const json& v, const std::string& rule) const {
    fail(src, key(k), show(v), rule);
  }
  bool has(const std::string& k) const { return j.contains(k) && !j.at(k).is_null(); }
  const json& at(const std::string& k) const {
    if (!has(k)) fail(src, key(k), "<missing>", "required key");
    return j.at(k);
  }
  Node child(const std::string& k) const {
    const json& c = at(k);
    if (!c.is_object()) bad(k, c, "must be a JSON object");
    return Node{c, key(k), src};
  }
  void allow(std::initializer_list<const char*> keys) const {
    for (auto it = j.begin(); it != j.end(); ++it) {
      bool ok = false;
      std::string list;
      for (const char* k : keys) {
        ok = ok || it.key() == k;
        list += (list.empty() ? "" : ", ") + std::string(k);
      }
      if (!ok) fail(src, key(it.key()), show(it.value()), "unknown key (allowed: " + list + ")");
    }
  }
  double num(const std::string& k) const {
    const json& v = at(k);
    if (!v.is_number() || !std::isfinite(v.get<double>())) bad(k, v, "must be a finite number");
    return v.get<double>();
  }
  double num(const std::string& k, double def) const { return has(k) ? num(k) : def; }
  double positive(const std::string& k) const {
    const double x = num(k);
    if (!(x > 0)) bad(k, j.at(k), "must be > 0");
    return x;
  }
  long integer(const std::string& k, long def, long lo, long hi) const {
    return has(k) ? get_integer_as<long>(j.at(k), src, key(k), lo, hi) : def;
  }
  std::string str(const std::string& k) const {
    const json& v = at(k);
    if (!v.is_string()) bad(k, v, "must be a string");
    return v.get<std::string>();
  }
  template <int D> Eigen::Matrix<double, D, 1> vec(const std::string& k) const {
    const json& v = at(k);
    if (!v.is_array() || v.size() != static_cast<std::size_t>(D))
      bad(k, v, "must be an array of " + std::to_string(D) + " numbers");
    Eigen::Matrix<double, D, 1> r;
    for (int a = 0; a < D; ++a) {
      const json& e = v[static_cast<std::size_t>(a)];
      if (!e.is_number() || !std::isfinite(e.get<double>()))
        bad(k, v, "must be an array of " + std::to_string(D) + " finite numbers");
      r[a] = e.get<double>();
    }
    return r;
  }
  Ramp ramp(const std::string& k) const {
    if (!has(k)) return Ramp{0.0, 0.0};
    const json& v = j.at(k);
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number() ||
        v[0].get<double>() < 0 || v[1].get<double>() < v[0].get<double>())
      bad(k, v, "must be [t_start, t_end] in s with 0 <= t_start <= t_end");
    return Ramp{v[0].get<double>(), v[1].get<double>()};
  }
  template <int D> int axis(const std::string& k, const json& v) const {
    static const char* names[] = {"x", "y", "z"};
    if (v.is_string())
      for (int a = 0; a < D; ++a)
        if (v.get<std::string>() == names[a]) return a;
    bad(k, v, D == 2 ? "must be \"x\" or \"y\"" : "must be \"x\", \"y\" or \"z\"");
  }
};

template <int D> struct Shape {
  using Vec = Eigen::Matrix<double, D, 1>;
  bool ball = false;
  Vec lo, hi, c;
  double r = 0.0;
  bool contains(const Vec& x) const {
    if (ball) return (x - c).squaredNorm() <= r * r;
    for (int a = 0; a < D; ++a)
      if (x[a] < lo[a] || x[a] > hi[a]) return false;
    return true;
  }
};

template <int D> Shape<D> read_shape(const Node& n) {
  Shape<D> s;
  const std::string kind = n.str("shape");
  if (kind == "box") {
    s.lo = n.vec<D>("min");
    s.hi = n.vec<D>("max");
    for (int a = 0; a < D; ++a)
      if (!(s.hi[a] > s.lo[a])) n.bad("max", n.at("max"), "must exceed min on every axis");
  } else if (kind == (D == 2 ? "circle" : "sphere")) {
    s.ball = true;
    s.c = n.vec<D>("center");
    s.r = n.positive("radius");
    s.lo = s.c.array() - s.r;
    s.hi = s.c.array() + s.r;
  } else {
    n.bad("shape", n.at("shape"),
          D == 2 ? "must be \"box\", \"circle\" or \"particles\""
                 : "must be \"box\", \"sphere\" or \"particles\"");
  }
  return s;
}

constexpr double kMaxEndTime = 1e6;         ///< s
constexpr double kMaxEstimatedSteps = 1e10; ///< without time.max_steps

std::string g(double x) {
  std::ostringstream o;
  o.precision(6);
  o << x;
  return o.str();
}

/// A fixed time.dt may not exceed the CFL step the solver computes at t = 0 (cfl h / (c +
/// |v|max), Solver::stable_dt); without time.max_steps the run must end in a bounded number of
/// steps (estimated with the step of t = 0).
void check_time_step(const Node& t, const RunConfig& rc, double cfl_dt) {
  if (rc.dt > 0 && rc.dt > cfl_dt)
    t.bad("dt", t.at("dt"),
          "the fixed step " + g(rc.dt) + " s exceeds the CFL step " + g(cfl_dt) + " s (cfl " +
              g(rc.cfl) + " x cell_size / (wave speed + largest particle speed)); give a dt <= " +
              g(cfl_dt) + " s or omit dt");
  const double dt0 = rc.dt > 0 ? rc.dt : cfl_dt;
  if (rc.max_steps == 0 && rc.t_end / dt0 > kMaxEstimatedSteps)
    t.bad("end", t.at("end"),
          "needs about " + g(rc.t_end / dt0) + " steps of " + g(dt0) +
              " s (more than 1e10): shorten time.end or set time.max_steps");
}

fs::path resolve(const std::string& base, const std::string& p) {
  fs::path q(p);
  return q.is_absolute() || base.empty() ? q : fs::path(base) / q;
}

} // namespace

int input_dimension(const std::string& path) {
  const json j = parse_json(read_text_file(path), path);
  if (!j.is_object()) fail(path, "", "", "the input must be one JSON object");
  if (!j.contains("dimension")) fail(path, "dimension", "<missing>", "required key (2 or 3)");
  const json& d = j["dimension"];
  if (!d.is_number_integer() || (d.get<long>() != 2 && d.get<long>() != 3))
    fail(path, "dimension", show(d), "must be 2 (plane strain) or 3");
  return static_cast<int>(d.get<long>());
}

template <int D> RunConfig load_input(const std::string& path, Solver<D>& solver) {
  return load_input_text<D>(read_text_file(path), path, fs::path(path).parent_path().string(),
                            solver);
}

template <int D>
RunConfig load_input_text(const std::string& text, const std::string& source,
                          const std::string& base_dir, Solver<D>& s) {
  using Vec = Eigen::Matrix<double, D, 1>;
  const json doc = parse_json(text, source);
  if (!doc.is_object()) fail(source, "", "", "the input must be one JSON object");
  const Node top{doc, "", source};
  top.allow({"dimension", "grid", "particles_per_cell", "materials", "bodies", "boundaries",
             "cracks", "loads", "time", "output", "threads", "title", "units", "damping",
             "fracture_every"});
  RunConfig rc;
  rc.source = source;
  rc.dimension = static_cast<int>(top.integer("dimension", 0, 2, 3));
  if (rc.dimension != D) top.bad("dimension", top.at("dimension"), "must be 2 or 3");
  if (top.has("units") && top.str("units") != "SI")
    top.bad("units", top.at("units"), "must be \"SI\" (m, kg, s, Pa)");

  // grid
  const Node g = top.child("grid");
  g.allow({"origin", "cells", "cell_size"});
  s.grid.origin = g.has("origin") ? g.vec<D>("origin") : Vec::Zero();
  s.grid.h = g.positive("cell_size");
  {
    const json& c = g.at("cells");
    if (!c.is_array() || c.size() != static_cast<std::size_t>(D))
      g.bad("cells", c, "must be an array of " + std::to_string(D) + " integers >= 2");
    for (int a = 0; a < D; ++a) {
      const json& e = c[static_cast<std::size_t>(a)];
      s.grid.n[a] = get_integer_as<int>(e, source, g.key("cells") + "[" + std::to_string(a) + "]",
                                        2, 100000) +
                    1;
    }
    double nodes = 1;
    for (int a = 0; a < D; ++a)
      nodes *= s.grid.n[a];
    if (nodes > 5e7) g.bad("cells", c, "at most 5e7 grid nodes");
  }
  const int ppc = static_cast<int>(top.integer("particles_per_cell", 2, 1, 4));

  // materials
  const json& mats = top.at("materials");
  if (!mats.is_array() || mats.empty()) top.bad("materials", mats, "must be a non-empty array");
  for (std::size_t k = 0; k < mats.size(); ++k) {
    const Node m{mats[k], "materials[" + std::to_string(k) + "]", source};
    if (!m.j.is_object()) fail(source, m.path, show(m.j), "must be a JSON object");
    const std::string name = m.str("name");
    for (const auto& prev : rc.material_names)
      if (prev == name) m.bad("name", m.at("name"), "material names must be unique");
    rc.material_names.push_back(name);
    const std::string type = m.str("type");
    const double rho = m.positive("density");
    if (type == "linear_elastic") {
      m.allow({"name", "type", "density", "E", "nu"});
      const double E = m.positive("E"), nu = m.num("nu");
      if (!(nu > -1 && nu < 0.5)) m.bad("nu", m.at("nu"), "must be in (-1, 0.5)");
      s.materials.push_back(std::make_shared<LinearElastic>(rho, E, nu));
    } else if (type == "hyperelastic_polymer") {
      m.allow({"name", "type", "density", "E", "nu", "c1", "c2"});
      double c1, c2;
      if (m.has("c1") || m.has("c2")) {
        if (m.has("E") || m.has("nu"))
          m.bad("E", m.has("E") ? m.at("E") : m.at("nu"), "give either (c1, c2) or (E, nu)");
        c1 = m.positive("c1");
        c2 = m.positive("c2");
      } else {
        const double E = m.num("E", 1.5e9), nu = m.num("nu", 0.33);
        if (!(E > 0)) m.bad("E", m.at("E"), "must be > 0");
        if (!(nu > -1 && nu < 0.5)) m.bad("nu", m.at("nu"), "must be in (-1, 0.5)");
        std::tie(c1, c2) = HyperelasticPolymer::calibrate(E, nu);
      }
      s.materials.push_back(std::make_shared<HyperelasticPolymer>(rho, c1, c2));
    } else if (type == "damage_card") {
      m.allow({"name", "type", "density", "card"});
      const fs::path card = resolve(base_dir, m.str("card"));
      if (!fs::exists(card)) m.bad("card", m.at("card"), "file not found: " + card.string());
      try {
        auto law = std::make_shared<const pnc::fe_material::Material>(
            pnc::fe_material::Material::from_card(card.string()));
        s.materials.push_back(std::make_shared<DamageLaw>(rho, law));
      } catch (const pnc::fe_material::Error& e) {
        m.bad("card", m.at("card"), std::string("not a usable material card: ") + e.what());
      }
    } else {
      m.bad("type", m.at("type"),
            "must be \"linear_elastic\", \"hyperelastic_polymer\" or \"damage_card\"");
    }
  }
  auto material_index = [&](const Node& n) {
    const std::string name = n.str("material");
    for (std::size_t i = 0; i < rc.material_names.size(); ++i)
      if (rc.material_names[i] == name) return static_cast<int>(i);
    n.bad("material", n.at("material"), "not the name of an entry of materials[]");
  };

  // bodies -> particles on a regular sub-grid of ppc^D points per cell
  const json& bodies = top.at("bodies");
  if (!bodies.is_array() || bodies.empty()) top.bad("bodies", bodies, "must be a non-empty array");
  const double d = s.grid.h / ppc;
  const Vec half = Vec::Constant(0.5 * d);
  const double vol = std::pow(d, D); // 2-D: area x 1 m
  std::array<long, D> ns{};
  for (int a = 0; a < D; ++a)
    ns[a] = static_cast<long>(s.grid.n[a] - 1) * ppc;
  std::set<long long> taken;
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    const Node b{bodies[k], "bodies[" + std::to_string(k) + "]", source};
    if (!b.j.is_object()) fail(source, b.path, show(b.j), "must be a JSON object");
    const int mi = material_index(b);
    const double rho = s.materials[static_cast<std::size_t>(mi)]->density();
    const Vec vel = b.has("velocity") ? b.vec<D>("velocity") : Vec::Zero();
    const std::size_t before = s.particles.size();
    if (b.has("shape") && b.str("shape") == "particles") {
      b.allow({"material", "shape", "file", "velocity"});
      const fs::path file = resolve(base_dir, b.str("file"));
      if (!fs::exists(file)) b.bad("file", b.at("file"), "file not found: " + file.string());
      const CsvTable t = read_csv(file.string());
      static const char* xn[] = {"x", "y", "z"};
      static const char* vn[] = {"vx", "vy", "vz"};
      std::array<std::size_t, D> cx{};
      for (int a = 0; a < D; ++a)
        cx[a] = t.column(xn[a]);
      const std::size_t cv = t.column("volume");
      bool has_v = true;
      for (int a = 0; a < D; ++a)
        has_v = has_v && std::find(t.header.begin(), t.header.end(), vn[a]) != t.header.end();
      for (std::size_t r = 0; r < t.rows.size(); ++r) {
        Vec x, v = vel;
        for (int a = 0; a < D; ++a)
          x[a] = t.rows[r][cx[a]];
        if (has_v)
          for (int a = 0; a < D; ++a)
            v[a] = t.rows[r][t.column(vn[a])];
        const double V = t.rows[r][cv];
        const std::string where = "line " + std::to_string(t.line_numbers[r]);
        if (!(V > 0))
          fail(file.string(), "volume (" + where + ")", std::to_string(V), "must be > 0");
        const double l = 0.5 * std::pow(V, 1.0 / D);
        if (l > 0.5 * s.grid.h * (1 + 1e-12))
          fail(file.string(), "volume (" + where + ")", std::to_string(V),
               "particle larger than a grid cell (uGIMP needs volume^(1/D) <= cell_size)");
        s.particles.add(x, Vec::Constant(l), rho * V, V, mi, v);
      }
    } else {
      b.allow({"material", "shape", "min", "max", "center", "radius", "velocity", "holes"});
      const Shape<D> sh = read_shape<D>(b);
      std::vector<Shape<D>> holes;
      if (b.has("holes")) {
        const json& hs = b.at("holes");
        if (!hs.is_array()) b.bad("holes", hs, "must be an array of shapes");
        for (std::size_t h = 0; h < hs.size(); ++h) {
          const Node hn{hs[h], b.key("holes[" + std::to_string(h) + "]"), source};
          if (!hn.j.is_object()) fail(source, hn.path, show(hn.j), "must be a JSON object");
          hn.allow({"shape", "min", "max", "center", "radius"});
          holes.push_back(read_shape<D>(hn));
        }
      }
      std::array<long, D> k0{}, k1{};
      // Clamped in floating point before the conversion: a body far outside the grid gives
      // quotients beyond the range of long (converting those is undefined behaviour).
      const auto cell_index = [](double q, long n) {
        return q > 0 ? static_cast<long>(std::min(q, static_cast<double>(n))) : 0L;
      };
      for (int a = 0; a < D; ++a) {
        k0[a] = cell_index(std::floor((sh.lo[a] - s.grid.origin[a]) / d), ns[a]);
        k1[a] = cell_index(std::ceil((sh.hi[a] - s.grid.origin[a]) / d), ns[a]);
      }
      std::array<long, D> q = k0;
      while (true) {
        Vec x;
        long long id = 0;
        for (int a = D - 1; a >= 0; --a) {
          x[a] = s.grid.origin[a] + (static_cast<double>(q[a]) + 0.5) * d;
          id = id * (ns[a] + 1) + q[a];
        }
        bool in = sh.contains(x);
        for (const auto& hole : holes)
          in = in && !hole.contains(x);
        if (in && taken.insert(id).second) s.particles.add(x, half, rho * vol, vol, mi, vel);
        int a = 0;
        for (; a < D; ++a) {
          if (++q[a] < k1[a]) break;
          q[a] = k0[a];
        }
        if (a == D) break;
      }
    }
    if (s.particles.size() == before)
      fail(source, b.path, show(b.j),
           "the body holds no particle (inside the grid, outside holes)");
  }
  // Particles must keep their support inside the grid.
  for (std::size_t p = 0; p < s.particles.size(); ++p) {
    Stencil<D> st;
    if (!compute_stencil(s.grid, s.particles.x[p], s.particles.l[p], st)) {
      std::ostringstream pos;
      for (int a = 0; a < D; ++a)
        pos << (a ? "," : "") << s.particles.x[p][a];
      fail(source, "bodies", "particle at (" + pos.str() + ")",
           "every particle's support must lie inside the grid: enlarge grid.cells or move the "
           "body at least half a cell away from the grid edge");
    }
  }

  // boundaries
  if (top.has("boundaries")) {
    const json& bs = top.at("boundaries");
    if (!bs.is_array()) top.bad("boundaries", bs, "must be an array");
    for (std::size_t k = 0; k < bs.size(); ++k) {
      const Node b{bs[k], "boundaries[" + std::to_string(k) + "]", source};
      if (!b.j.is_object()) fail(source, b.path, show(b.j), "must be a JSON object");
      b.allow({"name", "min", "max", "fix", "symmetry", "velocity", "ramp"});
      NodeBC<D> bc;
      bc.name = b.has("name") ? b.str("name") : "bc" + std::to_string(k);
      bc.lo = b.vec<D>("min");
      bc.hi = b.vec<D>("max");
      for (int a = 0; a < D; ++a)
        if (bc.hi[a] < bc.lo[a]) b.bad("max", b.at("max"), "must be >= min on every axis");
      const int kinds = int(b.has("fix")) + int(b.has("symmetry")) + int(b.has("velocity"));
      if (kinds != 1)
        fail(source, b.path, show(b.j), "give exactly one of fix, symmetry, velocity");
      if (b.has("fix")) {
        const json& fx = b.at("fix");
        if (fx.is_string() && fx.get<std::string>() == "all") {
          bc.mask.fill(true);
        } else if (fx.is_array() && !fx.empty()) {
          for (const auto& e : fx)
            bc.mask[static_cast<std::size_t>(b.axis<D>("fix", e))] = true;
        } else {
          b.bad("fix", fx, "must be \"all\" or an array of axis names");
        }
      } else if (b.has("symmetry")) {
        bc.mask[static_cast<std::size_t>(b.axis<D>("symmetry", b.at("symmetry")))] = true;
      } else {
        const Node v = b.child("velocity");
        static const char* names[] = {"x", "y", "z"};
        for (auto it = v.j.begin(); it != v.j.end(); ++it) {
          const int a = b.axis<D>("velocity", json(it.key()));
          bc.mask[static_cast<std::size_t>(a)] = true;
          bc.velocity[a] = v.num(names[a]);
        }
        if (v.j.empty())
          b.bad("velocity", v.j, "must give at least one component, e.g. {\"x\": 0.1}");
      }
      bc.ramp = b.ramp("ramp");
      // The box must contain at least one node.
      bool any = false;
      const double tol = 1e-9 * s.grid.h;
      for (std::int64_t i = 0; i < s.grid.nodes() && !any; ++i) {
        const Vec X = s.grid.position(i);
        bool in = true;
        for (int a = 0; a < D; ++a)
          in = in && X[a] >= bc.lo[a] - tol && X[a] <= bc.hi[a] + tol;
        any = in;
      }
      if (!any) fail(source, b.path, show(b.j), "the box [min, max] contains no grid node");
      s.bcs.push_back(bc);
    }
  }

  // cracks (2-D polylines, 3-D planar polygons: D42)
  if (top.has("cracks")) {
    const json& cs = top.at("cracks");
    if (!cs.is_array()) top.bad("cracks", cs, "must be an array");
    for (std::size_t k = 0; k < cs.size(); ++k) {
      const Node c{cs[k], "cracks[" + std::to_string(k) + "]", source};
      if (!c.j.is_object()) fail(source, c.path, show(c.j), "must be a JSON object");
      Crack cr;
      cr.name = c.has("name") ? c.str("name") : "crack" + std::to_string(k);
      if constexpr (D == 3) {
        if (c.has("points"))
          c.bad("points", c.at("points"),
                "in 3-D a crack is a planar polygon: give \"corners\" [[x, y, z], ...]");
        if (c.has("tips"))
          c.bad("tips", c.at("tips"), "in 3-D the fronts are edges: give \"front\"");
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
      } else {
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
            c.bad("tips", c.at("tips"),
                  "must be \"auto\", \"start\", \"end\", \"both\" or \"none\"");
        }
      } // D == 2

      // D40; 3-D: D43 (the same keys; a 3-D front advances in its plane, normal to itself)
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
      s.cracks.push_back(cr);
    }
  }

  // loads
  if (top.has("loads")) {
    const Node l = top.child("loads");
    l.allow({"gravity", "gravity_ramp", "tractions"});
    if (l.has("gravity")) s.gravity = l.vec<D>("gravity");
    s.gravity_ramp = l.ramp("gravity_ramp");
    if (l.has("tractions")) {
      const json& ts = l.at("tractions");
      if (!ts.is_array()) l.bad("tractions", ts, "must be an array");
      for (std::size_t k = 0; k < ts.size(); ++k) {
        const Node t{ts[k], l.key("tractions[" + std::to_string(k) + "]"), source};
        if (!t.j.is_object()) fail(source, t.path, show(t.j), "must be a JSON object");
        t.allow({"name", "min", "max", "axis", "traction", "ramp"});
        Traction<D> tr;
        tr.name = t.has("name") ? t.str("name") : "traction" + std::to_string(k);
        const Vec lo = t.vec<D>("min"), hi = t.vec<D>("max");
        tr.axis = t.axis<D>("axis", t.at("axis"));
        tr.traction = t.vec<D>("traction");
        tr.ramp = t.ramp("ramp");
        for (std::size_t p = 0; p < s.particles.size(); ++p) {
          bool in = true;
          for (int a = 0; a < D; ++a)
            in = in && s.particles.x[p][a] >= lo[a] && s.particles.x[p][a] <= hi[a];
          if (in) tr.particles.push_back(p);
        }
        if (tr.particles.empty())
          fail(source, t.path, show(t.j), "the box [min, max] selects no particle centroid");
        s.tractions.push_back(tr);
      }
    }
  }

  // time, output, threads
  const Node t = top.child("time");
  t.allow({"end", "cfl", "dt", "max_steps"});
  rc.t_end = t.positive("end");
  if (rc.t_end > kMaxEndTime) t.bad("end", t.at("end"), "must be in (0, 1e6] s");
  rc.cfl = t.num("cfl", 0.5);
  if (!(rc.cfl > 0 && rc.cfl <= 1)) t.bad("cfl", t.at("cfl"), "must be in (0, 1]");
  rc.dt = t.num("dt", 0.0);
  if (rc.dt < 0) t.bad("dt", t.at("dt"), "must be >= 0 (0: CFL step)");
  rc.max_steps = t.integer("max_steps", 0, 0, 1000000000000L);
  if (top.has("output")) {
    const Node o = top.child("output");
    o.allow({"interval", "vtu", "history_every", "checkpoint_every"});
    rc.output_interval = o.num("interval", 0.0);
    if (rc.output_interval < 0) o.bad("interval", o.at("interval"), "must be >= 0");
    if (o.has("vtu")) {
      const std::string f = o.str("vtu");
      if (f != "ascii" && f != "binary")
        o.bad("vtu", o.at("vtu"), "must be \"ascii\" or \"binary\"");
      rc.vtu_binary = f == "binary";
    }
    rc.history_every = o.integer("history_every", 1, 1, 1000000000L);
    rc.checkpoint_every = static_cast<int>(o.integer("checkpoint_every", 1, 1, 1000000L));
  }
  rc.threads = static_cast<int>(top.integer("threads", 1, 1, 256));
  if (top.has("damping")) { // D41
    s.damping = top.num("damping");
    if (!(s.damping >= 0)) top.bad("damping", top.at("damping"), "must be >= 0 (1/s)");
  }
  rc.fracture_every = top.integer("fracture_every", 10, 1, 1000000000L);
  s.threads = rc.threads;
  s.cfl = rc.cfl;
  check_time_step(t, rc, s.stable_dt());
  return rc;
}

template RunConfig load_input<2>(const std::string&, Solver<2>&);
template RunConfig load_input<3>(const std::string&, Solver<3>&);
template RunConfig load_input_text<2>(const std::string&, const std::string&, const std::string&,
                                      Solver<2>&);
template RunConfig load_input_text<3>(const std::string&, const std::string&, const std::string&,
                                      Solver<3>&);

} // namespace pnc::gimp
