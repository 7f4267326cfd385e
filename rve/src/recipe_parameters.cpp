// The keys of a `pnc characterize` recipe, each declared once (pnc/core/parameters.hpp): name,
// type, default (the value of the spec structs), range, unit and one line of text. parse_recipe
// reads through them; `pnc recipe parameters` prints them, and the key tables of docs/rve.md
// are generated from that printout (decisions D230-D232). Units: LAMMPS real (A, fs, kcal/mol,
// g/mol, atm, K).
#include "pnc/campaign/slurm_parameters.hpp"
#include "pnc/rve/recipe.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/damage/cases.hpp"

#include <limits>
#include <memory>
#include <stdexcept>

namespace pnc::rve {

namespace {

// LAMMPS runs at most 2^31 - 1 steps in one `run`.
constexpr std::int64_t kMaxSteps = 2000000000;

void declare_top(Parameters& p, Recipe& r) {
  p.string("name", r.name, {}, "the recipe's name, in data-file titles, logs and reports")
      .also("1 to " + std::to_string(kMaxTextChars) + " printable ASCII characters",
            [](const nlohmann::json& v, const std::string& source, const std::string& field) {
              check_free_text(source, field, v.get<std::string>());
            });
  p.integer("seed", r.seed, 1, 1000000, "",
            "random seed of the build, the velocities and the thermostats (replicas derive "
            "theirs from it)");
  p.string("model", r.model,
           {{"pp", "pure polymer"},
            {"pnc", "with clay"},
            {"kg", "glassy bead-spring polymer"},
            {"kg_platelet", "the glass with a platelet"}},
           "the system: the coarse-grained polypropylene, with clay, the bead-spring glass (D135) "
           "or the glass with a rigid platelet (D170)");
}

void declare_build(Parameters& p, Recipe& r, const std::string& applies) {
  p.section("build", "the builder: self-avoiding random-walk chains at a set density", applies);
  p.integer("chains", r.build.chains, 1, 100000, "", "polymer chains")
      .remark("chains x beads_per_chain <= 1000000");
  p.integer("beads_per_chain", r.build.beads_per_chain, 4, 10000, "",
            "beads per chain (a torsion needs 4)");
  p.real("density", r.build.density, RealRange::open(0.05, 3.0), "g/cm^3",
         "mass density of the built box");
  p.real("min_distance", r.build.min_distance, RealRange::open(0.0, 4.0), "A",
         "closest approach of beads that are not 1-2 or 1-3 neighbours at the build")
      .remark("model kg: below the bond length");
}

void declare_clay(Parameters& p, Recipe& r, const std::string& applies) {
  p.section("clay", "the montmorillonite platelet (D23-D25); required by model pnc", applies);
  p.integer("cells_a", r.clay.cells_a, 1, 200, "", "unit cells along x1 (crystal a)")
      .remark("cells_a x cells_b <= 200; not with aspect_ratio");
  p.integer("cells_b", r.clay.cells_b, 1, 200, "", "unit cells along x3 (crystal b)");
  p.real("aspect_ratio", r.clay.aspect_ratio, RealRange::at_least(0), "1",
         "instead of cells_a: cells_a = round(aspect_ratio cells_b b / a); 0 = use cells_a")
      .omit_when_default(); // expanded into cells_a
  p.real("min_distance", r.clay.min_distance, RealRange::open(0, 6), "A",
         "closest polymer bead to a clay atom at the build");
  p.real("gap_x", r.clay.gap_x, RealRange::open(0, 200), "A",
         "box length along x1 minus the platelet length");
}

void declare_pp_forcefield(Parameters& p, Recipe& r, const std::string& applies) {
  p.section("forcefield", "the coarse-grained polypropylene's Lennard-Jones pair (D13, D14)",
            applies);
  p.real("sigma", r.ff.sigma, RealRange::above(0), "A", "LJ diameter");
  p.real("epsilon", r.ff.epsilon, RealRange::above(0), "kcal/mol", "LJ well depth");
  p.real("cutoff_sigma", r.ff.cutoff_sigma, RealRange::closed(1.2, 5), "sigma",
         "LJ cutoff; twice the cutoff must fit in the box");
}

void declare_kg_forcefield(Parameters& p, Recipe& r, const std::string& applies) {
  p.section("forcefield", "the bead-spring (Kremer-Grest) chain: LJ pairs and FENE bonds (D136)",
            applies);
  p.real("sigma", r.kg.sigma, RealRange::above(0), "A", "LJ diameter, the length unit");
  p.real("epsilon", r.kg.epsilon, RealRange::above(0), "kcal/mol",
         "LJ well depth, the energy unit (eps / k_B = 400 K by default)");
  p.real("bead_mass", r.kg.bead_mass, RealRange::above(0), "g/mol", "mass of a bead");
  p.real("fene_K_reduced", r.kg.fene_K_reduced, RealRange::above(0), "eps/sigma^2",
         "FENE spring constant K");
  p.real("fene_R0_sigma", r.kg.fene_R0_sigma, RealRange::open_closed(1, 3), "sigma",
         "FENE range R0");
  p.real("cutoff_sigma", r.kg.cutoff_sigma, RealRange::closed(1.122462048309373, 5), "sigma",
         "LJ cutoff: 2^(1/6) purely repulsive (WCA), 2.5 a glass with cohesion");
  p.real("bond_length_sigma", r.kg.bond_length_sigma, RealRange::at_least(0.8), "sigma",
         "bond length the builder places")
      .remark("below fene_R0_sigma");
}

void declare_platelet(Parameters& p, Recipe& r, const std::string& applies) {
  p.section("platelet", "the rigid platelet in the glass (D170-D174)", applies);
  auto& s = r.platelet;
  p.integer("beads_side", s.beads_side, 2, 60, "", "beads along x1 and along x3")
      .remark("the edge <= 3/4 of the box (D172)");
  p.integer("layers", s.layers, 2, 4, "",
            "bead layers along x2 (one layer has no bending stiffness, D170)");
  p.real("spacing_sigma", s.spacing_sigma, RealRange::closed(0.8, 1.2), "sigma",
         "lattice spacing of the platelet");
  p.real("epsilon_wp_reduced", s.epsilon_wp_reduced, RealRange::open_closed(0, 5), "eps",
         "platelet-polymer LJ well depth: the adhesion");
  p.real("sigma_wp_sigma", s.sigma_wp_sigma, RealRange::closed(0.8, 1.5), "sigma",
         "platelet-polymer LJ diameter");
  p.real("bond_K_reduced", s.bond_K_reduced, RealRange::closed(10, 2000), "eps/sigma^2",
         "harmonic K of the platelet's bonds")
      .remark("its vibration bounds the time steps (D173)");
  p.real("min_distance_sigma", s.min_distance_sigma, RealRange::closed(0.8, 1.5), "sigma",
         "closest polymer bead to a platelet bead at the build")
      .remark(">= build.min_distance / sigma");
}

// The equilibration: the polypropylene protocol (models pp, pnc) or the glass's (kg,
// kg_platelet: push-off, melt, quench, NPT, NVT; its Langevin and clay stages do not exist).
void declare_equilibrate(Parameters& p, Recipe& r, bool kg, const std::string& applies) {
  auto& e = r.equilibrate;
  p.section("equilibrate",
            kg ? "the glass protocol (D137): push-off, melt, quench at set pressure, NPT, NVT"
               : "the melt protocol: push-off, hot, (clay), cool, Langevin, NPT or NVT, NVT",
            applies);
  p.real("timestep_fs", e.timestep_fs, RealRange::above(0), "fs", "MD time step");
  p.real("temperature", e.temperature, RealRange::above(0), "K",
         kg ? "the glass temperature (the quench's end)" : "the temperature of the RVE");
  p.real("damp_fs", e.damp_fs, RealRange::above(0), "fs", "thermostat damping time");
  p.integer("pushoff_steps", e.pushoff_steps, 100, kMaxSteps, "",
            "steps per push-off round (soft pair ramped up to remove overlaps)");
  p.integer("pushoff_max_rounds", e.pushoff_max_rounds, 1, 1000, "", "push-off rounds at most");
  p.real("pushoff_A_max", e.pushoff_A_max, RealRange::above(0), "kcal/mol",
         "soft pair prefactor at the end of a push-off round");
  p.real("pushoff_min_distance_sigma", e.pushoff_min_distance_sigma, RealRange::open(0, 1.2),
         "sigma", "push-off ends when no pair is closer than this");
  p.integer("hot_steps", e.hot_steps, kg ? 1000 : 0, kMaxSteps, "",
            kg ? "melt steps (the first 1000 with a displacement limit)"
               : "steps at hot_temperature");
  p.real("hot_temperature", e.hot_temperature, RealRange::above(0), "K",
         kg ? "melt temperature, above temperature" : "temperature of the hot stage");
  if (!kg)
    p.integer("clay_steps", e.clay_steps, 0, kMaxSteps, "",
              "model pnc: clay relaxation with the polymer fixed");
  p.integer("cool_steps", e.cool_steps, kg ? 100 : 0, kMaxSteps, "",
            kg ? "quench steps, hot_temperature to temperature" : "steps of the cooling ramp");
  if (!kg) {
    p.integer("langevin_chunk_steps", e.langevin_chunk_steps, 100, kMaxSteps, "",
              "steps per Langevin chunk");
    p.integer("langevin_max_chunks", e.langevin_max_chunks, 2, 10000, "",
              "Langevin chunks at most");
    p.real("steady_tolerance", e.steady_tolerance, RealRange::above(0), "1",
           "relative change between two chunks that ends the Langevin stage");
  }
  if (kg)
    p.string("ensemble", e.ensemble, {{"npt", "set pressure"}},
             "the glass is quenched and held at a set pressure");
  else
    p.string("ensemble", e.ensemble, {{"npt", "set pressure"}, {"nvt", "set density"}},
             "ensemble of the long run before the final NVT hold");
  p.real("pressure_atm", e.pressure_atm, RealRange::closed(-1e5, 1e5), "atm",
         "pressure of the NPT runs");
  p.real("pdamp_fs", e.pdamp_fs, RealRange::above(0), "fs", "barostat damping time");
  p.integer("npt_steps", e.npt_steps, kg ? 100 : 0, kMaxSteps, "",
            "steps of the NPT (or NVT) run; the box is then set to the mean volume of its "
            "second half");
  p.integer("final_steps", e.final_steps, 100, kMaxSteps, "",
            "steps of the final NVT hold (the start state of the cases)");
}

void declare_deform(Parameters& p, Recipe& r) {
  auto& d = r.deform;
  p.section("deform", "the deformation cases (docs/theory.md section 2.1)");
  p.integers("cases", r.cases, 1, static_cast<int>(damage::deformation_cases().size()), 1,
             std::numeric_limits<std::size_t>::max(), "",
             "case ids: 1-3 extension along x1..x3, 4-6 shear 2-3, 1-3, 1-2, 7-9 the same "
             "shears in the negative sense (D424)")
      .remark("models pnc and kg_platelet default to [1, 2, 3, 4, 5, 6]; models pp and kg "
              "need an extension case (D12l)");
  p.real("strain_max", d.strain_max, RealRange::closed(-0.5, 0.5), "1",
         "final engineering strain (gamma for shear); may be negative")
      .also("non-zero",
            [](const nlohmann::json& v, const std::string& source, const std::string& field) {
              if (v.get<double>() == 0.0)
                fail(source, field, "0", "must be non-zero with |strain_max| <= 0.5");
            });
  p.real("shear_strain_max", d.shear_strain_max, RealRange::closed(-0.5, 0.5), "1",
         "final |gamma| of the shear cases 4-9 (7-9 shear the other way); 0 = they use "
         "strain_max (D12m)")
      .omit_when_default(); // in the expanded recipe only when set
  p.integer("steps", d.steps, 1, 100000, "", "strain steps");
  p.real("timestep_fs", d.timestep_fs, RealRange::open_closed(0, 50), "fs", "MD time step");
  p.integer("hold_steps", d.hold_steps, 1, kMaxSteps, "", "MD steps held per strain step")
      .remark(">= sample_every x blocks");
  p.integer("sample_every", d.sample_every, 1, 1000000, "", "steps between stress samples");
  p.integer("blocks", d.blocks, 2, 10000, "", "blocks per hold for the standard error");
  p.integer("reference_holds", d.reference_holds, 1, 1000, "",
            "the zero-strain hold (row 0) lasts reference_holds x hold_steps (D131)");
  p.real("temperature", d.temperature, RealRange::at_least(0), "K",
         "Langevin temperature of the holds; 0 = static deformation (D120)");
  p.real("damp_fs", d.damp_fs, RealRange::above(0), "fs", "Langevin damping time");
  p.boolean("minimize", d.minimize,
            "static deformation only: minimise the atoms at the fixed box in every row");
}

void declare_phase_check(Parameters& p, Recipe& r) {
  auto& pc = r.phase_check;
  p.section("phase_check",
            "the phase check: is the RVE a solid on the time scale of one hold (D125-D129)");
  p.boolean("enabled", pc.enabled, "run the phase check before the cases (the presets do)");
  p.integer("steps", pc.steps, 1000, kMaxSteps, "", "NVE steps of the stress autocorrelation")
      .remark(">= 2 x deform.hold_steps");
  p.integer("sample_every", pc.sample_every, 1, 1000, "", "steps between stress samples");
  p.integer("blocks", pc.blocks, 4, 1000, "", "blocks of time origins for the standard errors");
  p.real("shear_strain", pc.shear_strain, RealRange::open_closed(0, 0.1), "1",
         "gamma of the +-shear step pair");
  p.real("bulk_strain", pc.bulk_strain, RealRange::open_closed(0, 0.1), "1",
         "volumetric strain of the +-volume pair");
  p.real("cavitation_strain", pc.cavitation_strain, RealRange::open_closed(0, 0.5), "1",
         "volumetric expansion of the cavitation hold");
  p.integer("cavitation_steps", pc.cavitation_steps, 100, kMaxSteps, "",
            "steps of the cavitation hold");
}

void declare_analysis_fit_run(Parameters& p, Recipe& r) {
  p.section("analysis", "what the fit gets (D18, D131-D134)");
  p.string("stress", r.stress,
           {{"total", "with the kinetic term, D134"}, {"virial", "no kinetic term"}},
           "the stress handed to the fit");
  p.integer("moving_average", r.moving_average, 1, 1001, "",
            "points of a moving average over strain steps, for display only (1 = off; D133)")
      .also("odd",
            [](const nlohmann::json& v, const std::string& source, const std::string& field) {
              if (v.get<long>() % 2 == 0)
                fail(source, field, v.dump(), "must be an odd number >= 1 (1 = off)");
            });
  p.string("reference", r.reference,
           {{"subtract", "stress relative to the zero-strain hold"}, {"none", "raw stress"}},
           "reference state of the fitted stress (D18, D131)");
  p.section("fit", "the NDM fit of the cases (D10-D12m)");
  p.boolean("fit_alpha", r.fit_alpha, "fit alpha (else held at its start value)")
      .remark("not with hold_alpha");
  p.boolean("hold_alpha", r.hold_alpha, "hold alpha at its start value past the damage onset")
      .remark("not with fit_alpha")
      .omit_when_default();
  p.real("alpha", r.fit_alpha_start, RealRange::closed(0.5, 1.5), "1",
         "alpha the fit starts from (or holds); the glass presets use 0.82 (D138)")
      .no_default("the dissertation's value");
  p.real("strain_max", r.fit_strain_max, RealRange::closed(0, 10), "1",
         "fit range: rows with every strain component <= it are fitted; 0 = every row (D12h)")
      .remark("not with stretch_max")
      .omit_when_default();
  p.real("stretch_max", r.fit_stretch_max, RealRange::closed(0, 10), "1",
         "fit range by stretch: rows with lambda_max - 1 <= it are fitted, lambda_max the "
         "largest principal stretch; 0 = every row (D12m)")
      .remark("not with strain_max")
      .omit_when_default();
  p.boolean("isotropic", r.fit_isotropic,
            "isotropic solid with isotropic damage: C44 = (C11 - C12)/2 and B4 = B1 - B2/2 "
            "derived, not fitted (D396)")
      .remark("models pp and kg")
      .omit_when_default();
  p.integer("bootstrap", r.fit_bootstrap, 0, 100000, "",
            "resamples of the bootstrap of the joint fit over replicas that checks the card's "
            "error bars and raises any below the joint fit's spread (>= 8 replicas; below 20 = "
            "off; D431)")
      .omit_when_default();
  p.section("run", "how the cases run");
  p.integer("jobs", r.jobs, 1, 64, "", "cases at a time (pnc characterize --jobs overrides)");
  p.integer("replicas", r.replicas, 1, kMaxReplicas, "",
            "independent replicas: own build seed, own equilibration, every case (D130)");
}

void declare_slurm(Parameters& p, Recipe& r) {
  campaign::declare_slurm_section(
      p, r.slurm,
      "the Slurm executor (docs/cluster.md, D245): where and how long the unit "
      "jobs run; the command-line options override it; in the expanded recipe "
      "only when given",
      true);
}

} // namespace

void declare_recipe(Parameters& p, Recipe& r, const std::string& variant) {
  const bool all = variant.empty();
  const bool user = variant == "system";
  const bool kg = variant == "kg" || variant == "kg_platelet";
  if (!all && !user && !kg && variant != "pp" && variant != "pnc")
    throw std::logic_error("declare_recipe: unknown variant '" + variant + "'");
  auto when = [&](const char* text) { return all ? std::string(text) : std::string(); };
  declare_top(p, r);
  if (!user) declare_build(p, r, when("built-in models; not with system"));
  if (all || variant == "pnc") declare_clay(p, r, when("model pnc"));
  if (all || variant == "pp" || variant == "pnc")
    declare_pp_forcefield(p, r, when("models pp, pnc"));
  if (all || kg) declare_kg_forcefield(p, r, when("models kg, kg_platelet"));
  if (all || variant == "kg_platelet") declare_platelet(p, r, when("model kg_platelet"));
  if (all || (!user && !kg)) declare_equilibrate(p, r, false, when("models pp, pnc"));
  if (all || kg) declare_equilibrate(p, r, true, when("models kg, kg_platelet"));
  if (all || user) // your own system: its file, force field and stages (user_system.hpp)
    declare_user_system(p, r.system, when("a recipe with your own system"), all);
  declare_deform(p, r);
  declare_phase_check(p, r);
  declare_analysis_fit_run(p, r);
  declare_slurm(p, r);
}

namespace {
// The declarations of `variant` bound to `*r`, defaults from a recipe of defaults.
Parameters declared_defaults(const std::string& variant, const std::shared_ptr<Recipe>& r) {
  if (variant == "pnc" || variant == "kg_platelet") r->cases = {1, 2, 3, 4, 5, 6};
  if (!variant.empty() && variant != "system") r->model = variant;
  Parameters p("pnc characterize recipe" +
               (variant.empty() ? std::string() : " (" + variant + ")"));
  declare_recipe(p, *r, variant);
  p.hold(r);
  return p;
}
} // namespace

Parameters recipe_parameters(const std::string& variant) {
  return declared_defaults(variant, std::make_shared<Recipe>());
}

nlohmann::json expanded_json(const Recipe& r) {
  auto bound = std::make_shared<Recipe>();
  const Parameters p = declared_defaults(r.system.enabled ? "system" : r.model, bound);
  *bound = r; // the declarations now read r's values
  nlohmann::json out = p.values();
  if (r.system.enabled) { // the resolved file and its hash, as the recipe reads them back
    const nlohmann::json u = user_system_json(r.system);
    out["system"] = u.at("system");
    out["equilibrate"] = u.at("equilibrate");
  }
  return out;
}

} // namespace pnc::rve
