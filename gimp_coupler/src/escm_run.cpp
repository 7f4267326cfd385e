// `pnc gimp couple`: an ESCM tension run from a JSON input (escm_run.hpp, docs/escm.md).
#include "pnc/gimp_coupler/escm_run.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/locate.hpp"
#include "pnc/core/params.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/subprocess.hpp"
#include "pnc/gimp_coupler/escm_checkpoint.hpp"
#include "pnc/gimp_coupler/escm_crack.hpp"
#include "pnc/gimp_coupler/escm_gradient.hpp"
#include "pnc/gimp_coupler/escm_lj.hpp"
#ifdef PNC_ESCM_HAS_POLYMER
#include "pnc/gimp_coupler/escm_polymer.hpp"
#endif
#include "pnc/gimp_coupler/fracture.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#ifndef PNC_GIMP_PYTHON
#define PNC_GIMP_PYTHON "/usr/bin/python3"
#endif

namespace pnc::gimp::escm {

namespace {

using json = nlohmann::json;

struct Params {
  double eps = 0.2381, sig = 3.405, rc = 2.5 * 3.405, mass = 39.948;
  int ncx = 40, ncy = 20, nbx = 14, nby = 14, nz = 3;
  int svc = 2, ivc = 1, substeps = 20;
  double dtau_fs = 4.0;
  std::string mode = "neumann";
  double temperature = 0.0;
  double strain = 1e-2, settle_ps = 10, load_ps = 40, hold_ps = 30, damping_fraction = 0.7;
  int frames = 8;
  double gradient_cells = 1.0;    ///< background grid spacing of eqs. 6.3-6.7, in cell sizes
  std::string load = "tension_x"; ///< tension_x (Case I), tension_y (Case II), shear (Case III)
  // Cases II/III (D80, D81): edge pre-crack on the line through the block centre.
  bool crack = false;
  int crack_cells = 3;         ///< initial tip in the middle of this cell column (from the left)
  double crack_Gc = 0.0;       ///< J/m^2, growth criterion of the continuum crack; 0: f W_sep (D83)
  double crack_f = 0.2;        ///< LJ epsilon across the crack line / epsilon (weak interface, D83)
  int crack_every = 5;         ///< coupled steps between J evaluations
  double checkpoint_ps = 10.0; ///< simulated time between checkpoints, ps; 0: only at the end
  // MD region: "lj" (the FCC crystal, default) or "polymer" (escm_polymer.hpp, D100-D106).
  std::string md_type = "lj";
  double cell_A = 6.0, slab_A = 16.0, density = -1, poly_T = 300, anneal_ps = 0,
         strain_probe = 1e-2;
  int beads_per_chain = -1, min_beads = 4;
  long md_seed = 1;
  double ff_sigma = -1, ff_epsilon = -1, ff_cutoff_sigma = -1; ///< < 0: rve/ defaults
  bool elastic_given = false;
  double elastic_lambda = 0, elastic_mu = 0; ///< Pa (given by the user)
};

const std::set<std::string> kKeys = {"lj",
                                     "cells",
                                     "block_cells",
                                     "slab_cells",
                                     "svc_rings",
                                     "ivc_rings",
                                     "substeps",
                                     "md_timestep_fs",
                                     "mode",
                                     "interior_temperature",
                                     "strain",
                                     "settle_ps",
                                     "load_ps",
                                     "hold_ps",
                                     "damping_fraction",
                                     "frames",
                                     "short",
                                     "comment",
                                     "gradient_spacing_cells",
                                     "load",
                                     "crack",
                                     "checkpoint_every_ps",
                                     "md"};

/// The "crack" object of Cases II/III (D80, D81, D83): length_cells, Gc, interface_fraction,
/// every; false disables it.
void apply_crack(const json& c, Params& p, const std::string& src, const std::string& key) {
  if (c.is_boolean() && !c.get<bool>()) {
    p.crack = false;
    return;
  }
  if (!c.is_object()) fail(src, key, show_json(c), "must be an object (or false)");
  p.crack = true;
  for (auto it = c.begin(); it != c.end(); ++it) {
    const std::string k = it.key();
    const json& v = it.value();
    if (k == "length_cells") {
      p.crack_cells = get_integer_as<int>(v, src, key + ".length_cells", 1, 2000);
    } else if (k == "Gc") {
      if (!v.is_number() || !(v.get<double>() > 0 && v.get<double>() < 1e3))
        fail(src, key + ".Gc", show_json(v), "a number in (0, 1e3) J/m^2");
      p.crack_Gc = v.get<double>();
    } else if (k == "interface_fraction") {
      if (!v.is_number() || !(v.get<double>() > 0 && v.get<double>() <= 1))
        fail(src, key + ".interface_fraction", show_json(v),
             "a number in (0, 1] (LJ epsilon across the crack line / epsilon, D83)");
      p.crack_f = v.get<double>();
    } else if (k == "every") {
      p.crack_every = get_integer_as<int>(v, src, key + ".every", 1, 100000); // coupled steps
    } else {
      fail(src, key + "." + k, "", "unknown key (length_cells, Gc, interface_fraction, every)");
    }
  }
}

/// The "md" object (docs/escm.md "Polymer MD region"): type "lj" | "polymer" and the polymer's
/// build keys; every key optional.
void apply_md(const json& m, Params& p, const std::string& src, const std::string& key) {
  if (!m.is_object()) fail(src, key, show_json(m), "must be an object");
  auto number = [&](const std::string& k, double lo, double hi, const std::string& rule) {
    const json& v = m.at(k);
    if (!v.is_number() || !(v.get<double>() >= lo && v.get<double>() <= hi))
      fail(src, key + "." + k, show_json(v), rule);
    return v.get<double>();
  };
  for (auto it = m.begin(); it != m.end(); ++it) {
    const std::string k = it.key();
    const json& v = it.value();
    if (k == "type") {
      if (!v.is_string() || (v.get<std::string>() != "lj" && v.get<std::string>() != "polymer"))
        fail(src, key + ".type", show_json(v), "\"lj\" or \"polymer\"");
      p.md_type = v.get<std::string>();
    } else if (k == "cell_A") {
      p.cell_A = number(k, 2, 100, "a number in [2, 100] A (cell size at the build density)");
    } else if (k == "slab_A") {
      p.slab_A = number(k, 5, 200, "a number in [5, 200] A (slab thickness at the build density)");
    } else if (k == "density") {
      p.density = number(k, 0.05, 3, "a number in [0.05, 3] g/cm^3 (build density)");
    } else if (k == "beads_per_chain") {
      p.beads_per_chain = get_integer_as<int>(v, src, key + "." + k, 4, 10000);
    } else if (k == "seed") {
      p.md_seed = get_integer_as<long>(v, src, key + ".seed", 1, 800000000);
    } else if (k == "temperature") {
      p.poly_T = number(k, 1, 2000, "a number in [1, 2000] K (NPT anneal)");
    } else if (k == "anneal_ps") {
      p.anneal_ps = number(k, 0, 1e4, "a number in [0, 1e4] ps");
    } else if (k == "min_beads_per_cell") {
      p.min_beads = get_integer_as<int>(v, src, key + "." + k, 1, 10000); // D105
    } else if (k == "strain_probe") {
      p.strain_probe = number(k, 1e-5, 0.05, "a number in [1e-5, 0.05] (D102)");
    } else if (k == "forcefield") {
      if (!v.is_object()) fail(src, key + ".forcefield", show_json(v), "must be an object");
      for (auto f = v.begin(); f != v.end(); ++f) {
        if (!f->is_number() || !(f->get<double>() > 0))
          fail(src, key + ".forcefield." + f.key(), show_json(*f), "a number > 0 (real units)");
        if (f.key() == "sigma")
          p.ff_sigma = f->get<double>();
        else if (f.key() == "epsilon")
          p.ff_epsilon = f->get<double>();
        else if (f.key() == "cutoff_sigma")
          p.ff_cutoff_sigma = f->get<double>();
        else
          fail(src, key + ".forcefield." + f.key(), "",
               "unknown key (sigma, epsilon, cutoff_sigma)");
      }
    } else if (k == "elastic") {
      if (v.is_string() && v.get<std::string>() == "measure") {
        p.elastic_given = false;
        continue;
      }
      const bool en = v.is_object() && v.size() == 2 && v.contains("E_Pa") && v.contains("nu");
      const bool lm =
          v.is_object() && v.size() == 2 && v.contains("lambda_Pa") && v.contains("mu_Pa");
      if (!(en || lm) || !v.begin()->is_number() || !(++v.begin())->is_number())
        fail(src, key + ".elastic", show_json(v),
             "\"measure\" or {\"E_Pa\", \"nu\"} or {\"lambda_Pa\", \"mu_Pa\"} (plane strain, Pa)");
      if (en) {
        const double E = v.at("E_Pa").get<double>(), nu = v.at("nu").get<double>();
        if (!(E > 0 && nu > -1 && nu < 0.5))
          fail(src, key + ".elastic", show_json(v), "E_Pa > 0 and nu in (-1, 0.5)");
        p.elastic_lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
        p.elastic_mu = E / (2 * (1 + nu));
      } else {
        p.elastic_lambda = v.at("lambda_Pa").get<double>();
        p.elastic_mu = v.at("mu_Pa").get<double>();
        if (!(p.elastic_mu > 0 && p.elastic_lambda + p.elastic_mu > 0))
          fail(src, key + ".elastic", show_json(v), "mu_Pa > 0 and lambda_Pa + mu_Pa > 0");
      }
      p.elastic_given = true;
    } else {
      fail(src, key + "." + k, "",
           "unknown key (type, cell_A, slab_A, density, beads_per_chain, seed, temperature, "
           "anneal_ps, min_beads_per_cell, strain_probe, forcefield, elastic)");
    }
  }
}

void apply(const json& j, Params& p, const std::string& src, const std::string& prefix) {
  auto num = [&](const std::string& k, double lo, double hi, const char* rule) {
    const json& v = j.at(k);
    if (!v.is_number() || !(v.get<double>() >= lo && v.get<double>() <= hi))
      fail(src, prefix + k, show_json(v), rule);
    return v.get<double>();
  };
  auto integer = [&](const std::string& k, int lo, int hi, const char*) {
    return get_integer_as<int>(j.at(k), src, prefix + k, lo, hi);
  };
  auto pair = [&](const std::string& k, int lo, int hi, const char* rule) {
    const json& v = j.at(k);
    if (!v.is_array() || v.size() != 2) fail(src, prefix + k, show_json(v), rule);
    return std::array<int, 2>{get_integer_as<int>(v[0], src, prefix + k + "[0]", lo, hi),
                              get_integer_as<int>(v[1], src, prefix + k + "[1]", lo, hi)};
  };
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!kKeys.count(it.key()) || (!prefix.empty() && (it.key() == "short" || it.key() == "lj")))
      fail(src, prefix + it.key(), "", "unknown key (docs/escm.md, \"Input file\")");
  if (j.contains("lj")) {
    const json& l = j.at("lj");
    if (!l.is_object()) fail(src, "lj", show_json(l), "must be an object");
    for (auto it = l.begin(); it != l.end(); ++it) {
      const std::string k = it.key();
      if (k != "epsilon" && k != "sigma" && k != "cutoff" && k != "mass")
        fail(src, "lj." + k, "", "unknown key (epsilon, sigma, cutoff, mass)");
      if (!it->is_number() || !(it->get<double>() > 0))
        fail(src, "lj." + k, show_json(*it), "must be a number > 0 (real units)");
    }
    p.eps = l.value("epsilon", p.eps);
    p.sig = l.value("sigma", p.sig);
    p.mass = l.value("mass", p.mass);
    p.rc = l.value("cutoff", 2.5 * p.sig);
    if (p.rc < 1.2 * p.sig || p.rc > 6 * p.sig)
      fail(src, "lj.cutoff", std::to_string(p.rc), "must be in [1.2, 6] sigma");
  }
  if (j.contains("cells")) {
    const auto c = pair("cells", 8, 2000, "two integers in [8, 2000]");
    p.ncx = c[0];
    p.ncy = c[1];
  }
  if (j.contains("block_cells")) {
    const auto c = pair("block_cells", 3, 200, "two integers in [3, 200]");
    p.nbx = c[0];
    p.nby = c[1];
  }
  if (j.contains("slab_cells")) p.nz = integer("slab_cells", 2, 50, "an integer in [2, 50]");
  if (j.contains("svc_rings")) p.svc = integer("svc_rings", 1, 10, "an integer in [1, 10]");
  if (j.contains("ivc_rings")) p.ivc = integer("ivc_rings", 1, 10, "an integer in [1, 10]");
  if (j.contains("substeps")) p.substeps = integer("substeps", 1, 10000, "an integer in [1, 1e4]");
  if (j.contains("md_timestep_fs"))
    p.dtau_fs = num("md_timestep_fs", 1e-4, 20, "a number in [1e-4, 20] fs");
  if (j.contains("mode")) {
    const json& v = j.at("mode");
    if (!v.is_string() || (v.get<std::string>() != "neumann" && v.get<std::string>() != "schwarz"))
      fail(src, prefix + "mode", show_json(v), "\"neumann\" or \"schwarz\"");
    p.mode = v.get<std::string>();
  }
  if (j.contains("interior_temperature"))
    p.temperature = num("interior_temperature", 0, 5000, "a number in [0, 5000] K");
  if (j.contains("strain")) p.strain = num("strain", -0.1, 0.1, "a number in [-0.1, 0.1]");
  if (j.contains("settle_ps")) p.settle_ps = num("settle_ps", 0, 1e5, "a number in [0, 1e5] ps");
  if (j.contains("load_ps")) p.load_ps = num("load_ps", 1e-3, 1e5, "a number in (0, 1e5] ps");
  if (j.contains("hold_ps")) p.hold_ps = num("hold_ps", 0, 1e5, "a number in [0, 1e5] ps");
  if (j.contains("damping_fraction"))
    p.damping_fraction = num("damping_fraction", 0, 10, "a number in [0, 10] (of critical)");
  if (j.contains("frames")) p.frames = integer("frames", 0, 1000, "an integer in [0, 1000]");
  if (j.contains("gradient_spacing_cells"))
    p.gradient_cells =
        num("gradient_spacing_cells", 0.5, 10,
            "a number in [0.5, 10] (spacing of the gradient grid in continuum cell sizes)");
  if (j.contains("load")) {
    const json& v = j.at("load");
    if (!v.is_string() || (v.get<std::string>() != "tension_x" &&
                           v.get<std::string>() != "tension_y" && v.get<std::string>() != "shear"))
      fail(src, prefix + "load", show_json(v), "\"tension_x\", \"tension_y\" or \"shear\"");
    p.load = v.get<std::string>();
  }
  if (j.contains("crack")) apply_crack(j.at("crack"), p, src, prefix + "crack");
  if (j.contains("md")) apply_md(j.at("md"), p, src, prefix + "md");
  if (j.contains("checkpoint_every_ps"))
    p.checkpoint_ps = num("checkpoint_every_ps", 0, 1e6,
                          "a number in [0, 1e6] ps (simulated time between checkpoints; 0: only "
                          "at the end and when stopped)");
}

/// Continuum particles as a VTU point cloud (SI: m, m/s): zone (-1 ordinary continuum, 1 IVC
/// probe, 2 SVC), displacement_m, velocity_m_per_s, F_solver (the GIMP solver's F11 F12 F21
/// F22), then `extra`.
void write_particles_vtu(const std::string& path, const Solver<2>& s, const std::vector<int>& zone,
                         const std::vector<PointArray>& extra) {
  const std::size_t n = s.particles.size();
  std::vector<Eigen::Vector3d> x(n);
  std::vector<PointArray> arrays = {
      {"displacement_m", 3, {}}, {"velocity_m_per_s", 3, {}}, {"F_solver", 4, {}}};
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& xi = s.particles.x[i];
    const Eigen::Vector2d u = xi - s.particles.x0[i];
    const Eigen::Vector2d& v = s.particles.v[i];
    const auto& F = s.particles.F[i];
    x[i] = Eigen::Vector3d(xi[0], xi[1], 0.0);
    arrays[0].values.insert(arrays[0].values.end(), {u[0], u[1], 0.0});
    arrays[1].values.insert(arrays[1].values.end(), {v[0], v[1], 0.0});
    arrays[2].values.insert(arrays[2].values.end(), {F(0, 0), F(0, 1), F(1, 0), F(1, 1)});
  }
  arrays.insert(arrays.end(), extra.begin(), extra.end());
  write_point_cloud_vtu(path, x, zone, arrays, 12);
}

/// Cases II/III (D80, D81): the crack line runs along the cell boundary through the centre of
/// the block, between two atom rows, and the pre-crack ends before the block.
void check_crack(const Params& p, const std::string& src) {
  if (p.load == "tension_x")
    fail(src, "load", "\"tension_x\"",
         "a crack along x needs load \"tension_y\" (Case II) or \"shear\" (Case III)");
  if (p.nby % 2 != 0)
    fail(src, "block_cells", std::to_string(p.nby),
         "with a crack the block needs an even number of cell rows (the crack line is the cell "
         "boundary through its centre, between two atom rows, D80)");
  if ((p.ncy - p.nby) % 2 != 0)
    fail(src, "cells", std::to_string(p.ncy),
         "with a crack cells[1] - block_cells[1] must be even (block centred on the crack line)");
  const int bx0 = (p.ncx - p.nbx) / 2;
  if (p.crack_cells > bx0 - 1)
    fail(src, "crack.length_cells", std::to_string(p.crack_cells),
         "the pre-crack tip must lie at least one cell before the atom block (<= " +
             std::to_string(bx0 - 1) + " here, D81)");
}

/// Reads the input and its "short" overrides and checks the geometry, before LAMMPS starts.
Params read_params(const CoupleOptions& o) {
  const std::string& src = o.input;
  const json j = parse_json(read_text_file(src), src);
  if (!j.is_object()) fail(src, "", "", "the input must be a JSON object");
  Params p;
  apply(j, p, src, "");
  if (o.short_mode && j.contains("short")) {
    if (!j.at("short").is_object())
      fail(src, "short", show_json(j.at("short")), "must be an object");
    apply(j.at("short"), p, src, "short.");
  }
  const int rings = p.svc + p.ivc;
  if (p.nbx < 2 * rings + 1 || p.nby < 2 * rings + 1)
    fail(src, "block_cells", std::to_string(p.nbx) + " x " + std::to_string(p.nby),
         "must be at least 2 (svc_rings + ivc_rings) + 1 cells per axis");
  if (p.nbx + 4 > p.ncx || p.nby + 4 > p.ncy)
    fail(src, "cells", std::to_string(p.ncx) + " x " + std::to_string(p.ncy),
         "the continuum needs >= 2 cells around the atom block on each side");
  if (p.crack) check_crack(p, src);
  if (p.md_type == "polymer") {
#ifndef PNC_ESCM_HAS_POLYMER
    fail(src, "md.type", "\"polymer\"", "this pnc was built without rve/ (PNC_BUILD_RVE=OFF)");
#endif
    // D114: Cases II/III with the polymer: the crack line is a weak interface of the block;
    // the continuum's Gc must be given (no lattice sum gives the polymer's work of separation).
    if (p.crack && !(p.crack_Gc > 0))
      fail(src, "crack.Gc", "", "must be given with md.type \"polymer\" (J/m^2, D114)");
    if (!p.crack && p.load != "tension_x")
      fail(src, "load", "\"" + p.load + "\"",
           "without a crack the polymer MD region runs Case I (\"tension_x\")");
    if (j.contains("lj")) fail(src, "lj", "", "not used with md.type \"polymer\"");
  }
  return p;
}

/// The loaded edge: BC index, displacement component, specimen length along the load (m) and
/// the wave speed of the fundamental mode (m/s, for the damping of D75).
struct Loading {
  std::size_t bc = 2;
  int comp = 0;
  double length = 0.0, speed = 0.0;
};

NodeBC<2> edge_bc(const std::string& name, Eigen::Vector2d lo, Eigen::Vector2d hi, bool x, bool y) {
  NodeBC<2> b;
  b.name = name;
  b.lo = lo;
  b.hi = hi;
  b.mask = {x, y};
  return b;
}

/// Grid, calibrated material (D76), one particle per cell, the BCs of the load case (D80; the
/// loaded edge's box includes the padding beyond it, D77) and the pre-crack (D80, D81).
Loading set_up_continuum(const Params& p, const LjFcc& lj, double Gc, Solver<2>& s) {
  const double h = lj.a0_A * units::m_per_A;
  s.grid.h = h;
  // Two cells of padding; in shear (Case III) the left and right edges travel |strain| H along
  // x, so the x padding grows by that many cells (D90).
  const int padx =
      2 + (p.load == "shear" ? static_cast<int>(std::ceil(std::abs(p.strain) * p.ncy)) : 0);
  s.grid.origin = Eigen::Vector2d(-padx * h, -2 * h);
  s.grid.n = {p.ncx + 2 * padx + 1, p.ncy + 5};
  s.materials.push_back(std::make_shared<LinearElastic>(lj.density, lj.E(), lj.nu())); // D76
  for (int jy = 0; jy < p.ncy; ++jy)
    for (int ix = 0; ix < p.ncx; ++ix)
      s.particles.add(Eigen::Vector2d((ix + 0.5) * h, (jy + 0.5) * h),
                      Eigen::Vector2d::Constant(0.5 * h), lj.density * h * h, h * h, 0);
  const double W = p.ncx * h, H = p.ncy * h, t = 0.1 * h;
  const Eigen::Vector2d corner_lo(-t, -t), corner_hi(t, t);
  Loading ld;
  if (p.load == "tension_x") { // Case I: left x-fixed, right pulled in x
    s.bcs = {edge_bc("left", {-t, -10 * h}, {t, H + 10 * h}, true, false),
             edge_bc("corner", corner_lo, corner_hi, false, true),
             edge_bc("right", {W - t, -10 * h}, {W + h + t, H + 10 * h}, true, false)};
    ld = {2, 0, W, std::sqrt(lj.strip_modulus() / lj.density)};
  } else if (p.load == "tension_y") { // Case II: bottom y-fixed, top pulled in y
    s.bcs = {edge_bc("bottom", {-10 * h, -t}, {W + 10 * h, t}, false, true),
             edge_bc("corner", corner_lo, corner_hi, true, false),
             edge_bc("top", {-10 * h, H - t}, {W + 10 * h, H + h + t}, false, true)};
    ld = {2, 1, H, std::sqrt(lj.strip_modulus() / lj.density)};
  } else { // Case III: bottom fixed, top moved along x (simple shear). D90: with the crack's
    // mouth on the left edge, strain < 0 (top moved in -x) presses the faces together (closed,
    // frictionless contact, D37: pure mode II); strain > 0 opens them (mixed mode).
    s.bcs = {edge_bc("bottom", {-10 * h, -t}, {W + 10 * h, t}, true, true),
             edge_bc("top", {-10 * h, H - t}, {W + 10 * h, H + h + t}, true, false)};
    ld = {1, 0, H, std::sqrt(0.5 * (lj.C11 - lj.C12) / lj.density)};
  }
  if (p.crack) {
    const int bx0 = (p.ncx - p.nbx) / 2, by0 = (p.ncy - p.nby) / 2;
    // D80: 0.01 h above the node line (ties count as no crossing, D37); D81: the last
    // increment puts the tip in the middle of the cell column just before the block.
    s.cracks.push_back(line_edge_crack((by0 + p.nby / 2 + 0.01) * h, (p.crack_cells + 0.5) * h, h,
                                       Gc, bx0 - 1 - p.crack_cells));
  }
  return ld;
}

/// D83: the atoms above the crack line become type 2; pairs across the line (types 1-2) get
/// LJ epsilon x interface_fraction (y_line_A in the LAMMPS frame).
void append_weak_interface(std::vector<std::string>& cmds, double y_line_A, const Params& p) {
  std::ostringstream s;
  s.precision(12);
  s << "region escm_upper block INF INF " << y_line_A << " INF INF INF units box";
  cmds.push_back(s.str());
  cmds.push_back("set region escm_upper type 2");
  s.str("");
  s << "pair_coeff 1 2 " << p.crack_f * p.eps << ' ' << p.sig;
  cmds.push_back(s.str());
}

/// One row of crack.csv and the quantities the summary needs (Cases II/III).
struct CrackRecord {
  double time = 0.0;
  TipResult tip;
  int increments = 0;
  AtomisticCrack md;
};

std::string crack_csv_header() {
  return "time_s,tip_x_m,crack_length_m,increments,J_J_per_m2,GI_J_per_m2,GII_J_per_m2,"
         "opening_m,sliding_m,md_bonds,md_broken_bonds,md_separated_columns,md_crack_length_m,"
         "md_entry_opening_m,md_entry_sliding_m,md_max_opening_m,md_max_abs_sliding_m,"
         "md_slipped_columns\n";
}

std::string crack_csv_row(const CrackRecord& c) {
  std::ostringstream o;
  o.precision(10);
  const double A = units::m_per_A;
  o << c.time << ',' << c.tip.tip[0] << ',' << c.tip.length << ',' << c.increments << ',' << c.tip.J
    << ',' << c.tip.GI << ',' << c.tip.GII << ',' << c.tip.opening << ',' << c.tip.sliding << ','
    << c.md.bonds << ',' << c.md.broken << ',' << c.md.separated_columns << ',' << c.md.length_A * A
    << ',' << c.md.entry_opening_A * A << ',' << c.md.entry_sliding_A * A << ','
    << c.md.max_opening_A * A << ',' << c.md.max_abs_sliding_A * A << ',' << c.md.slipped_columns
    << '\n';
  return o.str();
}

json crack_json(const CrackRecord& c) {
  const double A = units::m_per_A;
  return {{"time_s", c.time},
          {"tip_x_m", c.tip.tip[0]},
          {"crack_length_m", c.tip.length},
          {"increments", c.increments},
          {"J_J_per_m2", c.tip.J},
          {"GI_J_per_m2", c.tip.GI},
          {"GII_J_per_m2", c.tip.GII},
          {"opening_m", c.tip.opening},
          {"sliding_m", c.tip.sliding},
          {"md_bonds", c.md.bonds},
          {"md_broken_bonds", c.md.broken},
          {"md_separated_columns", c.md.separated_columns},
          {"md_columns", c.md.columns},
          {"md_crack_length_m", c.md.length_A * A},
          {"md_entry_opening_m", c.md.entry_opening_A * A},
          {"md_entry_sliding_m", c.md.entry_sliding_A * A},
          {"md_max_opening_m", c.md.max_opening_A * A},
          {"md_max_abs_sliding_m", c.md.max_abs_sliding_A * A},
          {"md_slipped_columns", c.md.slipped_columns}};
}

/// The "crack" block of summary.json: the continuum tip at the end, when it reached the stop
/// before the block (D81), when the first bond across the line broke and when the first column
/// separated (D82), the last record and the per-frame records.
json crack_summary(const std::vector<CrackRecord>& log, const json& frames, const Params& p,
                   double h, int max_increments) {
  const int bx0 = (p.ncx - p.nbx) / 2;
  json cj;
  cj["initial_tip_x_m"] = (p.crack_cells + 0.5) * h;
  cj["stop_tip_x_m"] = (bx0 - 0.5) * h;
  cj["block_x_m"] = bx0 * h;
  cj["max_increments"] = max_increments;
  cj["evaluations"] = log.size();
  json none; // null when it did not happen
  cj["time_tip_reached_stop_s"] = none;
  cj["time_first_broken_bond_s"] = none;
  cj["time_first_separated_column_s"] = none;
  cj["time_first_slipped_column_s"] = none;
  for (const CrackRecord& c : log) {
    if (cj["time_tip_reached_stop_s"].is_null() && c.increments >= max_increments)
      cj["time_tip_reached_stop_s"] = c.time;
    if (cj["time_first_broken_bond_s"].is_null() && c.md.broken > 0)
      cj["time_first_broken_bond_s"] = c.time;
    if (cj["time_first_separated_column_s"].is_null() && c.md.separated_columns > 0)
      cj["time_first_separated_column_s"] = c.time;
    if (cj["time_first_slipped_column_s"].is_null() && c.md.slipped_columns > 0)
      cj["time_first_slipped_column_s"] = c.time;
  }
  if (!log.empty()) cj["last"] = crack_json(log.back());
  cj["frames"] = frames;
  return cj;
}

// ---- Checkpoint and resume (docs/escm.md "Checkpoint and resume") ----

/// A stop request (CoupleOptions::stop) ends the run after coupled step `done` when that step
/// is on the checkpoint schedule (every `every` steps): its checkpoint is one the uninterrupted
/// run writes too, so the resumed run is bit for bit that run (the Langevin fixes are re-created
/// at every checkpoint, docs/escm.md). A second request, or no schedule, stops at once.
bool stop_now(const pnc::StopToken* stop, long done, long every, bool progress) {
  if (stop == nullptr || !stop->requested()) return false;
  if (every <= 0 || done % every == 0 || stop->count() >= 2) return true;
  static const pnc::StopToken* told = nullptr;
  if (progress && told != stop) {
    told = stop;
    std::fprintf(stderr,
                 "pnc gimp couple: stop requested: stopping at the next checkpoint (step %ld); "
                 "signal again to stop now (the resumed run then equals this one to round-off, "
                 "not bit for bit)\n",
                 (done / every + 1) * every);
  }
  return false;
}

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// --resume: the input must be the one the run was started with (stored in the checkpoint),
/// except `checkpoint_every_ps` and `comment` (top level and in "short"). The error names the
/// input file and the first key that differs.
void check_same_input(const std::string& src, const std::string& stored, const std::string& now,
                      const std::string& ckpt) {
  auto clean = [](json j) {
    if (!j.is_object()) return j;
    j.erase("comment");
    j.erase("checkpoint_every_ps");
    if (j.contains("short") && j["short"].is_object()) {
      j["short"].erase("comment");
      j["short"].erase("checkpoint_every_ps");
    }
    return j;
  };
  json a, b;
  try {
    a = clean(parse_json(stored, ckpt));
  } catch (const std::exception&) {
    fail(ckpt, "/run/input", "", "the stored input is not valid JSON");
  }
  b = clean(parse_json(now, src));
  if (a == b) return;
  auto text = [](const json& o, const std::string& k) {
    return o.is_object() && o.contains(k) ? o.at(k).dump() : std::string("<absent>");
  };
  std::string key, was, is;
  std::set<std::string> keys;
  for (const json* o : {&a, &b})
    if (o->is_object())
      for (auto it = o->begin(); it != o->end(); ++it)
        keys.insert(it.key());
  for (const std::string& k : keys) {
    if (text(a, k) == text(b, k)) continue;
    key = k;
    was = text(a, k);
    is = text(b, k);
    if (a.contains(k) && b.contains(k) && a[k].is_object() && b[k].is_object()) {
      std::set<std::string> sub;
      for (const json* o : {&a[k], &b[k]})
        for (auto it = o->begin(); it != o->end(); ++it)
          sub.insert(it.key());
      for (const std::string& q : sub)
        if (text(a[k], q) != text(b[k], q)) {
          key = k + "." + q;
          was = text(a[k], q);
          is = text(b[k], q);
          break;
        }
    }
    break;
  }
  fail(src, key, clip(is),
       "differs from the input this run was started with (" + clip(was) + ", stored in " + ckpt +
           "): --resume continues a run only with the same input (checkpoint_every_ps and "
           "comment may change); restore the value or start a new run in another --out directory");
}

constexpr int kCrackCols = 24;

std::vector<double> crack_row(const CrackRecord& c) {
  return {c.time,
          c.tip.tip[0],
          c.tip.tip[1],
          c.tip.e1[0],
          c.tip.e1[1],
          c.tip.J,
          c.tip.GI,
          c.tip.GII,
          c.tip.opening,
          c.tip.sliding,
          c.tip.length,
          static_cast<double>(c.tip.particles),
          static_cast<double>(c.tip.crack),
          static_cast<double>(c.tip.end),
          static_cast<double>(c.increments),
          static_cast<double>(c.md.bonds),
          static_cast<double>(c.md.broken),
          static_cast<double>(c.md.columns),
          static_cast<double>(c.md.separated_columns),
          c.md.length_A,
          c.md.entry_opening_A,
          c.md.entry_sliding_A,
          c.md.max_opening_A,
          c.md.max_abs_sliding_A};
}

CrackRecord crack_record(const double* d) {
  CrackRecord c;
  c.time = d[0];
  c.tip.tip = Eigen::Vector2d(d[1], d[2]);
  c.tip.e1 = Eigen::Vector2d(d[3], d[4]);
  c.tip.J = d[5];
  c.tip.GI = d[6];
  c.tip.GII = d[7];
  c.tip.opening = d[8];
  c.tip.sliding = d[9];
  c.tip.length = d[10];
  c.tip.particles = static_cast<int>(d[11]);
  c.tip.crack = static_cast<std::size_t>(d[12]);
  c.tip.end = static_cast<int>(d[13]);
  c.increments = static_cast<int>(d[14]);
  c.md.bonds = static_cast<int>(d[15]);
  c.md.broken = static_cast<int>(d[16]);
  c.md.columns = static_cast<int>(d[17]);
  c.md.separated_columns = static_cast<int>(d[18]);
  c.md.length_A = d[19];
  c.md.entry_opening_A = d[20];
  c.md.entry_sliding_A = d[21];
  c.md.max_opening_A = d[22];
  c.md.max_abs_sliding_A = d[23];
  return c;
}

std::string join_lines(const std::vector<std::string>& v) {
  std::string o;
  for (const auto& x : v)
    o += x + "\n";
  return o;
}

std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> v;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);)
    if (!l.empty()) v.push_back(l);
  return v;
}

} // namespace

CoupleSummary run_couple(const CoupleOptions& o) {
  const std::string& src = o.input;
  const Params p = read_params(o);
  // Checkpoint and resume: a directory that holds a run needs --resume, and --resume needs the
  // input the run was started with (docs/escm.md "Checkpoint and resume").
  const std::string ckpt_file = checkpoint_path(o.out_dir);
  const std::string input_text = read_text(src);
  std::unique_ptr<CoupledCheckpoint> resume_from;
  if (o.resume && std::filesystem::exists(ckpt_file)) {
    resume_from = std::make_unique<CoupledCheckpoint>(read_coupled_checkpoint(o.out_dir));
    if (resume_from->short_mode != o.short_mode)
      fail(src, "--short", o.short_mode ? "given" : "not given",
           "the run in " + o.out_dir + " was started " +
               (resume_from->short_mode ? "with" : "without") + " --short (" + ckpt_file +
               "): --resume must repeat it");
    check_same_input(src, resume_from->input_text, input_text, ckpt_file);
  } else if (o.resume) {
    if (o.progress)
      std::fprintf(stderr, "pnc gimp couple: --resume: no checkpoint in %s, starting at t = 0\n",
                   o.out_dir.c_str());
  }
  refuse_existing_run(o.out_dir, o.resume, {"checkpoint.h5", "summary.json"});
  // The MD region's continuum calibration: the LJ crystal's lattice sums (D76) or the measured
  // (or given) constants of the built polymer block (D101, D102), in the same struct (a0 = the
  // cell size h; lambda = C12, mu = (C11 - C12) / 2).
  const bool polymer = p.md_type == "polymer";
  LjFcc lj;
  double rc_A = p.rc;
  json poly_json;
#ifdef PNC_ESCM_HAS_POLYMER
  PolymerBlock poly;
  double poly_sigma_A = 0.0; // the polymer's LJ sigma (D114)
  if (polymer) {
    PolymerBlockSpec ps;
    ps.nbx = p.nbx;
    ps.nby = p.nby;
    ps.svc_rings = p.svc;
    ps.ivc_rings = p.ivc;
    ps.neumann = p.mode == "neumann";
    ps.cell_A = p.cell_A;
    ps.slab_A = p.slab_A;
    ps.density = p.density;
    ps.beads_per_chain = p.beads_per_chain;
    ps.seed = static_cast<std::uint64_t>(p.md_seed);
    ps.temperature = p.poly_T;
    ps.anneal_ps = p.anneal_ps;
    ps.min_beads_per_cell = p.min_beads;
    ps.strain_probe = p.strain_probe;
    ps.measure_elastic = !p.elastic_given;
    if (p.crack) { // D114: the crack line through the block's middle cell row
      ps.interface_row = p.nby / 2;
      ps.interface_fraction = p.crack_f;
    }
    if (p.ff_sigma > 0) ps.ff.sigma = p.ff_sigma;
    if (p.ff_epsilon > 0) ps.ff.epsilon = p.ff_epsilon;
    if (p.ff_cutoff_sigma > 0) ps.ff.cutoff_sigma = p.ff_cutoff_sigma;
    rc_A = ps.ff.cutoff();
    poly_sigma_A = ps.ff.sigma;
    pnc::make_output_directory(o.out_dir);
    if (o.progress)
      std::fprintf(stderr, "pnc gimp couple: building the polymer block (%d x %d cells)\n", p.nbx,
                   p.nby);
    poly = build_polymer_block(ps, o.out_dir, src);
    lj.a0_A = poly.h_A;
    lj.density = poly.density_kg_m3;
    const double lam = p.elastic_given ? p.elastic_lambda : poly.lambda;
    const double mu = p.elastic_given ? p.elastic_mu : poly.mu;
    if (!(mu > 0 && lam + mu > 0))
      throw std::runtime_error("escm polymer: the measured elastic constants are not positive "
                               "definite (lambda " +
                               std::to_string(lam) + " Pa, mu " + std::to_string(mu) +
                               " Pa): give md.elastic");
    lj.C11 = lam + 2 * mu;
    lj.C12 = lam;
    lj.C44 = mu;
    poly_json = {
        {"data_file", poly.data_file},
        {"cell_size_A", poly.h_A},
        {"slab_A", poly.Lz_A},
        {"density_kg_m3", poly.density_kg_m3},
        {"build_density_g_cm3", poly.build_density},
        {"atoms", poly.atoms},
        {"chains", poly.chains},
        {"beads_per_chain", poly.beads_per_chain},
        {"elastic_source", p.elastic_given ? "given" : "measured"},
        {"lambda_Pa", lam},
        {"mu_Pa", mu},
        {"E_Pa", lj.E()},
        {"nu", lj.nu()},
        {"measured_C_Pa",
         {{"C11", poly.C11},
          {"C22", poly.C22},
          {"C33", poly.C33},
          {"C12", poly.C12},
          {"C21", poly.C21},
          {"C31", poly.C31},
          {"C32", poly.C32}}},
        {"measured_lambda_Pa", poly.lambda},
        {"measured_mu_Pa", poly.mu},
        {"strain_probe", p.strain_probe},
        {"relaxed_pressure_atm",
         {{"p", poly.pressure_atm},
          {"pxx", poly.pxx_atm},
          {"pyy", poly.pyy_atm},
          {"pzz", poly.pzz_atm}}},
        {"cut_periodic",
         {poly.cut_periodic_bonds, poly.cut_periodic_angles, poly.cut_periodic_dihedrals}},
        {"cut_svc_free", {poly.cut_svc_bonds, poly.cut_svc_angles, poly.cut_svc_dihedrals}},
        {"cut_interface",
         {poly.cut_interface_bonds, poly.cut_interface_angles, poly.cut_interface_dihedrals}},
        {"interface_y_A", poly.interface_y_A},
        {"atoms_changed_zone", poly.moved_zone},
        {"surface_minimisation",
         {{"passes", poly.surface_passes},
          {"atoms_changed_zone_last_pass", poly.moved_zone_last},
          {"fmax_kcal_mol_A", poly.surface_fmax},
          {"fnorm_kcal_mol_A", poly.surface_fnorm}}},
        {"volume_cell_beads",
         {{"min", poly.min_cell_beads},
          {"mean", poly.mean_cell_beads},
          {"max", poly.max_cell_beads}}},
        {"wall_s",
         {{"relax", poly.relax_s}, {"surface", poly.surface_s}, {"total", poly.total_s}}}};
  }
#endif
  if (!polymer) lj = lj_fcc(p.eps, p.sig, p.rc, p.mass);
  if (p.mode == "schwarz" && p.svc * lj.a0_A < rc_A)
    fail(src, "svc_rings", std::to_string(p.svc),
         "in schwarz mode the SVC rings must be at least as wide as the cut-off (D72)");
  const double h = lj.a0_A * units::m_per_A;
  const int bx0 = (p.ncx - p.nbx) / 2, by0 = (p.ncy - p.nby) / 2;
  // D83: the crack line is a weak interface in both models: LJ epsilon x f across it in the MD,
  // and by default the continuum's Gc is its work of separation, f W_sep.
  const double wsep = polymer ? 0.0 : lj_fcc_separation_work(lj, p.eps, p.sig, p.rc);
  const double Gc = p.crack_Gc > 0 ? p.crack_Gc : p.crack_f * wsep;
  Solver<2> s;
  const Loading ld = set_up_continuum(p, lj, Gc, s);
  const double omega1 = M_PI * ld.speed / ld.length;
  const double damping = 2 * p.damping_fraction * omega1; // D75
  Config c;
  if (!polymer)
    c.md_setup =
        lj_fcc_block_commands(lj, p.nbx, p.nby, p.nz, p.mass, p.eps, p.sig, p.rc, p.crack ? 2 : 1);
#ifdef PNC_ESCM_HAS_POLYMER
  if (polymer) c.md_setup = poly.md_setup;
#endif
  // (the polymer block carries its interface in its data file and md_setup, D114)
  if (p.crack && !polymer) append_weak_interface(c.md_setup, (p.nby / 2 - 0.25) * lj.a0_A, p);
  // D93: the LJ energy shifted to zero at the cut-off (forces unchanged): otherwise every pair
  // crossing r_c changes the logged MD potential by -V(r_c) = 0.0163 epsilon with no work done
  // (the fifth FCC shell lies 2 % inside 2.5 sigma), and the energy log does not close.
  c.md_setup.push_back("pair_modify shift yes");
  // LJ: the FCC block starts a0/4 inside its first cell; polymer: the block's atoms lie in
  // [0, nb h) of the LAMMPS frame (D101).
  c.md_offset = polymer ? Eigen::Vector2d(bx0 * h, by0 * h)
                        : Eigen::Vector2d(bx0 * h + 0.25 * h, by0 * h + 0.25 * h);
  c.svc_rings = p.svc;
  c.ivc_rings = p.ivc;
  c.substeps = p.substeps;
  c.dt = p.substeps * p.dtau_fs * units::s_per_fs;
  c.mode = p.mode == "schwarz" ? Mode::schwarz : Mode::neumann;
  c.interior_temperature = p.temperature;
  c.interior_damp_fs = damping > 0 ? 1.0 / damping / units::s_per_fs : 0.0;
  c.ivc_damp_fs = damping > 0 ? c.interior_damp_fs : 1000.0;
  if (p.temperature > 0 && c.interior_damp_fs <= 0) c.interior_damp_fs = 1000.0;
  c.continuum_damping = damping;
  const double cfl_dt = 0.5 * h / std::sqrt(lj.C11 / lj.density);
  if (c.dt > cfl_dt)
    fail(src, "substeps", std::to_string(p.substeps),
         "substeps x md_timestep_fs exceeds the continuum CFL step " +
             std::to_string(cfl_dt / units::s_per_fs) + " fs");
  pnc::make_output_directory(o.out_dir);
  const std::string out = o.out_dir;
  c.lammps_log = out + "/lammps.log";
  Coupler cp(s, c);
  cp.setup();

  // Displacement gradients of eqs. 6.3-6.7 (D79): all continuum particles and all atoms
  // (projected on x, y) on a bilinear grid aligned with the continuum grid, updated at every
  // coupled step. IVC probes receive gradients but do not enter the nodal fit (their position
  // is a block-averaged copy of their atoms, D73).
  const std::size_t ncont = s.particles.size();
  std::vector<int> pzone(ncont, static_cast<int>(Zone::none));
  for (const Cell& cell : cp.cells())
    pzone[cell.particle] = static_cast<int>(cell.zone);
  GradientTracker grad(s.grid.origin, p.gradient_cells * h);
  std::vector<Eigen::Vector2d> gx;
  std::vector<int> gids;
  std::vector<Eigen::Vector3d> gax, gav;
  auto gather = [&] {
    cp.atoms(gids, gax, gav);
    gx.resize(ncont + gax.size());
    for (std::size_t k = 0; k < ncont; ++k)
      gx[k] = s.particles.x[k];
    for (std::size_t k = 0; k < gax.size(); ++k)
      gx[ncont + k] = cp.to_continuum(gax[k]);
  };
  gather();
  {
    std::vector<char> contributes(gx.size(), 1);
    for (std::size_t k = 0; k < ncont; ++k)
      contributes[k] = pzone[k] != static_cast<int>(Zone::ivc);
    grad.reset(gx, contributes);
  }
  double grad_wall = 0.0;
  // The four components and the support flag of particles [b, e) as VTU point arrays.
  auto grad_arrays = [&](std::size_t b, std::size_t e) {
    std::vector<PointArray> a = {{"du_dX", 1, {}},
                                 {"du_dY", 1, {}},
                                 {"dv_dX", 1, {}},
                                 {"dv_dY", 1, {}},
                                 {"gradient_supported", 1, {}}};
    for (std::size_t k = b; k < e; ++k) {
      const Eigen::Matrix2d H = grad.H(k);
      a[0].values.push_back(H(0, 0));
      a[1].values.push_back(H(0, 1));
      a[2].values.push_back(H(1, 0));
      a[3].values.push_back(H(1, 1));
      a[4].values.push_back(grad.supported()[k]);
    }
    return a;
  };

  // Cases II/III: the continuum crack tip (D38-D40, stopped by D81) and the atomistic crack
  // across the same line (D82), in the LAMMPS frame: the line lies a0/4 below the atom row of
  // the block's middle cell row; the free region starts svc_rings cells into the block.
  // Polymer (D114): the line at the middle row's lower edge, the block from 0; the monitored
  // pairs are the non-bonded ones across it at or inside the LJ minimum 2^(1/6) sigma at the
  // start (an amorphous block has pairs at every distance: only these are bonds), broken past
  // the LJ inflection (26/7)^(1/6) sigma, as for the crystal.
  std::unique_ptr<BondMonitor> bonds;
  if (p.crack && !polymer)
    bonds =
        std::make_unique<BondMonitor>(cp, (p.nby / 2 - 0.25) * lj.a0_A, (p.svc - 0.25) * lj.a0_A,
                                      lj.a0_A, 0.85 * lj.a0_A, lj_inflection(p.sig),
                                      0.5 * lj.a0_A); // D91: slip past a0/2
#ifdef PNC_ESCM_HAS_POLYMER
  if (p.crack && polymer)
    bonds = std::make_unique<BondMonitor>(cp, poly.interface_y_A, p.svc * lj.a0_A, lj.a0_A,
                                          std::pow(2.0, 1.0 / 6.0) * poly_sigma_A,
                                          lj_inflection(poly_sigma_A), 0.5 * lj.a0_A);
#endif
  const int max_increments = p.crack ? s.cracks[0].growth.max_increments : 0;
  std::vector<CrackRecord> crack_log;
  std::ostringstream crack_csv;
  crack_csv << crack_csv_header();
  auto evaluate_crack = [&] {
    CrackRecord rec;
    rec.time = s.time;
    const auto tips = crack_tips(s);
    if (!tips.empty()) rec.tip = tips.front();
    grow_cracks(s, tips);
    rec.increments = s.cracks[0].increments;
    rec.md = bonds->measure(gax);
    crack_csv << crack_csv_row(rec);
    crack_log.push_back(rec);
  };
  json frame_log = json::array();

  const double ps = 1e-12;
  const double t_settle = p.settle_ps * ps, t_load = p.load_ps * ps;
  const double t_end = t_settle + t_load + p.hold_ps * ps;
  const long nsteps = std::max(1L, std::lround(t_end / c.dt));
  const long frame_every = p.frames > 0 ? std::max(1L, nsteps / p.frames) : nsteps + 1;
  CoupleSummary r;
  // Profile along the block's middle cell row (the row just above the crack line in Cases
  // II/III): the displacement along the load and its gradient across the crack line.
  const int ucomp = p.load == "tension_y" ? 1 : 0;
  const int gcol = p.load == "tension_x" ? 0 : 1;
  const std::string uname = ucomp ? "uy_m" : "ux_m";
  const std::string gname = std::string(ucomp ? "duy" : "dux") + (gcol ? "_dY" : "_dX");
  std::ostringstream prof;
  prof.precision(10);
  prof << "time_s,x_m," << uname << ",source," << gname << '\n';
  const int jmid = by0 + p.nby / 2;
  auto profile = [&] {
    for (std::size_t k = 0; k < s.particles.size(); ++k) {
      const auto& x0 = s.particles.x0[k];
      if (static_cast<int>(std::floor(x0[1] / h)) != jmid) continue;
      prof << s.time << ',' << x0[0] << ',' << s.particles.x[k][ucomp] - x0[ucomp] << ",continuum,"
           << grad.H(k)(ucomp, gcol) << '\n';
    }
    std::map<int, std::array<double, 4>> acc; // cell i -> (x0 sum, u sum, n, gradient sum)
    for (std::size_t k = 0; k < gax.size(); ++k) {
      const Eigen::Vector2d x0 = cp.to_continuum(cp.atoms_initial()[k]);
      if (static_cast<int>(std::floor(x0[1] / h)) != jmid) continue;
      auto& a = acc[static_cast<int>(std::floor(x0[0] / h))];
      a[0] += x0[0];
      a[1] += (cp.to_continuum(gax[k]) - x0)[ucomp];
      a[2] += 1;
      a[3] += grad.H(ncont + k)(ucomp, gcol);
    }
    for (const auto& [i, a] : acc)
      prof << s.time << ',' << a[0] / a[2] << ',' << a[1] / a[2] << ",md," << a[3] / a[2] << '\n';
  };
  // Checkpoints every checkpoint_every_ps of simulated time, at the end and when stopped
  // (SIGINT/SIGTERM after the current coupled step, or stop_after_steps).
  const long ckpt_every =
      p.checkpoint_ps > 0 ? std::max(1L, std::lround(p.checkpoint_ps * ps / c.dt)) : 0;
  long k0 = 0;
  double wall_before = 0.0;
  r.checkpoint = ckpt_file;
  if (resume_from) {
    const CoupledCheckpoint& ck = *resume_from;
    if (ck.nsteps != nsteps)
      fail(ckpt_file, "/run/nsteps", std::to_string(ck.nsteps),
           "the input gives " + std::to_string(nsteps) + " coupled steps");
    restore_continuum(o.out_dir, ck, s);
    cp.restore(ck.coupler);
    gather();
    auto table = [&](const std::string& name, Eigen::Index rows, Eigen::Index cols) {
      const auto it = ck.tables.find(name);
      if (it == ck.tables.end()) {
        if (rows <= 0) return CheckpointTable(0, cols); // e.g. no crack records yet
        fail(ckpt_file, "/run/table/" + name, "<missing>", "needed to resume");
      }
      if ((rows >= 0 && it->second.rows() != rows) || it->second.cols() != cols)
        fail(ckpt_file, "/run/table/" + name,
             std::to_string(it->second.rows()) + " x " + std::to_string(it->second.cols()),
             "does not fit this set-up");
      return it->second;
    };
    auto text = [&](const std::string& name) {
      const auto it = ck.texts.find(name);
      return it == ck.texts.end() ? std::string() : it->second;
    };
    const auto gn = static_cast<Eigen::Index>(gx.size());
    const CheckpointTable gF = table("gradient_F", gn, 4), gs = table("gradient_supported", gn, 1),
                          gsc = table("gradient", 1, 2);
    std::vector<Eigen::Matrix2d> F(gx.size());
    std::vector<char> sup(gx.size());
    for (Eigen::Index i = 0; i < gn; ++i) {
      F[static_cast<std::size_t>(i)] << gF(i, 0), gF(i, 1), gF(i, 2), gF(i, 3);
      sup[static_cast<std::size_t>(i)] = static_cast<char>(gs(i, 0));
    }
    grad.restore(gx, F, sup, static_cast<long>(gsc(0, 0)));
    grad_wall = gsc(0, 1);
    const CheckpointTable bcr = table("bc_reaction", static_cast<Eigen::Index>(s.bcs.size()), 2);
    for (std::size_t b = 0; b < s.bcs.size(); ++b)
      s.bcs[b].reaction = bcr.row(static_cast<Eigen::Index>(b)).transpose();
    const CheckpointTable cl = table("crack_log", -1, kCrackCols);
    crack_log.clear();
    for (Eigen::Index i = 0; i < cl.rows(); ++i)
      crack_log.push_back(crack_record(cl.row(i).data()));
    if (ck.texts.count("crack_csv")) {
      crack_csv.str("");
      crack_csv << text("crack_csv");
    }
    prof.str("");
    prof << text("profile_csv");
    frame_log = ck.texts.count("frame_log") ? json::parse(text("frame_log")) : json::array();
    r.frames = split_lines(text("frames"));
    r.particle_frames = split_lines(text("particle_frames"));
    k0 = ck.step;
    wall_before = ck.wall_s;
    r.resumed = true;
    r.start_step = k0;
    if (o.progress)
      std::fprintf(stderr, "pnc gimp couple: resumed from %s at step %ld/%ld (t = %.2f ps)\n",
                   ckpt_file.c_str(), k0, nsteps, s.time / ps);
  }
  auto write_ckpt = [&](long done, double wall) {
    const auto t0 = std::chrono::steady_clock::now();
    CoupledCheckpoint ck;
    ck.coupler = cp.checkpoint();
    ck.input_path = src;
    ck.input_text = input_text;
    ck.short_mode = o.short_mode;
    ck.step = done;
    ck.nsteps = nsteps;
    ck.time_s = s.time;
    ck.wall_s = wall;
    ck.texts = {{"profile_csv", prof.str()},
                {"crack_csv", p.crack ? crack_csv.str() : std::string()},
                {"frame_log", frame_log.dump()},
                {"frames", join_lines(r.frames)},
                {"particle_frames", join_lines(r.particle_frames)}};
    const auto gn = static_cast<Eigen::Index>(grad.size());
    CheckpointTable gF(gn, 4), gs(gn, 1), gsc(1, 2),
        bcr(static_cast<Eigen::Index>(s.bcs.size()), 2),
        cl(static_cast<Eigen::Index>(crack_log.size()), kCrackCols);
    for (Eigen::Index i = 0; i < gn; ++i) {
      const Eigen::Matrix2d& F = grad.F()[static_cast<std::size_t>(i)];
      gF.row(i) << F(0, 0), F(0, 1), F(1, 0), F(1, 1);
      gs(i, 0) = grad.supported()[static_cast<std::size_t>(i)];
    }
    gsc << static_cast<double>(grad.increments()), grad_wall;
    for (std::size_t b = 0; b < s.bcs.size(); ++b)
      bcr.row(static_cast<Eigen::Index>(b)) = s.bcs[b].reaction.transpose();
    for (std::size_t i = 0; i < crack_log.size(); ++i) {
      const auto row = crack_row(crack_log[i]);
      for (int j = 0; j < kCrackCols; ++j)
        cl(static_cast<Eigen::Index>(i), j) = row[static_cast<std::size_t>(j)];
    }
    ck.tables = {{"gradient_F", gF},
                 {"gradient_supported", gs},
                 {"gradient", gsc},
                 {"bc_reaction", bcr},
                 {"crack_log", cl}};
    r.checkpoint_bytes = write_coupled_checkpoint(o.out_dir, s, ck);
    ++r.checkpoints;
    r.checkpoint_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  // Polymer (D107): the left reaction at the end of the settle phase, before any load; a block
  // that is not in equilibrium when the coupling starts shows up here (not kept over a resume).
  double reaction_settle = std::numeric_limits<double>::quiet_NaN();
  const auto w0 = std::chrono::steady_clock::now();
  auto last = w0;
  for (long k = k0; k < nsteps; ++k) {
    const double tl = s.time + 0.5 * c.dt - t_settle;
    s.bcs[ld.bc].velocity[ld.comp] =
        (tl > 0 && tl < t_load)
            ? p.strain * ld.length / t_load * (1 - std::cos(2 * M_PI * tl / t_load))
            : 0.0;
    cp.step();
    if (polymer && std::isnan(reaction_settle) && s.time >= t_settle - 0.5 * c.dt)
      reaction_settle = s.bcs[0].reaction[ld.comp];
    {
      const auto g0 = std::chrono::steady_clock::now();
      gather();
      grad.update(gx);
      grad_wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - g0).count();
    }
    if (p.crack && (k + 1) % p.crack_every == 0) evaluate_crack();
    if ((k + 1) % frame_every == 0) {
      const std::string idx = std::to_string((k + 1) / frame_every);
      const std::string f = out + "/atoms_" + idx + ".vtu";
      cp.write_atoms_vtu(f, grad_arrays(ncont, gx.size()));
      r.frames.push_back(f);
      const std::string fp = out + "/particles_" + idx + ".vtu";
      write_particles_vtu(fp, s, pzone, grad_arrays(0, ncont));
      r.particle_frames.push_back(fp);
      profile();
      if (p.crack) {
        CrackRecord rec = crack_log.empty() ? CrackRecord{} : crack_log.back();
        rec.time = s.time;
        rec.md = bonds->measure(gax);
        frame_log.push_back(crack_json(rec));
        if (o.progress)
          std::fprintf(stderr,
                       "frame %s  t = %.2f ps  continuum tip x = %.2f A (%d/%d increments)  MD: "
                       "%d/%d bonds broken, separated %.1f A, %d columns slipped\n",
                       idx.c_str(), s.time / ps, rec.tip.tip[0] / units::m_per_A, rec.increments,
                       max_increments, rec.md.broken, rec.md.bonds, rec.md.length_A,
                       rec.md.slipped_columns);
      }
    }
    const auto now = std::chrono::steady_clock::now();
    if (o.progress && (std::chrono::duration<double>(now - last).count() > 2 || k + 1 == nsteps)) {
      last = now;
      const double el = std::chrono::duration<double>(now - w0).count();
      std::fprintf(stderr, "step %ld/%ld  t = %.2f ps  elapsed %.1f s  ETA %.1f s\n", k + 1, nsteps,
                   s.time / ps, el,
                   el / static_cast<double>(k + 1 - k0) * static_cast<double>(nsteps - k - 1));
    }
    const long done = k + 1;
    const bool stop = stop_now(o.stop, done, ckpt_every, o.progress);
    if (done < nsteps && (stop || (o.stop_after_steps > 0 && done >= o.stop_after_steps))) {
      write_ckpt(done,
                 wall_before +
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
      r.signal = stop ? o.stop->signal() : 0;
      r.interrupted = stop ? "signal " + std::to_string(r.signal) : "max_steps";
      break;
    }
    if (ckpt_every > 0 && done % ckpt_every == 0 && done < nsteps)
      write_ckpt(done,
                 wall_before +
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
  }
  r.wall_s =
      wall_before + std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  // The run's numbers and its CSVs, written whether it finished or stopped.
  auto finish_common = [&](long steps) {
    r.steps = steps;
    r.time_s = s.time;
    r.outside_share = cp.timing().outside_share();
    r.atoms = cp.zone_counts();
    r.particles = s.particles.size();
    r.energy = cp.energy_log().back();
    r.reaction_left = s.bcs[0].reaction[ld.comp];
    r.profile_csv = out + "/profile.csv";
    r.energy_csv = out + "/energy.csv";
    r.lammps_log = c.lammps_log;
    pnc::write_text_atomically(r.profile_csv, prof.str());
    cp.write_energy_csv(r.energy_csv);
    if (p.crack) {
      r.crack_csv = out + "/crack.csv";
      pnc::write_text_atomically(r.crack_csv, crack_csv.str());
    }
  };
  if (!r.interrupted.empty()) { // stopped with a checkpoint: the CSVs so far, no summary
    finish_common(s.steps);
    if (o.progress)
      std::fprintf(stderr,
                   "pnc gimp couple: stopped (%s) after step %ld/%ld (t = %.2f ps); checkpoint "
                   "%s: continue with --resume\n",
                   r.interrupted.c_str(), r.steps, nsteps, s.time / ps, ckpt_file.c_str());
    return r;
  }
  write_ckpt(nsteps, r.wall_s);
  finish_common(nsteps);
  r.strain_modulus_pa = lj.strip_modulus();
  r.summary_json = out + "/summary.json";
  json sj;
  sj["input"] = src;
  sj["short"] = o.short_mode;
  sj["load"] = p.load;
  sj["strain"] = p.strain;
  sj["steps"] = r.steps;
  sj["time_s"] = r.time_s;
  sj["wall_s"] = r.wall_s;
  sj["outside_lammps_share"] = r.outside_share;
  sj["atoms"] = {{"interior", r.atoms[0]}, {"ivc", r.atoms[1]}, {"svc", r.atoms[2]}};
  sj["particles"] = r.particles;
  sj["cell_size_m"] = h;
  sj["block_origin_m"] = {bx0 * h, by0 * h};
  sj["block_cells"] = {p.nbx, p.nby};
  sj["md_type"] = p.md_type;
  if (polymer) {
    sj["polymer"] = poly_json;
    if (!std::isnan(reaction_settle))
      sj["polymer"]["reaction_left_end_of_settle_N_per_m"] = reaction_settle;
  } else
    sj["lj_fcc"] = {{"a0_A", lj.a0_A},      {"C11_Pa", lj.C11}, {"C12_Pa", lj.C12},
                    {"C44_Pa", lj.C44},     {"E_Pa", lj.E()},   {"nu", lj.nu()},
                    {"density", lj.density}};
  sj["continuum"] = {{"lambda_Pa", lj.C12},
                     {"mu_Pa", 0.5 * (lj.C11 - lj.C12)},
                     {"E_Pa", lj.E()},
                     {"nu", lj.nu()},
                     {"density_kg_m3", lj.density},
                     {"strip_modulus_Pa", lj.strip_modulus()}};
  // The fixed edge's reaction along the load (N per m); for Case I the left edge (as before).
  sj["reaction_fixed_N_per_m"] = r.reaction_left;
  if (p.load == "tension_x") {
    sj["reaction_left_N_per_m"] = r.reaction_left;
    sj["expected_reaction_N_per_m"] = -lj.strip_modulus() * p.strain * p.ncy * h;
  }
  sj["gradient"] = {
      {"spacing_m", grad.spacing()}, {"increments", grad.increments()}, {"wall_s", grad_wall}};
  // Handshake continuity at the end (D106): for every IVC cell the mean displacement of its atoms,
  // the standard deviation of its atoms' displacements, and the displacement of the continuum
  // particle(s) of the SVC cell(s) just outside it (m).
  {
    gather();
    int imin = 1 << 30, imax = -(1 << 30), jmin = imin, jmax = imax;
    std::map<std::pair<int, int>, std::size_t> svc_particle;
    for (const Cell& cell : cp.cells()) {
      imin = std::min(imin, cell.ij[0]);
      imax = std::max(imax, cell.ij[0]);
      jmin = std::min(jmin, cell.ij[1]);
      jmax = std::max(jmax, cell.ij[1]);
      if (cell.zone == Zone::svc) svc_particle[{cell.ij[0], cell.ij[1]}] = cell.particle;
    }
    json hs = json::array();
    for (const Cell& cell : cp.cells()) {
      if (cell.zone != Zone::ivc) continue;
      const int i = cell.ij[0], j = cell.ij[1];
      Eigen::Vector2d sum = Eigen::Vector2d::Zero(), sq = Eigen::Vector2d::Zero();
      for (int id : cell.atoms) {
        const auto k = static_cast<std::size_t>(id - 1);
        const Eigen::Vector2d u = cp.to_continuum(gax[k]) - cp.to_continuum(cp.atoms_initial()[k]);
        sum += u;
        sq += u.cwiseProduct(u);
      }
      const double n = static_cast<double>(cell.atoms.size());
      const Eigen::Vector2d mean = sum / n;
      const Eigen::Vector2d var = (sq / n - mean.cwiseProduct(mean)).cwiseMax(0.0);
      Eigen::Vector2d uc = Eigen::Vector2d::Zero();
      int nc = 0;
      const int rr = p.svc;
      for (const auto& q : std::vector<std::pair<int, int>>{{i - imin == rr ? i - 1 : i, j},
                                                            {imax - i == rr ? i + 1 : i, j},
                                                            {i, j - jmin == rr ? j - 1 : j},
                                                            {i, jmax - j == rr ? j + 1 : j}}) {
        const auto it = svc_particle.find(q);
        if (it == svc_particle.end()) continue;
        uc += s.particles.x[it->second] - s.particles.x0[it->second];
        ++nc;
      }
      if (nc == 0) continue;
      uc /= nc;
      hs.push_back({{"cell", {i, j}},
                    {"atoms", cell.atoms.size()},
                    {"u_ivc_m", {mean[0], mean[1]}},
                    {"sd_atoms_m", {std::sqrt(var[0]), std::sqrt(var[1])}},
                    {"u_svc_m", {uc[0], uc[1]}}});
    }
    sj["handshake"] = hs;
  }
  sj["particle_frames"] = r.particle_frames;
  sj["checkpoint"] = {{"file", r.checkpoint},        {"every_steps", ckpt_every},
                      {"written", r.checkpoints},    {"wall_s", r.checkpoint_s},
                      {"bytes", r.checkpoint_bytes}, {"resumed", r.resumed},
                      {"start_step", r.start_step}};
  if (p.crack) {
    sj["crack"] = crack_summary(crack_log, frame_log, p, h, max_increments);
    sj["crack"]["Gc_J_per_m2"] = Gc;
    sj["crack"]["interface_fraction"] = p.crack_f;
    sj["crack"]["separation_work_bulk_J_per_m2"] = wsep;
    sj["crack"]["separation_work_interface_J_per_m2"] = p.crack_f * wsep;
    sj["crack_csv"] = r.crack_csv;
  }
  const EnergyRow& e = r.energy;
  sj["energy_J"] = {{"cont_kinetic", e.cont_kinetic},
                    {"cont_strain", e.cont_strain},
                    {"md_kinetic", e.md_kinetic},
                    {"md_potential", e.md_potential},
                    {"work_boundary", e.work_boundary},
                    {"work_cont_on_md", e.work_cont_on_md},
                    {"work_md_on_cont", e.work_md_on_cont},
                    {"heat_removed_int", e.heat_removed_int},
                    {"heat_removed_ivc", e.heat_removed_ivc},
                    {"heat_removed_cont", e.heat_removed_cont},
                    {"balance", e.balance()}};
  pnc::write_text_atomically(r.summary_json, sj.dump(2) + "\n");
  if (o.plot) {
    // plot_escm.py from the installed (or build) tree, found relative to the executable (D151)
    const char* env_py = std::getenv("PNC_PYTHON");
    const std::string py = env_py && *env_py ? env_py : PNC_GIMP_PYTHON;
    const pnc::Located script =
        pnc::locate_shipped(pnc::ShippedDir::scripts, "plot_escm.py", "PNC_SCRIPTS_DIR");
    if (script.path.empty()) {
      r.plot_warning = "plots not written: plot_escm.py not found (" + script.looked_in() +
                       "; set PNC_SCRIPTS_DIR)";
    } else {
      // argument vector, no shell: the output directory is one argument whatever it contains
      const pnc::SubprocessResult pr = pnc::run_subprocess({py, script.path, out});
      pnc::write_text_atomically(out + "/plot.log", pr.started ? pr.output : pr.error + "\n");
      if (pr.ok()) {
        r.plots = {out + "/profile.png", out + "/energy.png"};
        if (p.crack) r.plots.push_back(out + "/crack.png");
      } else {
        r.plot_warning =
            "plots not written (needs " + py + " with matplotlib; see " + out + "/plot.log)";
      }
    }
  }
  return r;
}

} // namespace pnc::gimp::escm
