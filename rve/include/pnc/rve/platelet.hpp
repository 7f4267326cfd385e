#pragma once
// pnc/rve/platelet.hpp: a model nanocomposite, the glassy bead-spring polymer (bead_spring.hpp)
// with one embedded stiff platelet (recipe "model": "kg_platelet", section "platelet";
// decisions D170-D174).
//
// Units: LAMMPS `real` (A, fs, kcal/mol, g/mol); the platelet's parameters are given in the
// reduced units of the polymer (sigma, eps, eps/sigma^2), stated per field.
//
// The platelet (decision D170): `layers` square bead layers of `beads_side` x `beads_side`
// beads at spacing a = spacing_sigma sigma, in the x1-x3 plane (normal x2), stacked along x2 at
// the same spacing, centred in the cubic box; not spanning the box (its edge (beads_side - 1) a
// is at most 3/4 of the box edge at the build, decision D172). Atom type 2, molecule
// chains + 1, bead mass = the polymer's. Every pair of platelet beads at distance a (cube edge)
// or a sqrt(2) (face diagonal) is joined by a harmonic bond (LAMMPS bond_style harmonic,
// E = K (r - r0)^2, K = bond_K_reduced eps/sigma^2; bond types 2 and 3): a truss of cubes with
// braced faces, rigid with central forces (a single layer would have no bending stiffness,
// hence layers >= 2). The platelet's own LJ pairs are excluded (neigh_modify exclude type 2 2):
// its shape is its bonds'. Platelet-polymer: LJ 12-6 with eps_wp = epsilon_wp_reduced eps,
// sigma_wp = sigma_wp_sigma sigma, cut at cutoff_sigma sigma_wp (the adhesion, so that the
// interface can open: debonding). Why bonds, not a rigid body (fix rigid): decision D171.
#include "pnc/md/builder.hpp"
#include "pnc/rve/bead_spring.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pnc::rve {

struct PlateletSpec {
  int beads_side = 7;              ///< beads along x1 and along x3
  int layers = 2;                  ///< bead layers along x2 (2..4)
  double spacing_sigma = 1.0;      ///< lattice spacing a, in sigma
  double epsilon_wp_reduced = 1.0; ///< platelet-polymer LJ well depth, in eps
  double sigma_wp_sigma = 1.0;     ///< platelet-polymer LJ diameter, in sigma
  double bond_K_reduced = 300.0;   ///< harmonic K of the platelet bonds, in eps/sigma^2
  /// builder: no polymer bead centre closer than this to a platelet bead centre, in sigma
  double min_distance_sigma = 1.0;

  /// Throws pnc::InputError (source, field "platelet.<name>", value, rule) for values outside:
  /// beads_side 2..60, layers 2..4, spacing_sigma [0.8, 1.2], epsilon_wp_reduced (0, 5],
  /// sigma_wp_sigma [0.8, 1.5], bond_K_reduced [10, 2000], min_distance_sigma [0.8, 1.5] and
  /// >= the polymer's build.min_distance / sigma.
  void validate(const std::string& source) const;
};

/// The cubic box edge (A) of the composite: (polymer beads + platelet beads) x bead_mass at
/// spec.density (decision D172: every bead, polymer or platelet, counts at the build density).
double kg_platelet_box(const md::BuildSpec& spec, const BeadSpringForceField& ff,
                       const PlateletSpec& p);
/// The rules of D172 on the box: platelet edge <= 3/4 of the box edge and leaving >= 2 sigma of
/// polymer between the platelet and its periodic image; thickness <= box / 2; the box edge >
/// twice the largest LJ cutoff. Throws an InputError naming `source` and field
/// "platelet.beads_side" (or "build.chains").
void check_kg_platelet_box(const md::BuildSpec& spec, const BeadSpringForceField& ff,
                           const PlateletSpec& p, const std::string& source);

struct PlateletInfo {
  int platelet_beads = 0, polymer_beads = 0, platelet_bonds = 0;
  double edge_A = 0, thickness_A = 0; ///< bead-centre extents along x1 (= x3) and x2
  double box_A = 0;                   ///< cubic box edge at the build
  double volume_fraction = 0;         ///< platelet beads / all beads (each one bead volume)
  double omega_bound_per_fs = 0;      ///< rigorous upper bound of the network's frequencies
};

/// The platelet alone (atoms 0..n-1 of the result, type 2, molecule `mol`, bonds types 2, 3),
/// centred at `centre` (A). Positions unwrapped.
md::System build_platelet(const PlateletSpec& p, const BeadSpringForceField& ff,
                          const std::array<double, 3>& centre, int mol);
/// The composite: the platelet at the box centre, then the chains grown around it (the random
/// walk of build_bead_spring, a trial bead also rejected when closer than min_distance_sigma
/// sigma to a platelet bead). Deterministic for a given spec.
md::System build_kg_platelet(const md::BuildSpec& spec, const BeadSpringForceField& ff,
                             const PlateletSpec& p, PlateletInfo* info = nullptr);

/// Upper bound of the angular frequencies (1/fs) of the platelet's bond network with its
/// beads of mass ff.bead_mass: omega^2 <= 2 max_i lambda_max(sum over i's bonds of k e e^T) / m
/// with k = 2 K (the stiffness matrix of a bond, k e e^T (x) [[1,-1],[-1,1]], is <= 2 its
/// diagonal blocks). Decision D173: omega_bound x timestep <= 1 (Verlet is stable below 2).
double platelet_omega_bound(const md::System& platelet, const PlateletSpec& p,
                            const BeadSpringForceField& ff);
/// Smallest minimum-image distance (A) between a polymer bead (type 1) and a platelet bead
/// (type 2).
double min_polymer_platelet_distance(const md::System& s);

/// LAMMPS commands of the composite (re-issued after every read_restart): LJ between all types
/// with the platelet-polymer pair's own coefficients, platelet pairs excluded, bond_style
/// hybrid fene harmonic (type 1 the polymer's FENE, 2 and 3 the platelet's edges and
/// diagonals), special_bonds lj 0 1 1.
std::vector<std::string> kg_platelet_commands(const BeadSpringForceField& ff,
                                              const PlateletSpec& p);
/// The push-off's pair commands (decision D174): soft between polymer beads (pair_style
/// hybrid, its prefactor ramped by `fix adapt ... pair soft a 1 1`), the full platelet-polymer
/// LJ from the start (the build keeps every polymer bead >= min_distance_sigma from the
/// platelet, so no chain is pushed through it).
std::vector<std::string> kg_platelet_pushoff_pair(const BeadSpringForceField& ff,
                                                  const PlateletSpec& p, double soft_A);

/// The build's record next to build.h5 (platelet.json): counts, sizes, fractions, the
/// frequency bound, the smallest polymer-platelet distance.
nlohmann::json platelet_info_json(const PlateletInfo& i, const PlateletSpec& p,
                                  const BeadSpringForceField& ff, double min_polymer_platelet_A);

} // namespace pnc::rve
