// The input of `pnc gimp run` (JSON or TOML, D357) (input.hpp, docs/gimp.md): the file, its top
// level, the grid, materials, boundaries, loads and run controls. Bodies: input_bodies.cpp; cracks:
// input_cracks.cpp.
#include "pnc/gimp_coupler/input.hpp"

#include "input_parts.hpp"

#include "pnc/fe_material/material.hpp"

#include <sstream>

namespace pnc::gimp {

using namespace input_detail;

namespace {

namespace fs = std::filesystem;

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

} // namespace

namespace input_detail {

fs::path resolve(const std::string& base, const std::string& p) {
  fs::path q(p);
  return q.is_absolute() || base.empty() ? q : fs::path(base) / q;
}

template <int D> void read_grid(const Node& top, Solver<D>& s) {
  using Vec = Eigen::Matrix<double, D, 1>;
  const Node g = top.child("grid"); // types and ranges checked (checked_input)
  s.grid.origin = g.has("origin") ? g.vec<D>("origin") : Vec::Zero();
  s.grid.h = g.num("cell_size");
  {
    const json& c = g.at("cells");
    for (int a = 0; a < D; ++a)
      s.grid.n[a] = c[static_cast<std::size_t>(a)].get<int>() + 1;
    double nodes = 1;
    for (int a = 0; a < D; ++a)
      nodes *= s.grid.n[a];
    if (nodes > 5e7) g.bad("cells", c, "at most 5e7 grid nodes");
  }
}

template <int D>
void read_materials(const Node& top, const std::string& base_dir, RunConfig& rc, Solver<D>& s) {
  const std::string& source = top.src;
  const json& mats = top.at("materials"); // each checked against its type's keys
  for (std::size_t k = 0; k < mats.size(); ++k) {
    const Node m{mats[k], "materials[" + std::to_string(k) + "]", source};
    const std::string name = m.str("name");
    for (const auto& prev : rc.material_names)
      if (prev == name) m.bad("name", m.at("name"), "material names must be unique");
    rc.material_names.push_back(name);
    const std::string type = m.str("type");
    const double rho = m.num("density");
    const MaterialKind* kind = find_material_kind(type); // the declarations checked it
    if (!kind) m.bad("type", m.at("type"), "must be one of the material laws");
    s.materials.push_back(kind->make(m, base_dir, rho));
  }
}

template <int D> void read_boundaries(const Node& top, Solver<D>& s) {
  using Vec = Eigen::Matrix<double, D, 1>;
  const std::string& source = top.src;
  const json& bs = top.at("boundaries"); // each checked against the declared keys
  for (std::size_t k = 0; k < bs.size(); ++k) {
    const Node b{bs[k], "boundaries[" + std::to_string(k) + "]", source};
    NodeBC<D> bc;
    bc.name = b.has("name") ? b.str("name") : "bc" + std::to_string(k);
    bc.lo = b.vec<D>("min");
    bc.hi = b.vec<D>("max");
    for (int a = 0; a < D; ++a)
      if (bc.hi[a] < bc.lo[a]) b.bad("max", b.at("max"), "must be >= min on every axis");
    const int kinds = int(b.has("fix")) + int(b.has("symmetry")) + int(b.has("velocity"));
    if (kinds != 1) fail(source, b.path, show(b.j), "give exactly one of fix, symmetry, velocity");
    if (b.has("fix")) {
      const json& fx = b.at("fix");
      if (fx.is_string()) { // "all"
        bc.mask.fill(true);
      } else {
        for (const auto& e : fx)
          bc.mask[static_cast<std::size_t>(b.axis<D>("fix", e))] = true;
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

template <int D> void read_loads(const Node& top, Solver<D>& s) {
  using Vec = Eigen::Matrix<double, D, 1>;
  const std::string& source = top.src;
  const Node l = top.child("loads"); // types and ranges checked (checked_input)
  if (l.has("gravity")) s.gravity = l.vec<D>("gravity");
  s.gravity_ramp = l.ramp("gravity_ramp");
  if (l.has("tractions")) {
    const json& ts = l.at("tractions");
    for (std::size_t k = 0; k < ts.size(); ++k) {
      const Node t{ts[k], l.key("tractions[" + std::to_string(k) + "]"), source};
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

template void read_grid<2>(const Node&, Solver<2>&);
template void read_grid<3>(const Node&, Solver<3>&);
template void read_materials<2>(const Node&, const std::string&, RunConfig&, Solver<2>&);
template void read_materials<3>(const Node&, const std::string&, RunConfig&, Solver<3>&);
template void read_boundaries<2>(const Node&, Solver<2>&);
template void read_boundaries<3>(const Node&, Solver<3>&);
template void read_loads<2>(const Node&, Solver<2>&);
template void read_loads<3>(const Node&, Solver<3>&);

} // namespace input_detail

int input_dimension(const std::string& path) {
  const json j = read_input_file(path, "a GIMP input file", "input"); // D357
  if (!j.is_object()) fail(path, "", "", "the input must be one JSON object");
  if (!j.contains("dimension")) fail(path, "dimension", "<missing>", "required key (2 or 3)");
  const json& d = j["dimension"];
  if (!d.is_number_integer() || (d.get<long>() != 2 && d.get<long>() != 3))
    fail(path, "dimension", show(d), "must be 2 (plane strain) or 3");
  return static_cast<int>(d.get<long>());
}

template <int D> RunConfig load_input(const std::string& path, Solver<D>& solver) {
  return load_input_json<D>(read_input_file(path, "a GIMP input file", "input"), path,
                            fs::path(path).parent_path().string(), solver); // D357
}

template <int D>
RunConfig load_input_text(const std::string& text, const std::string& source,
                          const std::string& base_dir, Solver<D>& s) {
  return load_input_json<D>(parse_json(text, source), source, base_dir, s);
}

template <int D>
RunConfig load_input_json(const json& raw, const std::string& source, const std::string& base_dir,
                          Solver<D>& s) {
  if (!raw.is_object()) fail(source, "", "", "the input must be one JSON object");
  if (raw.contains("dimension") && raw["dimension"].is_number_integer() &&
      raw["dimension"].get<long>() != D)
    fail(source, "dimension", show(raw["dimension"]),
         "must be " + std::to_string(D) + " for this reader (input_dimension() picks it)");
  // Every key declared, typed and in range, the defaults filled in (input_parameters.cpp);
  // below: the rules between keys.
  const json doc = checked_input(raw, source, D);
  const Node top{doc, "", source};
  RunConfig rc;
  rc.source = source;
  rc.dimension = D;
  rc.expanded_input = doc.dump(); // D339
  read_grid<D>(top, s);
  const int ppc = doc.at("particles_per_cell").get<int>();
  read_materials<D>(top, base_dir, rc, s);
  read_bodies<D>(top, ppc, base_dir, rc, s);
  read_boundaries<D>(top, s);
  read_cracks<D>(top, s);
  if (raw.contains("loads")) read_loads<D>(top, s);

  const Node t = top.child("time");
  rc.t_end = t.num("end");
  rc.cfl = t.num("cfl");
  rc.dt = t.num("dt");
  rc.max_steps = t.at("max_steps").get<long>();
  const Node o = top.child("output");
  rc.output_interval = o.num("interval");
  rc.vtu_binary = o.str("vtu") == "binary";
  rc.history_every = o.at("history_every").get<long>();
  rc.checkpoint_every = o.at("checkpoint_every").get<int>();
  rc.threads = doc.at("threads").get<int>();
  s.damping = doc.at("damping").get<double>(); // D41
  rc.fracture_every = doc.at("fracture_every").get<long>();
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
template RunConfig load_input_json<2>(const json&, const std::string&, const std::string&,
                                      Solver<2>&);
template RunConfig load_input_json<3>(const json&, const std::string&, const std::string&,
                                      Solver<3>&);

} // namespace pnc::gimp
