#pragma once
// pnc/rve/clay.hpp: the montmorillonite platelet (docs/theory.md §3.2, D23) and the
// polymer-nanoclay composite RVE built around it.
//
// Units: LAMMPS `real` (A, g/mol, kcal/mol); densities g/cm^3; fractions dimensionless.
//
// Crystal (Table 3.1, after Toth et al. 2004): C2/m, a = 5.20, b = 9.20, c = 10.13 A,
// beta = 99 deg. The asymmetric unit is expanded with the C-centring (1/2,1/2,0) and the 2/m
// operations (x,y,z), (-x,y,-z), (-x,-y,-z), (x,-y,z); duplicates (periodic tolerance 1e-3 in
// fractional coordinates) are removed. One t-o-t layer is the cell with z wrapped to
// [-1/2, 1/2): Si8 Al4 O24 H4 = 2 Al2Si4O10(OH)2 (no interlayer cations: fully exfoliated).
// Crystal frame: X = xi a + zeta c cos(beta), Y = eta b, Z = zeta c sin(beta); box frame
// (platelet along x1, width along x3, layer normal along x2): x1 = X, x3 = Y, x2 = -Z.
//
// Label mapping (decision D23): Table 6.2-6.4 use "O1" = octahedral oxygen and "O2" =
// surface oxygen. In Table 3.1 the octahedral (apical) oxygens are O3 and OH (zeta ~ 0.11,
// bonded to Al) and the surface (basal) oxygens are O1 and O2 (zeta ~ 0.33, above Si at
// 0.27). Topology by distance: Al-O(oct) < 2.4 A, O(OH)-H < 1.3 A, Si-O < 1.9 A.
//
// Force field (Tables 6.2-6.5, forms without 1/2) -> LAMMPS:
//   bond harmonic K = kl as printed; angle cosine/squared K = k as printed (O1-Al-O1 split in
//   a 90 deg and a 180 deg type by the built angle, < 135 deg -> 90); torsion O2-Si-O1-Al
//   V[1 + cos(n phi - delta)] with n = 0, delta = 0 -> the constant 2V, kept as dihedral
//   multi/harmonic A1 = 2V (energy as printed, no force); pair lj/cut with the cross terms of
//   Table 6.5 as given (no mixing), per-pair cutoff cutoff_sigma * sigma_ij; H has eps = 0.
//   No charges, no Coulomb (none are listed).
#include "pnc/md/builder.hpp"
#include "pnc/md/forcefield.hpp"

#include <array>
#include <string>
#include <vector>

namespace pnc::rve {

/// Atom types of the composite data file.
enum ClayAtomType { type_C = 1, type_Si = 2, type_Al = 3, type_O = 4, type_H = 5 };
/// Bond types: 1 polymer, then Table 6.2.
enum ClayBondType { bond_Al_O1 = 2, bond_O1_H = 3, bond_Si_O2 = 4, bond_Si_O1 = 5 };
/// Angle types: 1 polymer, then Table 6.3.
enum ClayAngleType {
  angle_Al_O1_H = 2,
  angle_Si_O1_Al = 3,
  angle_O2_Si_O1 = 4,
  angle_Al_O1_Al = 5,
  angle_O1_Al_O1_90 = 6,
  angle_O1_Al_O1_180 = 7
};
constexpr int dihedral_O2_Si_O1_Al = 2;

/// Table 3.1 site labels and fractional coordinates (asymmetric unit).
struct ClaySite {
  std::string label; ///< Al, O1, O2, O3, OH, H, Si (Table 3.1)
  std::array<double, 3> frac;
};
const std::vector<ClaySite>& clay_asymmetric_unit();
/// The C2/m expansion of the asymmetric unit: one cell, z in [-1/2, 1/2), duplicates removed.
std::vector<ClaySite> clay_unit_cell();

struct ClayLattice {
  double a = 5.20, b = 9.20, c = 10.13, beta_deg = 99.0; ///< A, deg (Table 3.1)
};

/// Table 6.2-6.5 parameters (kcal/mol, A, deg), as printed.
struct ClayForceField {
  // bonds: {l0, kl}
  std::array<double, 2> Al_O1{1.955, 382.617}, O1_H{0.988, 827.209}, Si_O2{1.626, 492.387},
      Si_O1{1.62, 558.593};
  // angles: {theta0 (deg), k}
  std::array<double, 2> Al_O1_H{118, 34.933}, Si_O1_Al{124.5, 155.754}, O2_Si_O1{110.6, 97.493},
      Al_O1_Al{109.5, 198.27}, O1_Al_O1_90{90, 80.0}, O1_Al_O1_180{180, 80.0};
  double torsion_V = 0.722; ///< O2-Si-O1-Al, n = 0 (constant 2V)
  /// Table 6.5 {sigma, eps} per pair of (C, Si, Al, O); H: eps = 0.
  std::array<double, 2> O_O{2.86, 0.228}, Si_Si{4.05, 0.04}, Al_Al{4.05, 0.04}, C_O{3.33, 0.094},
      C_Al{3.96, 0.0395}, C_Si{3.96, 0.0395}, O_Si{3.404, 0.0955}, O_Al{3.404, 0.0955},
      Si_Al{4.053, 0.04};
  double cutoff_sigma = 2.5; ///< per-pair LJ cutoff in units of sigma_ij
  /// {sigma, eps} of a type pair (types ClayAtomType; C-C from the polymer force field).
  std::array<double, 2> lj(int ti, int tj, const md::PolymerForceField& pff) const;
};

/// Element masses (g/mol) of the types 2..5.
double clay_type_mass(int type);

/// A platelet of cells_a x cells_b cells in the box frame (not yet placed in a box).
struct Platelet {
  std::vector<std::array<double, 3>> x;        ///< A, box frame, centred at the origin
  std::vector<int> type;                       ///< ClayAtomType
  std::vector<std::string> site;               ///< Table 3.1 label
  std::vector<std::array<int, 3>> bonds;       ///< ClayBondType, i, j (0-based)
  std::vector<std::array<int, 4>> angles;      ///< ClayAngleType, i, j, k
  std::vector<std::array<int, 5>> dihedrals;   ///< type 2, i, j, k, l
  double length = 0, width = 0, thickness = 0; ///< A: cells_a a, cells_b b, atom-centre extent
  int removed_isolated = 0; ///< edge atoms without any bond, removed (finite platelet only)
  double mass() const;      ///< g/mol
  double bounding_volume() const { return length * width * thickness; } ///< A^3
};

/// Builds the layer. `periodic`: bonds across the in-plane cell boundaries (a test of the
/// infinite layer; the atoms are then all kept); otherwise a finite platelet whose edge atoms
/// with no bond are removed.
Platelet build_platelet(int cells_a, int cells_b, bool periodic = false,
                        const ClayLattice& lat = {});

struct ClaySpec {
  int cells_a = 7;           ///< cells along x1 (crystal a)
  int cells_b = 1;           ///< cells along x3 (crystal b)
  double aspect_ratio = 0;   ///< > 0: cells_a = round(aspect_ratio cells_b b / a) (recipe)
  double min_distance = 3.0; ///< A, smallest polymer bead - clay atom distance at the build
  double gap_x = 10.0;       ///< A, box length along x1 = platelet length + gap_x
  void validate(const std::string& source) const;
};

struct CompositeInfo {
  int clay_atoms = 0, polymer_beads = 0;
  double clay_mass = 0, polymer_mass = 0; ///< g/mol
  double clay_volume = 0, box_volume = 0; ///< A^3 (platelet bounding volume, box)
  double volume_fraction = 0;             ///< clay_volume / box_volume
  double weight_fraction = 0;             ///< W_clay / (W_clay + W_PP)
  double length = 0, width = 0, thickness = 0, aspect_ratio = 0; ///< platelet, A
};

/// Box for the composite: Lx = length + gap_x, Ly = Lz with Lx Ly Lz = polymer volume at
/// `spec.density` + platelet bounding volume. Throws InputError (fields clay.*) when the
/// platelet does not fit.
std::array<double, 3> composite_box(const md::BuildSpec& spec, const md::PolymerForceField& ff,
                                    const ClaySpec& clay, const std::string& source);

/// Platelet centred in the box (clay atoms first, molecule chains + 1), then the chains
/// grown around it (no bead closer than clay.min_distance to a clay atom).
md::System build_composite(const md::BuildSpec& spec, const md::PolymerForceField& ff,
                           const ClaySpec& clay, CompositeInfo* info = nullptr);

/// Smallest minimum-image distance between a polymer bead (type 1) and a clay atom.
double min_polymer_clay_distance(const md::System& s);

/// LAMMPS commands for the composite (5 atom types, 5 bond, 7 angle, 2 dihedral types),
/// plus the groups pnc_clay (types 2-5) and pnc_poly (type 1).
std::vector<std::string> composite_forcefield_commands(const md::PolymerForceField& ff,
                                                       const ClayForceField& cff = {});

} // namespace pnc::rve
