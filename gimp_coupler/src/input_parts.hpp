#pragma once
// The parts of the JSON input of `pnc gimp run` (input.hpp, docs/gimp.md), one reader per
// section; private to the solver library. Every error is a pnc::InputError naming the file,
// the key path, the value and the rule. SI units (m, kg, s, Pa).
#include "pnc/gimp_coupler/input.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/params.hpp"
#include "pnc/gimp_coupler/materials.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace pnc::gimp::input_detail {

using json = nlohmann::json;

inline std::string show(const json& v) {
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

/// The input checked against the declarations (input_parameters.cpp): no unknown key, every
/// value of its type and in its range, every default filled in (in the tables too); then the
/// readers below check the rules between keys and build the solver.
json checked_input(const json& doc, const std::string& source, int dimension);

/// One material law the input can name (materials[].type): its name, one line of text, its
/// keys beyond name, type and density (declared on the parameter layer), and how the law is
/// built from an entry that passed the declarations (rules between keys checked there).
/// The laws are the rows of material_kinds() in material_kinds.cpp, one line each.
struct MaterialKind {
  std::string type;
  std::string text;
  void (*declare)(Parameters& p);
  std::shared_ptr<const Material> (*make)(const Node& m, const std::string& base_dir,
                                          double density_kg_per_m3);
};
/// The registered laws, in the order of the documentation.
const std::vector<MaterialKind>& material_kinds();
/// The law named `type`, or nullptr.
const MaterialKind* find_material_kind(const std::string& type);
/// The laws as the allowed values of materials[].type.
std::vector<Choice> material_type_choices();

/// A relative path `p` resolved against the input's folder `base`.
std::filesystem::path resolve(const std::string& base, const std::string& p);

/// grid: origin, cells, cell_size.
template <int D> void read_grid(const Node& top, Solver<D>& s);
/// materials[]: the laws (materials.hpp); their names into rc.material_names.
template <int D>
void read_materials(const Node& top, const std::string& base_dir, RunConfig& rc, Solver<D>& s);
/// bodies[] -> particles on a regular sub-grid of ppc^D points per cell, or from a CSV file;
/// every particle's support must lie inside the grid.
template <int D>
void read_bodies(const Node& top, int ppc, const std::string& base_dir, const RunConfig& rc,
                 Solver<D>& s);
/// boundaries[]: velocity BCs on the grid nodes in a box.
template <int D> void read_boundaries(const Node& top, Solver<D>& s);
/// cracks[]: 2-D polylines, 3-D planar polygons (D42), their growth (D40, D43).
template <int D> void read_cracks(const Node& top, Solver<D>& s);
/// loads: gravity and surface tractions (D44).
template <int D> void read_loads(const Node& top, Solver<D>& s);

} // namespace pnc::gimp::input_detail
