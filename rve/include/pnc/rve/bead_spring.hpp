#pragma once
// pnc/rve/bead_spring.hpp: the glassy bead-spring polymer (recipe "model": "kg", a
// Kremer-Grest type chain model): force field, its LAMMPS commands and the chain builder.
//
// Units: LAMMPS `real` (A, fs, kcal/mol, g/mol, K; densities g/cm^3); the reduced (LJ) units of
// the model are stated where a parameter is naturally one (eps/sigma^2, sigma).
//
// Model (docs/theory.md section 3, "A glassy bead-spring polymer"; decision D135):
//   E_pair = 4 eps ((s/r)^12 - (s/r)^6), r < r_c = cutoff_sigma * s, not shifted, no tail
//            correction, between every pair except the two beads of a bond (1-2);
//   E_bond = -K R0^2 / 2 ln(1 - (r/R0)^2) + 4 eps ((s/r)^12 - (s/r)^6) + eps for r < 2^(1/6) s
//            (FENE with the repulsive WCA core; LAMMPS bond_style fene), K = fene_K_reduced
//            eps/s^2, R0 = fene_R0_sigma s;
//   special_bonds lj 0 1 1 (LAMMPS `special_bonds fene`): the bonded pair feels the bond
//   only (its WCA core is inside the bond), 1-3 and 1-4 pairs feel the full LJ (decision D136).
// The mapping onto real units (sigma, epsilon, mass) and the resulting T, tau and stress
// scale are decision D135: sigma = 5 A, epsilon / k_B = 400 K, m = 80 g/mol.
#include "pnc/core/units.hpp"
#include "pnc/md/builder.hpp"
#include "pnc/rve/equilibrate.hpp"

#include <string>
#include <vector>

namespace pnc::rve {

struct PlateletSpec; // platelet.hpp

struct BeadSpringForceField {
  double sigma = 5.0;                            ///< A
  double epsilon = 400.0 * units::kB_kcal_mol_K; ///< kcal/mol (eps / k_B = 400 K)
  double bead_mass = 80.0;                       ///< g/mol
  double fene_K_reduced = 30.0;                  ///< K in eps / sigma^2
  double fene_R0_sigma = 1.5;                    ///< R0 in sigma
  double cutoff_sigma = 2.5;                     ///< LJ cutoff in sigma (2.5: attractive tail kept)
  /// Bond length the builder places (the minimum of FENE + WCA is at 0.97 sigma).
  double bond_length_sigma = 0.97;

  double cutoff() const { return cutoff_sigma * sigma; }                       ///< A
  double fene_K() const { return fene_K_reduced * epsilon / (sigma * sigma); } ///< kcal/mol/A^2
  double fene_R0() const { return fene_R0_sigma * sigma; }                     ///< A
  double bond_length() const { return bond_length_sigma * sigma; }             ///< A
  /// eps / k_B in K: the temperature of T* = 1.
  double temperature_unit() const { return epsilon / units::kB_kcal_mol_K; }
  /// tau = sigma sqrt(m / eps) in fs.
  double tau_fs() const;
  /// eps / sigma^3 in Pa: the stress (and modulus) unit.
  double stress_unit_pa() const;
  /// Number density sigma^3 N / V of a mass density (g/cm^3).
  double reduced_density(double g_cm3) const;

  /// Throws pnc::InputError (source `source`, fields "forcefield.<name>") for values outside
  /// the model's range: every parameter finite and > 0, cutoff_sigma in [2^(1/6), 5],
  /// fene_R0_sigma in (1, 3], bond_length_sigma in [0.8, fene_R0_sigma) (a bond at build
  /// time must be shorter than R0, or the FENE energy is undefined).
  void validate(const std::string& source) const;
};

/// LAMMPS commands of the model (atom type 1, bond type 1): pair lj/cut, bond fene,
/// special_bonds lj 0 1 1. Re-issued after every read_restart.
std::vector<std::string> bead_spring_commands(const BeadSpringForceField& ff);

/// Closed forms of the model's energies (kcal/mol) at distance r (A), for tests and records:
/// the LJ pair energy (0 beyond the cutoff) and the bond energy (FENE + WCA core; +inf at r >= R0).
double bead_spring_pair_energy(const BeadSpringForceField& ff, double r);
double bead_spring_bond_energy(const BeadSpringForceField& ff, double r);

/// Grows spec.chains chains of spec.beads_per_chain beads in a cubic periodic box whose edge
/// gives exactly spec.density (g/cm^3) with bead_mass: a random walk in continuous space, every
/// bond of length ff.bond_length() (so below R0 by construction), directions uniform on the
/// sphere, a trial bead rejected when closer than spec.min_distance (minimum image) to any bead
/// already placed except its bonded predecessor. A bead with no acceptable position after
/// spec.max_trials trials backs the chain up spec.backtrack beads; after
/// spec.max_chain_restarts failures the build fails with an InputError naming density and
/// min_distance. mt19937_64 seeded with spec.seed (top 53 bits to doubles): deterministic.
/// Atoms type 1, molecules 1..chains, bonds type 1, no angles or dihedrals.
md::System build_bead_spring(const md::BuildSpec& spec, const BeadSpringForceField& ff);

/// The random walk of build_bead_spring into `s`, whose box (cubic) is set and whose atoms (e.g.
/// the platelet of platelet.hpp) are obstacles no bead centre may approach closer than
/// `obstacle_min_distance` (A). The chains are appended: type 1, molecules 1..chains, bond type 1.
/// build_bead_spring is this on an empty box (identical beads for a given seed).
void grow_bead_spring_chains(md::System& s, const md::BuildSpec& spec,
                             const BeadSpringForceField& ff, double obstacle_min_distance);

/// Smallest minimum-image distance (A) between beads that are not bonded (1-2) neighbours.
double min_unbonded_distance(const md::System& s);

/// HDF5 record of the build (spec, force field with its reduced-unit mapping, counts,
/// positions, box, measured density and smallest distances). Written atomically.
void write_bead_spring_record(const std::string& path, const md::System& s,
                              const md::BuildSpec& spec, const BeadSpringForceField& ff,
                              const std::string& recipe_json);

/// The glass protocol's rules on an EquilibrateSpec (on top of EquilibrateSpec::validate):
/// ensemble "npt", hot_temperature > temperature, hot_steps >= 1000, cool_steps and npt_steps
/// >= 100. Throws pnc::InputError naming `source` and the field.
void check_glass_protocol(const EquilibrateSpec& s, const std::string& source);

/// Equilibration of the glass (decision D137), one supervised child per stage, each writing
/// `<dir>/<stage>.restart`, `.h5` (criterion, trace) and `.log`; a stage whose files exist is
/// skipped when `resume`. The EquilibrateSpec fields mean here:
///  1 pushoff  pair soft ramped 0 -> pushoff_A_max over pushoff_steps (repeated up to
///             pushoff_max_rounds until no unbonded pair is closer than
///             pushoff_min_distance_sigma sigma), NVE with a displacement limit of 0.02 sigma per
///             step + Langevin at hot_temperature (damp_fs);
///  2 melt     LJ on, energy minimisation, hot_steps of Langevin at hot_temperature (the melt,
///             T* ~ 1) at the build density (first 1000 steps with the displacement limit);
///  3 quench   Nose-Hoover NPT at pressure_atm (iso, pdamp_fs), T ramped linearly
///             hot_temperature -> temperature over cool_steps (the quench rate is logged);
///  4 final    the glass hold: NPT at (temperature, pressure_atm) for npt_steps, box set to the
///             mean volume of the second half, NVT (Langevin) for final_steps, then the
///             measurement of equilibrate.hpp stage 6 (density, pressures, void fraction with
///             probe sigma, smallest pair distance) in `<dir>`/final.h5.
/// langevin_chunk_steps, langevin_max_chunks, steady_tolerance and clay_steps are not used.
/// With `platelet` (model kg_platelet, platelet.hpp): the composite's force field
/// (kg_platelet_commands) in every stage and, in the push-off, soft pairs between polymer beads
/// only, the platelet-polymer LJ in full (kg_platelet_pushoff_pair, decision D174).
EquilibratedState equilibrate_glass(const std::string& data_file, const BeadSpringForceField& ff,
                                    const EquilibrateSpec& spec, const std::string& dir,
                                    bool resume, const std::string& recipe_json, int ranks = 1,
                                    const PlateletSpec* platelet = nullptr);

} // namespace pnc::rve
