// The bodies of the JSON input of `pnc gimp run` (input_parts.hpp, docs/gimp.md): particles
// on a sub-grid inside shapes (box, circle/sphere, minus holes) or read from a CSV file.
#include "input_parts.hpp"

#include "pnc/core/csv.hpp"

#include <algorithm>
#include <array>
#include <set>
#include <sstream>

namespace pnc::gimp::input_detail {

namespace {

namespace fs = std::filesystem;

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
  const std::string kind = n.str("shape"); // one of the declared shapes (checked_input)
  // the keys a shape needs (declared without a default: "required by shape ...")
  for (const char* k : kind == "box" ? std::array<const char*, 2>{"min", "max"}
                                     : std::array<const char*, 2>{"center", "radius"})
    if (!n.has(k)) fail(n.src, n.key(k), "<missing>", "required by shape \"" + kind + "\"");
  if (kind == "box") {
    s.lo = n.vec<D>("min");
    s.hi = n.vec<D>("max");
    for (int a = 0; a < D; ++a)
      if (!(s.hi[a] > s.lo[a])) n.bad("max", n.at("max"), "must exceed min on every axis");
  } else { // circle (2-D), sphere (3-D)
    s.ball = true;
    s.c = n.vec<D>("center");
    s.r = n.num("radius");
    s.lo = s.c.array() - s.r;
    s.hi = s.c.array() + s.r;
  }
  return s;
}

int material_index(const Node& n, const RunConfig& rc) {
  const std::string name = n.str("material");
  for (std::size_t i = 0; i < rc.material_names.size(); ++i)
    if (rc.material_names[i] == name) return static_cast<int>(i);
  n.bad("material", n.at("material"), "not the name of an entry of materials[]");
}

} // namespace

template <int D>
void read_bodies(const Node& top, int ppc, const std::string& base_dir, const RunConfig& rc,
                 Solver<D>& s) {
  using Vec = Eigen::Matrix<double, D, 1>;
  const std::string& source = top.src;
  const json& bodies = top.at("bodies"); // each checked against its shape's keys
  const double d = s.grid.h / ppc;
  const Vec half = Vec::Constant(0.5 * d);
  const double vol = std::pow(d, D); // 2-D: area x 1 m
  std::array<long, D> ns{};
  for (int a = 0; a < D; ++a)
    ns[a] = static_cast<long>(s.grid.n[a] - 1) * ppc;
  std::set<long long> taken;
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    const Node b{bodies[k], "bodies[" + std::to_string(k) + "]", source};
    const int mi = material_index(b, rc);
    const double rho = s.materials[static_cast<std::size_t>(mi)]->density();
    const Vec vel = b.has("velocity") ? b.vec<D>("velocity") : Vec::Zero();
    const std::size_t before = s.particles.size();
    if (b.str("shape") == "particles") {
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
      const Shape<D> sh = read_shape<D>(b);
      std::vector<Shape<D>> holes;
      const json& hs = b.at("holes");
      for (std::size_t h = 0; h < hs.size(); ++h)
        holes.push_back(
            read_shape<D>(Node{hs[h], b.key("holes[" + std::to_string(h) + "]"), source}));
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
}

template void read_bodies<2>(const Node&, int, const std::string&, const RunConfig&, Solver<2>&);
template void read_bodies<3>(const Node&, int, const std::string&, const RunConfig&, Solver<3>&);

} // namespace pnc::gimp::input_detail
