// The keys of the JSON input of `pnc gimp couple`, each declared once (pnc/core/parameters.hpp):
// name, type, default, range, unit and one line of text (D293-D296). read_couple_input
// (couple_input.cpp) reads through them; `pnc gimp couple-parameters` prints them, and the key
// tables of docs/escm.md "Every key" are generated from that printout. Units: LAMMPS real for
// the MD keys (kcal/mol, A, g/mol, fs, K), ps for the schedule, J/m^2 and Pa where the key says
// so; cell counts have none. The rules between keys (lj.cutoff in sigma, the block inside the
// continuum, the crack geometry, the MD region kind's rules) are checked by the reader after
// read().
#include "couple_input.hpp"
#include "md_region.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"

#include <memory>

namespace pnc::gimp::escm {

namespace {

using json = nlohmann::json;

const char* kind_meaning(const std::string& kind) {
  if (kind == "lj") return "the LJ FCC crystal of the lj section (D76)";
  if (kind == "polymer") return "a coarse-grained polymer block built by rve/ (D100-D106)";
  return "";
}

// Two integers bound to `a` and `b` (cells per axis).
Parameter& pair(Parameters& p, const std::string& key, int& a, int& b, std::int64_t lo,
                std::int64_t hi, std::string text) {
  Parameter e = detail::param_entry(key, ParamType::integer_list, json{a, b}, "", std::move(text));
  e.int_min = lo;
  e.int_max = hi;
  e.min_size = e.max_size = 2;
  e.store = [&a, &b](const json& v) {
    a = static_cast<int>(detail::param_integer(v[0]));
    b = static_cast<int>(detail::param_integer(v[1]));
  };
  e.load = [&a, &b] { return json{a, b}; };
  return p.add(std::move(e));
}

// md.elastic (D102): "measure", or the plane-strain constants as {E_Pa, nu} or {lambda_Pa,
// mu_Pa}; stored as lambda, mu.
void check_elastic(const json& v, const std::string& src, const std::string& field) {
  if (v.is_string() && v.get<std::string>() == "measure") return;
  const bool en = v.is_object() && v.size() == 2 && v.contains("E_Pa") && v.contains("nu");
  const bool lm = v.is_object() && v.size() == 2 && v.contains("lambda_Pa") && v.contains("mu_Pa");
  if (!(en || lm) || !v.begin()->is_number() || !(++v.begin())->is_number())
    fail(src, field, show_json(v),
         "\"measure\" or {\"E_Pa\", \"nu\"} or {\"lambda_Pa\", \"mu_Pa\"} (plane strain, Pa)");
  if (en) {
    const double E = v.at("E_Pa").get<double>(), nu = v.at("nu").get<double>();
    if (!(E > 0 && nu > -1 && nu < 0.5))
      fail(src, field, show_json(v), "E_Pa > 0 and nu in (-1, 0.5)");
  } else {
    const double lambda = v.at("lambda_Pa").get<double>(), mu = v.at("mu_Pa").get<double>();
    if (!(mu > 0 && lambda + mu > 0))
      fail(src, field, show_json(v), "mu_Pa > 0 and lambda_Pa + mu_Pa > 0");
  }
}

void store_elastic(const json& v, CoupleInput& in) {
  in.elastic_given = v.is_object();
  if (!in.elastic_given) return; // "measure"
  if (v.contains("E_Pa")) {
    const double E = v.at("E_Pa").get<double>(), nu = v.at("nu").get<double>();
    in.elastic_lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    in.elastic_mu = E / (2 * (1 + nu));
  } else {
    in.elastic_lambda = v.at("lambda_Pa").get<double>();
    in.elastic_mu = v.at("mu_Pa").get<double>();
  }
}

} // namespace

void declare_couple_input(Parameters& p, CoupleInput& in, bool top, bool& crack_given) {
  const auto any = [](const json&, const std::string&, const std::string&) {};
  p.custom("comment", "any", "any JSON value", "", "free text for the reader; ignored",
           "no comment", any);
  pair(p, "cells", in.ncx, in.ncy, 8, 2000, "continuum cells [nx, ny] of the specimen");
  pair(p, "block_cells", in.nbx, in.nby, 3, 200,
       "cells [nx, ny] of the atom block at the specimen's centre");
  p.integer("slab_cells", in.nz, 2, 50, "", "LJ: unit cells through the periodic slab");
  p.integer("svc_rings", in.svc, 1, 10, "", "cell rings of the surface coupling volume (SVC)");
  p.integer("ivc_rings", in.ivc, 1, 10, "", "cell rings of the interior coupling volume (IVC)");
  p.integer("substeps", in.substeps, 1, 10000, "", "MD steps per coupled continuum step");
  p.real("md_timestep_fs", in.dtau_fs, RealRange::closed(1e-4, 20), "fs", "MD time step");
  p.string("mode", in.mode,
           {{"neumann", "D71"}, {"schwarz", "D71; needs SVC rings >= the cut-off (D72)"}},
           "how the MD region is driven");
  p.real("interior_temperature", in.temperature, RealRange::closed(0, 5000), "K",
         "Langevin target temperature of the interior atoms (INT)");
  p.real("strain", in.strain, RealRange::closed(-0.1, 0.1), "1",
         "applied strain at the end of the load ramp (shear: engineering shear)");
  p.real("settle_ps", in.settle_ps, RealRange::closed(0, 1e5), "ps", "settling before the load");
  p.real("load_ps", in.load_ps, RealRange::closed(1e-3, 1e5), "ps", "duration of the load ramp");
  p.real("hold_ps", in.hold_ps, RealRange::closed(0, 1e5), "ps", "hold at the final strain");
  p.real("damping_fraction", in.damping_fraction, RealRange::closed(0, 10), "1",
         "continuum damping, of critical for the fundamental mode; 0: undamped");
  p.integer("frames", in.frames, 0, 1000, "", "atom and particle VTU / profile frames");
  p.real("gradient_spacing_cells", in.gradient_cells, RealRange::closed(0.5, 10), "1",
         "spacing of the gradient grid in continuum cell sizes (D79)");
  p.string("load", in.load,
           {{"tension_x", "Case I"},
            {"tension_y", "Case II: top pulled in y, bottom on rollers"},
            {"shear", "Case III: top moved in x, bottom fixed; strain = engineering shear"}},
           "the loading");
  p.real("checkpoint_every_ps", in.checkpoint_ps, RealRange::closed(0, 1e6), "ps",
         "simulated time between checkpoints (whole coupled steps, at least 1); 0: only at the "
         "end and when stopped; may change between sessions of a run");
  if (top)
    p.custom("short", "table", "a JSON object", "",
             "overrides applied with --short: any key of this table but lj and short, with the "
             "same rules (checked only with --short)",
             "no overrides", any);

  if (top) {
    p.optional_section("lj", in.lj_given, "the LJ crystal (md.type \"lj\"), real units");
    p.real("epsilon", in.eps, RealRange::above(0), "kcal/mol", "LJ well depth");
    p.real("sigma", in.sig, RealRange::above(0), "A", "LJ length");
    p.real("cutoff", in.rc, RealRange::above(0), "A", "pair cut-off")
        .no_default("2.5 sigma")
        .remark("in [1.2, 6] sigma");
    p.real("mass", in.mass, RealRange::above(0), "g/mol", "atom mass");
  }

  p.optional_section("crack", crack_given,
                     "the edge pre-crack of Cases II/III on the line through the block centre "
                     "(D80, D81, D83): given (even {}) it is on; false or absent: no crack");
  p.integer("length_cells", in.crack_cells, 1, 2000, "",
            "the initial tip lies in the middle of this cell column (from the left)");
  p.real("Gc", in.crack_Gc, RealRange::open(0, 1e3), "J/m^2",
         "growth criterion of the continuum crack")
      .no_default("interface_fraction x W_sep of the lattice (D83)");
  p.real("interface_fraction", in.crack_f, RealRange::open_closed(0, 1), "1",
         "LJ epsilon across the crack line / epsilon (weak interface, D83)");
  p.integer("every", in.crack_every, 1, 100000, "", "coupled steps between J evaluations");

  p.section("md", "the MD region (docs/escm.md \"Polymer MD region\")");
  std::vector<Choice> kinds;
  for (const auto& k : md_region_kinds())
    kinds.push_back({k, kind_meaning(k)});
  p.string("type", in.md_type, kinds, "the MD region kind (those registered in this build)");
  p.real("cell_A", in.cell_A, RealRange::closed(2, 100), "A",
         "polymer: continuum cell size at the build density");
  p.real("slab_A", in.slab_A, RealRange::closed(5, 200), "A",
         "polymer: slab thickness at the build density");
  p.real("density", in.density, RealRange::closed(0.05, 3), "g/cm^3", "polymer: build density")
      .no_default("the builder's default (rve/)");
  p.integer("beads_per_chain", in.beads_per_chain, 4, 10000, "", "polymer: chain length")
      .no_default("the builder's default (rve/)");
  p.integer("seed", in.md_seed, 1, 800000000, "", "polymer: seed of the build");
  p.real("temperature", in.poly_T, RealRange::closed(1, 2000), "K", "polymer: NPT anneal");
  p.real("anneal_ps", in.anneal_ps, RealRange::closed(0, 1e4), "ps",
         "polymer: duration of the anneal");
  p.integer("min_beads_per_cell", in.min_beads, 1, 10000, "",
            "polymer: fewest beads per continuum cell of the block (D105)");
  p.real("strain_probe", in.strain_probe, RealRange::closed(1e-5, 0.05), "1",
         "polymer: strain of the elastic-constant probe (D102)");
  Parameter& el =
      p.custom("elastic", "string or table",
               "\"measure\" or {\"E_Pa\", \"nu\"} or {\"lambda_Pa\", \"mu_Pa\"} (plane strain, Pa)",
               "Pa", "polymer: the continuum's elastic constants (D102)",
               "measure: probed on the block", check_elastic);
  el.store = [&in](const json& v) { store_elastic(v, in); };
  el.remark("E_Pa > 0 and nu in (-1, 0.5); mu_Pa > 0 and lambda_Pa + mu_Pa > 0");

  p.section("md.forcefield", "polymer: overrides of the rve/ force field, real units");
  p.real("sigma", in.ff_sigma, RealRange::above(0), "A", "bead LJ length")
      .no_default("the rve/ force field");
  p.real("epsilon", in.ff_epsilon, RealRange::above(0), "kcal/mol", "bead LJ well depth")
      .no_default("the rve/ force field");
  p.real("cutoff_sigma", in.ff_cutoff_sigma, RealRange::above(0), "1", "pair cut-off in sigma")
      .no_default("the rve/ force field");
}

Parameters couple_input_parameters() {
  struct Bound {
    CoupleInput in;
    bool crack_given = false;
  };
  Parameters p("pnc gimp couple input");
  auto b = std::make_shared<Bound>();
  p.hold(b);
  declare_couple_input(p, b->in, true, b->crack_given);
  return p;
}

} // namespace pnc::gimp::escm
