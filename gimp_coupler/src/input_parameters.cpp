// The keys of the JSON input of `pnc gimp run`, each declared once (pnc/core/parameters.hpp):
// name, type, default, range, unit (SI: m, kg, s, Pa) and one line of text. load_input reads
// through them (checked_input); `pnc gimp parameters` prints them, and the key tables of
// docs/gimp.md are generated from that printout (decisions D290-D292). The rules between keys
// (a box needs min and max, exactly one of fix / symmetry / velocity, unique material names,
// the CFL step, ...) are checked by the readers after read() (input.cpp, input_bodies.cpp,
// input_cracks.cpp).
#include "input_declare.hpp"
#include "input_parts.hpp"

#include "pnc/core/parameters.hpp"

#include <memory>

namespace pnc::gimp {

namespace {

using json = nlohmann::json;

// ---- entries not bound to a variable: read() returns their values ----

using declare::integer;
using declare::real;
using declare::string;

// A vector of one number per axis (dimension 0: the documentation of 2-D and 3-D).
Parameter& vec(Parameters& p, int dim, const std::string& key, std::string unit, std::string text) {
  Parameter e =
      detail::param_entry(key, ParamType::real_list, nullptr, std::move(unit), std::move(text));
  e.min_size = dim == 0 ? 2 : static_cast<std::size_t>(dim);
  e.max_size = dim == 0 ? 3 : static_cast<std::size_t>(dim);
  if (dim == 0) e.note = "one number per axis (dimension)";
  return p.add(std::move(e));
}

Parameter& table_list(Parameters& p, const std::string& key, std::size_t min_size, std::string text,
                      ParamCheck each) {
  Parameter e = detail::param_entry(key, ParamType::table_list, json::array(), "", std::move(text));
  e.min_size = min_size;
  e.check = std::move(each);
  if (min_size > 0) e.require();
  return p.add(std::move(e));
}

std::vector<Choice> axes(int dim) {
  std::vector<Choice> c = {{"x", ""}, {"y", ""}};
  if (dim != 2) c.push_back({"z", dim == 0 ? "3-D only" : ""});
  return c;
}

std::string axis_names(int dim) {
  return dim == 2 ? "\"x\" or \"y\"" : "\"x\", \"y\" or \"z\"";
}

bool is_axis(const json& v, int dim) {
  if (!v.is_string()) return false;
  const std::string& s = v.get_ref<const std::string&>();
  return s == "x" || s == "y" || (dim != 2 && s == "z");
}

bool finite_number(const json& v) {
  return v.is_number() && std::isfinite(v.get<double>());
}

// A custom entry whose check is `ok`; its refusal is "must be " + rule.
Parameter& custom(Parameters& p, const std::string& key, std::string type, std::string rule,
                  std::string unit, std::string text, std::string absent,
                  std::function<bool(const json&)> ok) {
  const std::string must = "must be " + rule;
  return p.custom(key, std::move(type), std::move(rule), std::move(unit), std::move(text),
                  std::move(absent),
                  [ok = std::move(ok), must](const json& v, const std::string& source,
                                             const std::string& field) {
                    if (!ok(v)) fail(source, field, show_json(v), must);
                  });
}

Parameter& ramp(Parameters& p, const std::string& key, std::string text) {
  return custom(p, key, "list of reals", "[t_start, t_end] in s with 0 <= t_start <= t_end", "s",
                std::move(text), "full value from t = 0", [](const json& v) {
                  return v.is_array() && v.size() == 2 && finite_number(v[0]) &&
                         finite_number(v[1]) && v[0].get<double>() >= 0 &&
                         v[1].get<double>() >= v[0].get<double>();
                });
}

// An array of points of `n` finite coordinates each, at least `min` of them.
bool points_ok(const json& v, std::size_t n, std::size_t min) {
  if (!v.is_array() || v.size() < min) return false;
  for (const auto& q : v) {
    if (!q.is_array() || q.size() != n) return false;
    for (const auto& x : q)
      if (!finite_number(x)) return false;
  }
  return true;
}

// ---- the tables (elements of materials[], bodies[], ...) ----

// The keys every material has, then those of its law (material_kinds.cpp: one entry per law).
void declare_material(Parameters& p, const std::string& type) {
  string(p, "name", nullptr, {}, "the material's name (unique), named by bodies[].material")
      .require();
  string(p, "type", nullptr, input_detail::material_type_choices(), "the law").require();
  real(p, "density", nullptr, RealRange::above(0), "kg/m^3", "mass density").require();
  if (const auto* k = input_detail::find_material_kind(type)) k->declare(p);
}

std::vector<Choice> shapes(int dim, bool particles) {
  std::vector<Choice> c = {{"box", "min..max"}};
  if (dim != 3) c.push_back({"circle", dim == 0 ? "2-D: center, radius" : "center, radius"});
  if (dim != 2) c.push_back({"sphere", dim == 0 ? "3-D: center, radius" : "center, radius"});
  if (particles) c.push_back({"particles", "read from a CSV file"});
  return c;
}

void declare_shape_keys(Parameters& p, int dim) {
  vec(p, dim, "min", "m", "lower corner of a box").no_default("required by shape box");
  vec(p, dim, "max", "m", "upper corner of a box").no_default("required by shape box");
  vec(p, dim, "center", "m", "centre of a circle or sphere")
      .no_default("required by shape circle, sphere");
  real(p, "radius", nullptr, RealRange::above(0), "m", "radius of a circle or sphere")
      .no_default("required by shape circle, sphere");
}

json read_hole(const json& v, const std::string& source, const std::string& field, int dim) {
  Parameters p("hole");
  string(p, "shape", nullptr, shapes(dim, false), "the hole's shape").require();
  declare_shape_keys(p, dim);
  return p.read(v, source, field);
}

void declare_body(Parameters& p, int dim, const std::string& shape) {
  string(p, "material", nullptr, {}, "the name of an entry of materials[]").require();
  string(p, "shape", nullptr, shapes(dim, true), "particles on a sub-grid in a shape, or a file")
      .require();
  vec(p, dim, "velocity", "m/s", "initial velocity").no_default("at rest");
  if (shape == "particles") {
    string(p, "file", nullptr, {},
           "CSV with columns x,y[,z],volume[,vx,vy[,vz]] (m, m^3; 2-D volume = area x 1 m; "
           "relative to the input file's folder)")
        .require();
    return;
  }
  declare_shape_keys(p, dim);
  table_list(p, "holes", 0, "shapes (box, circle or sphere) cut out of the body",
             [dim](const json& v, const std::string& source, const std::string& field) {
               for (std::size_t i = 0; i < v.size(); ++i)
                 (void)read_hole(v[i], source, field + "[" + std::to_string(i) + "]", dim);
             })
      .remark("each with shape and its keys (min, max or center, radius)");
}

void declare_boundary(Parameters& p, int dim) {
  string(p, "name", nullptr, {}, "name in the history columns").no_default("bc<index>");
  vec(p, dim, "min", "m", "lower corner of the box of grid nodes").require();
  vec(p, dim, "max", "m", "upper corner (>= min on every axis)").require();
  custom(p, "fix", "string or list of strings",
         "\"all\" or a non-empty array of axis names, each " + axis_names(dim), "",
         "velocity components held at 0", "not fixed",
         [dim](const json& v) {
           if (v.is_string()) return v.get_ref<const std::string&>() == "all";
           if (!v.is_array() || v.empty()) return false;
           for (const auto& e : v)
             if (!is_axis(e, dim)) return false;
           return true;
         })
      .remark("exactly one of fix, symmetry, velocity");
  string(p, "symmetry", nullptr, axes(dim), "the normal axis of a symmetry plane (held at 0)")
      .no_default("no symmetry");
  custom(p, "velocity", "table",
         "a table of velocity components, e.g. {\"x\": 0.1}: keys " + axis_names(dim) +
             ", finite numbers in m/s, at least one",
         "m/s", "prescribed velocity components (a moving boundary)", "none", [dim](const json& v) {
           if (!v.is_object() || v.empty()) return false;
           for (auto it = v.begin(); it != v.end(); ++it)
             if (!is_axis(json(it.key()), dim) || !finite_number(it.value())) return false;
           return true;
         });
  ramp(p, "ramp", "linear ramp from 0 at t_start to 1 at t_end");
}

void declare_traction(Parameters& p, int dim) {
  string(p, "name", nullptr, {}, "name of the load").no_default("traction<index>");
  vec(p, dim, "min", "m", "lower corner of the box of particle centroids").require();
  vec(p, dim, "max", "m", "upper corner").require();
  string(p, "axis", nullptr, axes(dim), "the loaded face's normal").require();
  vec(p, dim, "traction", "Pa", "traction vector").require();
  ramp(p, "ramp", "linear ramp from 0 at t_start to 1 at t_end");
}

// The crack keys of dimension `dim` (2 or 3); `at` is the section path of the crack ("" when
// reading one).
void declare_crack(Parameters& p, int dim, const std::string& at, bool& growth_given) {
  string(p, "name", nullptr, {}, "name in the history columns").no_default("crack<index>");
  if (dim == 2) {
    custom(p, "points", "list of points", "an array of >= 2 points [x, y] (finite numbers, m)", "m",
           "the polyline, undeformed configuration (consecutive points differ)", "",
           [](const json& v) { return points_ok(v, 2, 2); })
        .require();
    string(p, "tips", "auto",
           {{"auto", "an end is a tip if material lies within h ahead of it"},
            {"start", ""},
            {"end", ""},
            {"both", ""},
            {"none", ""}},
           "which ends are crack tips (D38)");
  } else {
    custom(p, "corners", "list of points", "an array of >= 3 corners [x, y, z] (finite numbers, m)",
           "m", "planar convex polygon, corners in order (D42)", "",
           [](const json& v) { return points_ok(v, 3, 3); })
        .require();
    custom(p, "front", "string or list of integers",
           "\"auto\" or an array of edge indices (edge k runs from corners[k] to corners[k+1])", "",
           "the front edges", "auto: an edge is a front if material lies within h ahead",
           [](const json& v) {
             if (v.is_string()) return v.get_ref<const std::string&>() == "auto";
             if (!v.is_array()) return false;
             for (const auto& e : v)
               if (!e.is_number_integer() || e.get<std::int64_t>() < 0) return false;
             return true;
           })
        .remark("indices < the number of corners");
  }
  custom(p, "j_radius", "list of reals", "[r_inner, r_outer] in m with 0 <= r_inner < r_outer", "m",
         "J-integral domain radii", "[h, 4h]", [](const json& r) {
           return r.is_array() && r.size() == 2 && finite_number(r[0]) && finite_number(r[1]) &&
                  r[0].get<double>() >= 0 && r[1].get<double>() > r[0].get<double>();
         });
  p.optional_section(at.empty() ? "growth" : at + ".growth", growth_given,
                     dim == 3 ? "growth of the fronts in the crack plane (D43)"
                              : "growth of the tips (D40)");
  real(p, "Gc", nullptr, RealRange::above(0), "J/m^2", "critical energy release rate").require();
  real(p, "GIIc", nullptr, RealRange::above(0), "J/m^2",
       "mode II toughness: criterion G_I/Gc + G_II/GIIc >= 1")
      .no_default("criterion J >= Gc");
  real(p, "increment", nullptr, RealRange::above(0), "m", "crack advance per growth step")
      .no_default("h, the cell size");
  if (dim != 3)
    custom(p, "direction", "string or list of reals", "\"hoop\" or a non-zero [dx, dy]", "1",
           "growth direction", "hoop: maximum hoop stress from the mode mix",
           [](const json& v) {
             if (v.is_string()) return v.get_ref<const std::string&>() == "hoop";
             return v.is_array() && v.size() == 2 && finite_number(v[0]) && finite_number(v[1]) &&
                    (v[0].get<double>() != 0 || v[1].get<double>() != 0);
           })
        .remark("2-D only");
  integer(p, "max_increments", 1000000, 0, 1000000000, "growth increments per tip at most");
}

json read_element(const std::string& what, const json& v, const std::string& source,
                  const std::string& field, const std::string& selector,
                  const std::function<void(Parameters&, const std::string&)>& declare,
                  const Parameter& sel) {
  if (!v.is_object()) fail(source, field, show_json(v), "must be a JSON object");
  const std::string f = field + "." + selector;
  if (!v.contains(selector)) fail(source, f, "<missing>", "is required: " + sel.rule());
  sel.validate(v.at(selector), source, f);
  Parameters p(what);
  declare(p, v.at(selector).get<std::string>());
  return p.read(v, source, field);
}

// The tables of the input as read (each with its defaults).
struct Tables {
  std::vector<json> materials, bodies, boundaries, cracks, tractions;
};

std::string at(const std::string& field, std::size_t i) {
  return field + "[" + std::to_string(i) + "]";
}

ParamCheck read_materials(std::vector<json>& out) {
  return [&out](const json& v, const std::string& source, const std::string& field) {
    Parameters types("material");
    declare_material(types, "");
    for (std::size_t i = 0; i < v.size(); ++i)
      out.push_back(read_element(
          "material", v[i], source, at(field, i), "type",
          [](Parameters& p, const std::string& t) { declare_material(p, t); }, types.at("type")));
  };
}

ParamCheck read_bodies(std::vector<json>& out, int dim) {
  return [&out, dim](const json& v, const std::string& source, const std::string& field) {
    Parameters shape("body");
    declare_body(shape, dim, "particles");
    for (std::size_t i = 0; i < v.size(); ++i)
      out.push_back(read_element(
          "body", v[i], source, at(field, i), "shape",
          [dim](Parameters& p, const std::string& s) { declare_body(p, dim, s); },
          shape.at("shape")));
  };
}

template <class Declare> ParamCheck read_tables(std::vector<json>& out, Declare declare) {
  return [&out, declare](const json& v, const std::string& source, const std::string& field) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      Parameters p("table");
      auto given = std::make_shared<bool>(false);
      p.hold(given);
      declare(p, *given);
      out.push_back(p.read(v[i], source, at(field, i)));
    }
  };
}

// The whole input; `t` null: the documentation (dimension 0: both dimensions), with the tables'
// keys as sections "materials[]", ... when `tables`.
void declare_input(Parameters& p, int dim, Tables* t, bool tables) {
  integer(p, "dimension", 0, 2, 3, "2 (plane strain) or 3").require();
  string(p, "title", nullptr, {}, "what the run is").no_default("no title");
  string(p, "units", "SI", {{"SI", "m, kg, s, Pa"}}, "the units of every number");
  integer(p, "particles_per_cell", 2, 1, 4,
          "particles per cell and axis on the sub-grid of the shapes (l = h / (2 ppc))");
  const auto none = [](const json&, const std::string&, const std::string&) {};
  table_list(p, "materials", 1, "the materials (section materials[])",
             t ? read_materials(t->materials) : ParamCheck(none));
  table_list(p, "bodies", 1,
             "the bodies (section bodies[]); a sub-grid point belongs to the first body that "
             "contains it",
             t ? read_bodies(t->bodies, dim) : ParamCheck(none));
  table_list(
      p, "boundaries", 0, "velocity conditions on grid nodes (section boundaries[])",
      t ? read_tables(t->boundaries, [dim](Parameters& q, bool&) { declare_boundary(q, dim); })
        : ParamCheck(none));
  table_list(
      p, "cracks", 0, "the cracks (section cracks[])",
      t ? read_tables(t->cracks, [dim](Parameters& q, bool& g) { declare_crack(q, dim, "", g); })
        : ParamCheck(none));
  real(p, "damping", 0.0, RealRange::at_least(0), "1/s",
       "grid velocity damping: nodal accelerations get -damping v (D41)");
  integer(p, "fracture_every", 10, 1, 1000000000, "steps between J evaluations and growth checks");
  integer(p, "threads", 1, 1, 256, "worker threads");

  p.section("grid", "the background grid of cubic cells");
  vec(p, dim, "origin", "m", "lower corner").no_default("the origin at 0");
  Parameter cells =
      detail::param_entry("cells", ParamType::integer_list, nullptr, "", "cells per axis");
  cells.int_min = 2;
  cells.int_max = 100000;
  cells.min_size = dim == 0 ? 2 : static_cast<std::size_t>(dim);
  cells.max_size = dim == 0 ? 3 : static_cast<std::size_t>(dim);
  p.add(std::move(cells)).require().remark("at most 5e7 grid nodes");
  real(p, "cell_size", nullptr, RealRange::above(0), "m", "cell size h").require();

  p.section("loads", "body and surface loads");
  vec(p, dim, "gravity", "m/s^2", "body acceleration").no_default("none");
  ramp(p, "gravity_ramp", "linear ramp of gravity from 0 at t_start to 1 at t_end");
  table_list(
      p, "tractions", 0, "surface tractions on particle strips (section loads.tractions[], D44)",
      t ? read_tables(t->tractions, [dim](Parameters& q, bool&) { declare_traction(q, dim); })
        : ParamCheck(none));

  p.section("time", "the time integration");
  real(p, "end", nullptr, RealRange::open_closed(0, 1e6), "s", "end time").require();
  real(p, "cfl", 0.5, RealRange::open_closed(0, 1), "1", "safety factor on the CFL step");
  real(p, "dt", 0.0, RealRange::at_least(0), "s", "fixed step; 0 = the CFL step every step")
      .remark("at most the CFL step of t = 0");
  integer(p, "max_steps", 0, 0, 1000000000000,
          "steps at most; 0 = no limit (then end must be reachable in 1e10 steps)");

  p.section("output", "frames, history and checkpoints");
  real(p, "interval", 0.0, RealRange::at_least(0), "s",
       "time between VTU frames; 0 = first and last only");
  string(p, "vtu", "ascii", {{"ascii", ""}, {"binary", "base64"}}, "encoding of the VTU arrays");
  integer(p, "history_every", 1, 1, 1000000000, "steps between history rows");
  integer(p, "checkpoint_every", 1, 1, 1000000, "VTU frames between checkpoints");

  if (t || !tables) return;
  for (const auto& m : input_detail::material_kinds()) {
    p.section("materials[]", m.text, "type = \"" + m.type + "\"");
    declare_material(p, m.type);
  }
  p.section("bodies[]", "particles on a sub-grid inside a shape minus holes",
            "shape != \"particles\"");
  declare_body(p, dim, "box");
  p.section("bodies[]", "particles read from a CSV file", "shape = \"particles\"");
  declare_body(p, dim, "particles");
  p.section("boundaries[]", "velocity conditions on the grid nodes inside min..max");
  declare_boundary(p, dim);
  static bool docs_growth = false;
  for (const int d : {2, 3}) {
    if (dim != 0 && d != dim) continue;
    p.section("cracks[]", d == 2 ? "a polyline crack" : "a planar polygon crack",
              dim == 0 ? "dimension " + std::to_string(d) : "");
    declare_crack(p, d, "cracks[]", docs_growth);
  }
  p.section("loads.tractions[]", "a traction on the particles whose centroid is in min..max");
  declare_traction(p, dim);
}

// 3-D: the 2-D crack keys refused with what to give instead (before the unknown-key rule).
void refuse_2d_crack_keys(const json& doc, const std::string& source) {
  if (!doc.is_object() || !doc.contains("cracks") || !doc["cracks"].is_array()) return;
  const json& cs = doc["cracks"];
  for (std::size_t k = 0; k < cs.size(); ++k) {
    const json& c = cs[k];
    if (!c.is_object()) continue;
    const auto has = [](const json& o, const char* key) {
      return o.contains(key) && !o.at(key).is_null();
    };
    const std::string f = at("cracks", k);
    if (has(c, "points"))
      fail(source, f + ".points", show_json(c["points"]),
           "in 3-D a crack is a planar polygon: give \"corners\" [[x, y, z], ...]");
    if (has(c, "tips"))
      fail(source, f + ".tips", show_json(c["tips"]),
           "in 3-D the fronts are edges: give \"front\"");
    if (has(c, "growth") && c["growth"].is_object() && has(c["growth"], "direction"))
      fail(source, f + ".growth.direction", show_json(c["growth"]["direction"]),
           "in 3-D a front advances in the crack plane, normal to itself (D43): kinking out of "
           "the plane (\"hoop\", the mode-mix direction) and prescribed directions are 2-D "
           "only; omit \"direction\"");
  }
}

} // namespace

Parameters input_parameters(int dimension, bool tables) {
  if (dimension != 0 && dimension != 2 && dimension != 3)
    throw std::invalid_argument("input_parameters: dimension must be 0, 2 or 3");
  Parameters p(dimension == 0 ? "pnc gimp run input"
                              : "pnc gimp run input (dimension " + std::to_string(dimension) + ")");
  declare_input(p, dimension, nullptr, tables);
  return p;
}

namespace input_detail {

json checked_input(const json& doc, const std::string& source, int dimension) {
  if (dimension == 3) refuse_2d_crack_keys(doc, source);
  Tables t;
  Parameters p("pnc gimp run input");
  declare_input(p, dimension, &t, false);
  json out = p.read(doc, source);
  out["materials"] = t.materials;
  out["bodies"] = t.bodies;
  out["boundaries"] = t.boundaries;
  out["cracks"] = t.cracks;
  out["loads"]["tractions"] = t.tractions;
  return out;
}

} // namespace input_detail

} // namespace pnc::gimp
