#pragma once
// pnc/md/builder.hpp: the coarse-grained polypropylene RVE builder.
//
// Units: LAMMPS `real` (Angstrom, g/mol; densities in g/cm^3 at the interface).
//
// Chains of N beads are grown one after the other by a self-avoiding random walk in
// continuous space with periodic boundaries (cubic box sized to the target density): every
// bond has length l0, every bond angle is theta0, the torsion angle is uniform in
// [0, 360) deg, and a trial bead is rejected when it lies closer than `min_distance` (minimum
// image) to any bead already placed other than its own chain's 1-2 and 1-3 neighbours.
// A bead with no acceptable position after `max_trials` trials makes the walk back up
// `backtrack` beads; a chain that fails `max_chain_restarts` times makes the build fail with
// an InputError naming the density and min_distance. Random numbers: std::mt19937_64
// seeded with `seed`, mapped to doubles by the top 53 bits (identical on every platform).
#include "pnc/md/forcefield.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pnc::h5 {
class File;
} // namespace pnc::h5

namespace pnc::md {

struct BuildSpec {
  int chains = 75;          ///< number of chains
  int beads_per_chain = 20; ///< N
  double density = 0.9;     ///< target density, g/cm^3
  std::uint64_t seed = 1;
  double min_distance = 2.0; ///< A, between beads that are not 1-2 or 1-3 neighbours
  int max_trials = 200;
  int backtrack = 3;
  int max_chain_restarts = 2000;
  void validate(const std::string& source) const;
};

/// An atomistic system in a (possibly triclinic) periodic box. Positions are unwrapped
/// (chains continuous); the data-file writer wraps them and writes image flags.
struct System {
  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
  double xy = 0, xz = 0, yz = 0;
  std::vector<std::array<double, 3>> x;      ///< A, unwrapped
  std::vector<int> mol;                      ///< molecule id, 1-based (0 = none)
  std::vector<int> type;                     ///< atom type, 1-based
  std::vector<double> type_mass;             ///< g/mol, per type (index type-1)
  std::vector<double> charge;                ///< e; empty = no charges (atom_style molecular)
  std::vector<std::array<int, 3>> bonds;     ///< type, i, j (0-based atoms)
  std::vector<std::array<int, 4>> angles;    ///< type, i, j, k
  std::vector<std::array<int, 5>> dihedrals; ///< type, i, j, k, l
  int bond_types = 1, angle_types = 1, dihedral_types = 1;

  double volume() const;                                                       ///< A^3
  double mass() const;                                                         ///< g/mol
  double density() const { return mass() / (volume() * avogadro_per_A3_cm3); } ///< g/cm^3
  std::array<double, 3> length() const { return {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}; }
  /// Minimum-image vector b - a (orthogonal boxes).
  std::array<double, 3> min_image(const std::array<double, 3>& a,
                                  const std::array<double, 3>& b) const;
};

/// Grows the chains. Deterministic for a given spec (seed included).
System build_polymer(const BuildSpec& spec, const PolymerForceField& ff);

/// Grows spec.chains chains into `s` (box set; atoms already in `s`, e.g. the clay, are
/// obstacles no bead may approach closer than `obstacle_min_distance`). Bead atoms get type 1
/// and molecules 1..chains; topology types 1.
void grow_chains(System& s, const BuildSpec& spec, const PolymerForceField& ff,
                 double obstacle_min_distance);

/// Smallest minimum-image distance between two beads that are not 1-2 or 1-3 bonded
/// neighbours in the same chain (cell list; O(N)). Pairs of two non-bead atoms (type != 1,
/// the clay) are not counted.
double min_nonbonded_distance(const System& s);

/// LAMMPS data file (atom_style molecular, or full when charges are present), written
/// atomically. Coefficients are not written: they come from the force-field commands. `title`
/// is the header line: a control character in it (newline, ...) is a pnc::InputError.
void write_data_file(const std::string& path, const System& s, const std::string& title);

/// HDF5 record of what was built and how (spec, seed, force field, counts, positions, box,
/// measured density and minimum distance, pnc version, time). Written atomically.
void write_build_record(const std::string& path, const System& s, const BuildSpec& spec,
                        const PolymerForceField& ff, const std::string& recipe_json);

/// What every build record holds, written into the open record `f` (the writers of each
/// force field add their /forcefield group and model-specific results): provenance, format
/// "pnc-rve-build", units (LAMMPS real), /recipe, /spec (chains, beads_per_chain, density
/// g/cm^3, seed, min_distance A, `method` in words), /result atoms, bonds, density (g/cm^3),
/// box (A: xlo ylo zlo xhi yhi zhi xy xz yz) and unwrapped positions (A).
void write_build_common(h5::File& f, const System& s, const BuildSpec& spec,
                        const std::string& recipe_json, const std::string& method);

} // namespace pnc::md
