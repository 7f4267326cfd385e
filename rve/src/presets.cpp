// The recipe presets of `pnc characterize` (pnc/rve/recipe.hpp): demo, paper (the dissertation's
// polypropylene), demo_pnc, paper_pnc (with the clay platelet), demo_glass, paper_glass,
// card_glass (the glassy bead-spring polymer), demo_glass_pnc (the glass with a platelet).
// Units as in recipes: LAMMPS real (A, fs, kcal/mol, atm, K).
//
// Two presets are written out (demo, demo_glass); every other one is its parent with a JSON
// merge patch (RFC 7386: an object merges key by key, null removes a key, anything else
// replaces), so that what a preset shares with its parent is written once (decision D233).
#include "pnc/rve/recipe.hpp"

#include "pnc/core/error.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pnc::rve {

namespace {

using json = nlohmann::json;

// The small pure polymer of the README's main job (600 beads, cases 2 and 6, minutes).
const char* demo_text = R"({
  "name": "demo",
  "seed": 1,
  "model": "pp",
  "build": { "chains": 30, "beads_per_chain": 20, "density": 0.9, "min_distance": 2.0 },
  "equilibrate": { "timestep_fs": 1.0, "pushoff_steps": 2000, "hot_steps": 10000,
                   "cool_steps": 10000, "langevin_chunk_steps": 5000, "langevin_max_chunks": 6,
                   "ensemble": "npt", "pressure_atm": 0.0, "npt_steps": 20000,
                   "final_steps": 5000 },
  "deform": { "cases": [2, 6], "strain_max": 0.1, "steps": 20, "timestep_fs": 1.0,
              "hold_steps": 5000, "sample_every": 10, "blocks": 10, "reference_holds": 5 },
  "phase_check": { "enabled": true, "steps": 12000, "sample_every": 5,
                   "cavitation_steps": 5000 },
  "analysis": { "stress": "total", "moving_average": 1, "reference": "subtract" },
  "run": { "jobs": 2 }
})";

// The dissertation's polypropylene: 1500 beads, its protocol, 0.5 fs, the virial-only stress
// (docs/theory.md §3.5, said so: D134), 10 x hold at zero strain (D131).
const char* paper_patch = R"({
  "name": "paper",
  "build": { "chains": 75 },
  "equilibrate": { "timestep_fs": 0.5, "pushoff_steps": 10000, "hot_steps": 200000,
                   "hot_temperature": 1000, "cool_steps": 200000,
                   "langevin_chunk_steps": 20000, "langevin_max_chunks": 20, "npt_steps": 400000,
                   "final_steps": 20000 },
  "deform": { "steps": 40, "timestep_fs": 0.5, "hold_steps": 10000, "temperature": 300,
              "reference_holds": 10 },
  "phase_check": { "steps": 40000, "sample_every": 10, "cavitation_steps": null },
  "analysis": { "stress": "virial" }
})";

// Nanocomposite (decision D24): paper with a platelet of 7 x 1 cells (36.4 x 9.2 A, aspect
// ratio 3.96, the closest to the printed 4.19), 1500 beads, cases 1-6, 0.5 fs (O-H bond).
const char* paper_pnc_patch = R"({
  "name": "paper_pnc",
  "model": "pnc",
  "clay": { "cells_a": 7, "cells_b": 1, "min_distance": 3.0, "gap_x": 10.0 },
  "equilibrate": { "clay_steps": 20000 },
  "deform": { "cases": [1, 2, 3, 4, 5, 6], "reference_holds": 4 }
})";

// Small nanocomposite that finishes in minutes: demo with 400 beads, 3 x 1 cells, short holds.
const char* demo_pnc_patch = R"({
  "name": "demo_pnc",
  "model": "pnc",
  "build": { "chains": 20 },
  "clay": { "cells_a": 3, "cells_b": 1, "min_distance": 3.0, "gap_x": 10.0 },
  "equilibrate": { "timestep_fs": 0.5, "hot_steps": 6000, "clay_steps": 2000, "cool_steps": 6000,
                   "langevin_chunk_steps": 3000, "langevin_max_chunks": 3, "npt_steps": 10000,
                   "final_steps": 2000 },
  "deform": { "cases": [1, 2, 3, 4, 5, 6], "strain_max": 0.05, "steps": 10, "timestep_fs": 0.5,
              "hold_steps": 2000, "reference_holds": 1 },
  "phase_check": { "steps": 10000, "sample_every": 10, "cavitation_steps": 4000 }
})";

// Glassy bead-spring polymer (model kg, decisions D135-D139): sigma 5 A, eps/k_B 400 K,
// m 80 g/mol (tau 2.45 ps, eps/sigma^3 44.2 MPa); melt at 400 K (T* 1), quench at P = 0 to
// 80 K (T* 0.2), 20 fs steps (0.008 tau). Measured wall times: docs/rve.md.
const char* demo_glass_text = R"({
  "name": "demo_glass",
  "seed": 1,
  "model": "kg",
  "build": { "chains": 40, "beads_per_chain": 25, "density": 0.9, "min_distance": 3.5 },
  "forcefield": { "sigma": 5.0, "epsilon": 0.79488268, "bead_mass": 80.0,
                  "fene_K_reduced": 30.0, "fene_R0_sigma": 1.5, "cutoff_sigma": 2.5 },
  "equilibrate": { "timestep_fs": 20.0, "temperature": 80.0, "hot_temperature": 400.0,
                   "damp_fs": 2000.0, "pushoff_steps": 2000, "pushoff_A_max": 40.0,
                   "hot_steps": 10000, "cool_steps": 25000, "ensemble": "npt",
                   "pressure_atm": 0.0, "pdamp_fs": 20000.0, "npt_steps": 10000,
                   "final_steps": 2500 },
  "deform": { "cases": [2, 6], "strain_max": 0.12, "steps": 48, "timestep_fs": 20.0,
              "hold_steps": 1000, "sample_every": 10, "blocks": 10, "temperature": 80.0,
              "damp_fs": 2000.0 },
  "phase_check": { "enabled": true, "steps": 4000, "sample_every": 10,
                   "cavitation_steps": 2000 },
  "analysis": { "stress": "total", "moving_average": 1, "reference": "subtract" },
  "fit": { "fit_alpha": true, "alpha": 0.82, "strain_max": 0.08 },
  "run": { "jobs": 2, "replicas": 4 }
})";

// demo_glass at 4000 beads with longer melt, quench and holds.
const char* paper_glass_patch = R"({
  "name": "paper_glass",
  "build": { "chains": 100, "beads_per_chain": 40 },
  "equilibrate": { "pushoff_steps": 5000, "hot_steps": 50000, "cool_steps": 125000,
                   "npt_steps": 25000, "final_steps": 5000 },
  "deform": { "hold_steps": 2500 },
  "phase_check": { "steps": 10000, "cavitation_steps": 5000 }
})";

// demo_glass's glass with the protocol of its best card (decision D398; docs/rve.md, "24
// replicas"): cases 1-6 to a stretch of 0.05 (shear to 0.10) in 72 steps of 600-step holds,
// and each shear in the negative sense too (cases 7-9, D424, D426: the two senses of one
// replica soften differently, their mean scatters less between replicas); fitted over a stretch of
// 0.03, where the law follows the glass's shear on independent replicas, with 48 replicas
// (decision D421). About 2 h on 2 cores (docs/rve.md, "Both senses in one run").
const char* card_glass_patch = R"({
  "name": "card_glass",
  "deform": { "cases": [1, 2, 3, 4, 5, 6, 7, 8, 9], "strain_max": 0.05, "shear_strain_max": 0.10,
              "steps": 72, "hold_steps": 600 },
  "fit": { "strain_max": null, "stretch_max": 0.03 },
  "run": { "replicas": 48 }
})";

// Model nanocomposite (model kg_platelet, decisions D170-D176): the demo_glass polymer (32 chains
// x 25 beads) with one 8 x 8 x 2 bead platelet (edge 7 sigma = 35 A, ~0.7 of the box), normal x2,
// weak adhesion eps_wp = 0.5 eps so that case 2 can open the interface; cases 1-6, 4 replicas,
// every row fitted. Measured wall time: docs/rve.md, "A model nanocomposite: glass + rigid
// platelet".
const char* demo_glass_pnc_patch = R"({
  "name": "demo_glass_pnc",
  "model": "kg_platelet",
  "build": { "chains": 32 },
  "platelet": { "beads_side": 8, "layers": 2, "spacing_sigma": 1.0, "epsilon_wp_reduced": 0.5,
                "sigma_wp_sigma": 1.0, "bond_K_reduced": 300.0, "min_distance_sigma": 1.0 },
  "equilibrate": { "hot_steps": 8000, "cool_steps": 20000, "npt_steps": 8000,
                   "final_steps": 2000 },
  "deform": { "cases": [1, 2, 3, 4, 5, 6], "strain_max": 0.08, "steps": 20, "hold_steps": 1500,
              "reference_holds": 2 },
  "fit": { "strain_max": null }
})";

struct Preset {
  const char* name;
  const char* parent; ///< nullptr: `text` is the whole recipe; else a merge patch of the parent
  const char* text;
};

// In the order `pnc recipe show` lists them; a parent before its children.
const Preset kPresets[] = {
    {"demo", nullptr, demo_text},
    {"paper", "demo", paper_patch},
    {"demo_pnc", "demo", demo_pnc_patch},
    {"paper_pnc", "paper", paper_pnc_patch},
    {"demo_glass", nullptr, demo_glass_text},
    {"paper_glass", "demo_glass", paper_glass_patch},
    {"card_glass", "demo_glass", card_glass_patch},
    {"demo_glass_pnc", "demo_glass", demo_glass_pnc_patch},
};

} // namespace

std::vector<std::string> preset_names() {
  std::vector<std::string> n;
  for (const auto& p : kPresets)
    n.emplace_back(p.name);
  return n;
}

nlohmann::json preset_json(const std::string& name) {
  for (const auto& p : kPresets)
    if (name == p.name) {
      if (!p.parent) return json::parse(p.text);
      json j = preset_json(p.parent);
      j.merge_patch(json::parse(p.text));
      return j;
    }
  std::string list;
  for (const auto& p : kPresets)
    list += (list.empty() ? "" : ", ") + std::string(p.name);
  fail("<command line>", "preset", name, "must be one of: " + list);
}

} // namespace pnc::rve
