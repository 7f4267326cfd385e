#pragma once
// pnc/rve/recipe.hpp: the recipe of `pnc characterize` (JSON or TOML) and its presets.
//
// Units: LAMMPS `real` for everything the recipe feeds to LAMMPS (A, fs, kcal/mol, atm, K;
// densities g/cm^3); the cases.h5 the pipeline hands to the fit is in SI (Pa).
//
// A recipe is a JSON object (or a TOML document with the same tables): the top-level keys
// "name", "seed", "model" and the sections "build", "clay" (model pnc), "forcefield" (one set
// of keys for models pp and pnc, another for kg and kg_platelet), "platelet" (model
// kg_platelet), "equilibrate", "deform", "phase_check", "analysis", "fit", "run", "slurm"
// (pnc/campaign/slurm.hpp), or, instead of the builder, "system" (user_system.hpp). Every key is
// declared once, with its type, default (the values of the structs below), range, unit and text, in
// recipe_parameters.cpp (declare_recipe); `pnc recipe parameters` prints them (JSON, a TOML
// template, the Markdown tables of docs/rve.md). Every key is optional; unknown keys are
// errors. Errors name the file, the field (dotted path), the value and the rule.
#include "pnc/md/builder.hpp"
#include "pnc/rve/bead_spring.hpp"
#include "pnc/rve/clay.hpp"
#include "pnc/rve/deform.hpp"
#include "pnc/rve/equilibrate.hpp"
#include "pnc/rve/phase_check.hpp"
#include "pnc/rve/platelet.hpp"
#include "pnc/rve/user_system.hpp"

#include "pnc/campaign/slurm.hpp"
#include "pnc/core/parameters.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pnc::rve {

/// The most independent replicas a run may have (run.replicas, --replicas); the Student factors
/// of the replica statistics are tabulated up to it (replica_trend.cpp).
inline constexpr int kMaxReplicas = 64;

struct Recipe {
  std::string name = "custom";
  std::uint64_t seed = 1;
  /// "pp" (pure polymer), "pnc" (with the clay platelet), "kg" (glassy bead-spring polymer,
  /// bead_spring.hpp; fitted with the pure-polymer NDM) or "kg_platelet" (the glass with one
  /// stiff platelet, platelet.hpp; fitted with the nanocomposite NDM, decision D175)
  std::string model = "pp";
  md::BuildSpec build;
  ClaySpec clay; ///< used when model == "pnc"
  md::PolymerForceField ff;
  BeadSpringForceField kg; ///< models "kg" and "kg_platelet": their "forcefield" section
  PlateletSpec platelet;   ///< model "kg_platelet" (the glass with a platelet, decision D170)
  EquilibrateSpec equilibrate;
  DeformSpec deform;          ///< template: case_id, seed, start_state filled per case
  PhaseCheckSpec phase_check; ///< off unless the recipe enables it (the presets do)
  std::vector<int> cases = {2, 6};
  /// which stress goes to the fit: "total" (with the kinetic term, the default: decision D134)
  /// or "virial" (docs/theory.md §3.5, the dissertation's; biases every normal constant by -rho k_B
  /// T)
  std::string stress = "total";
  /// points of a moving average over strain steps stored for display only (1 = off); the fit
  /// always gets the unsmoothed points and their own errors (decision D133)
  int moving_average = 1;
  /// "subtract": the fit gets sigma(eps_k) - sigma_ref, sigma_ref the mean of the zero-strain
  /// holds (row 0) of all cases of a replica (decisions D18, D131); "none": the raw stress,
  /// row 0 included.
  std::string reference = "subtract";
  bool fit_alpha = false;
  /// α held at fit_alpha_start even past the damage onset (key "fit.hold_alpha")
  bool hold_alpha = false;
  /// α the fit starts from (or holds); 0 = the dissertation's value. Key "fit.alpha", in
  /// [0.5, 1.5]; the glass presets hold it at 0.82 (decision D138).
  double fit_alpha_start = 0;
  /// fit range (key "fit.strain_max", decision D12h): rows with every strain component <= it
  /// are fitted; 0 = every row. Dimensionless.
  double fit_strain_max = 0;
  /// fit.stretch_max: fit range by largest principal stretch - 1, exclusive with
  /// fit.strain_max; 0 = every row (decision D12m)
  double fit_stretch_max = 0;
  /// fit.isotropic: the pure polymer's C44 and B4 derived by isotropy, C44 = (C11 - C12)/2,
  /// B4 = B1 - B2/2 (decision D396); models pp and kg only
  bool fit_isotropic = false;
  /// fit.bootstrap: resamples of the bootstrap of the joint fit over replicas, the calibration
  /// check of the card's error bars (decision D431); runs with >= 8 replicas; < 20 = off
  int fit_bootstrap = 200;
  int jobs = 1;
  /// "system": the user's own data/restart file and force field instead of the builder
  /// (user_system.hpp); then "build", "clay" and "forcefield" are refused and "equilibrate"
  /// holds the user's stages.
  UserSystem system;
  /// independent replicas: own build seed, own equilibration, every case (decision D130); 1 to
  /// kMaxReplicas
  int replicas = 1;
  /// "slurm": where and how the Slurm executor runs the units (pnc/campaign/slurm.hpp, D245); in
  /// the expanded recipe only when given
  campaign::SlurmSpec slurm;
  nlohmann::json source_json; ///< the recipe as given (stored in every output)
};

/// Longest free-text field of a recipe (name), in characters.
inline constexpr std::size_t kMaxTextChars = 64;
/// Free-text fields (the recipe name, titles) end up in LAMMPS data-file headers, logs and
/// reports: they must be 1..max_chars printable ASCII characters (0x20..0x7e; no newline, tab
/// or other control character). Throws pnc::InputError naming `source`, `field` and the rule.
void check_free_text(const std::string& source, const std::string& field, const std::string& value,
                     std::size_t max_chars = kMaxTextChars);

/// Parses and validates: the declared reads (declare_recipe, for the recipe's model or "system"),
/// then the rules between keys (exclusive keys, model-dependent sections, phase_check.steps >=
/// 2 x deform.hold_steps, the box against the cutoffs, ...). `source` names the file in errors.
Recipe parse_recipe(const nlohmann::json& j, const std::string& source);
/// Declares the recipe's keys in `p`, bound to `r` (defaults: r's values now). `variant`: "pp",
/// "pnc", "kg", "kg_platelet" (that model's sections), "system" (a recipe with your own
/// system: declare_user_system), or "" (every section of every variant and the keys of each
/// kind of user stage, for the documentation: printable, not readable).
void declare_recipe(Parameters& p, Recipe& r, const std::string& variant);
/// declare_recipe() bound to a recipe of defaults that the result keeps alive (for printing:
/// `pnc recipe parameters`). For "pnc" and "kg_platelet" deform.cases defaults to 1..6.
Parameters recipe_parameters(const std::string& variant = "");
/// Model kg_platelet's rules that need the whole recipe (implemented in platelet.cpp): the
/// box of check_kg_platelet_box (D172); the platelet's frequency bound times equilibrate.
/// timestep_fs and deform.timestep_fs <= 1 (D173). Throws InputError naming source and field.
void check_platelet_recipe(const Recipe& r, const std::string& source);
/// Reads a recipe file: JSON (".json") or TOML (".toml", same sections as tables, same keys);
/// other extensions are an InputError.
Recipe read_recipe(const std::string& path);
/// The presets "demo", "paper", "demo_pnc", "paper_pnc", "demo_glass", "paper_glass" as JSON (what
/// `pnc recipe show` prints).
nlohmann::json preset_json(const std::string& name);
std::vector<std::string> preset_names();
/// A recipe (JSON form, e.g. preset_json) written as TOML; read_recipe reads it back.
std::string recipe_toml(const nlohmann::json& recipe);
/// The recipe fully expanded (every declared key with its value; fit.alpha, fit.hold_alpha,
/// fit.strain_max, fit.stretch_max, deform.shear_strain_max and clay.aspect_ratio only when set,
/// the slurm section only when given), for records and `recipe show`: the declarations'
/// values() (declare_recipe) plus the user's system with its resolved file and hash.
nlohmann::json expanded_json(const Recipe& r);

} // namespace pnc::rve
