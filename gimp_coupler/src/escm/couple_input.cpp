// The JSON input of `pnc gimp couple` (couple_input.hpp, docs/escm.md "Input file").
#include "couple_input.hpp"

#include "md_region.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <fstream>
#include <set>
#include <sstream>

namespace pnc::gimp::escm {

namespace {

using json = nlohmann::json;

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
void apply_crack(const json& c, CoupleInput& p, const std::string& src, const std::string& key) {
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
void apply_md(const json& m, CoupleInput& p, const std::string& src, const std::string& key) {
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
      // the kinds registered in this build (md_region.hpp), e.g. "lj" or "polymer"
      if (!v.is_string() || !md_region_known(v.get<std::string>()))
        fail(src, key + ".type", show_json(v), md_region_kinds_text());
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

void apply(const json& j, CoupleInput& p, const std::string& src, const std::string& prefix) {
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

/// Cases II/III (D80, D81): the crack line runs along the cell boundary through the centre of
/// the block, between two atom rows, and the pre-crack ends before the block.
void check_crack(const CoupleInput& p, const std::string& src) {
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

} // namespace

CoupleInput read_couple_input(const std::string& src, bool short_mode) {
  const json j = parse_json(read_text_file(src), src);
  if (!j.is_object()) fail(src, "", "", "the input must be a JSON object");
  CoupleInput p;
  apply(j, p, src, "");
  if (short_mode && j.contains("short")) {
    if (!j.at("short").is_object())
      fail(src, "short", show_json(j.at("short")), "must be an object");
    apply(j.at("short"), p, src, "short.");
  }
  p.lj_given = j.contains("lj");
  const int rings = p.svc + p.ivc;
  if (p.nbx < 2 * rings + 1 || p.nby < 2 * rings + 1)
    fail(src, "block_cells", std::to_string(p.nbx) + " x " + std::to_string(p.nby),
         "must be at least 2 (svc_rings + ivc_rings) + 1 cells per axis");
  if (p.nbx + 4 > p.ncx || p.nby + 4 > p.ncy)
    fail(src, "cells", std::to_string(p.ncx) + " x " + std::to_string(p.ncy),
         "the continuum needs >= 2 cells around the atom block on each side");
  if (p.crack) check_crack(p, src);
  make_md_region(p.md_type, src)->check_input(p, src); // the region kind's own rules
  return p;
}

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

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

} // namespace pnc::gimp::escm
