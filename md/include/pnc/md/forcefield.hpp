#pragma once
// pnc/md/forcefield.hpp: the coarse-grained polypropylene force field of Nair (2010)
// (docs/theory.md §3.1; after Wei et al. 2002) and its mapping onto LAMMPS styles.
//
// Units: LAMMPS `real` throughout rve/ -- Angstrom, fs, kcal/mol, g/mol, atm, K.
//
// Physical forms (docs/theory.md §3.1), with the parameters stored here as printed
// (after the unit reading of decision D13, converted to kcal/mol):
//   E_bond  = k_l/2 (l - l0)^2                 -> bond harmonic        K = k_l/2
//   E_angle = k_theta/2 (cos th - cos th0)^2   -> angle cosine/squared K = k_theta/2
//   E_tors  = sum_{n=0..3} C_n cos^n(omega), omega = 0 trans (polymer convention)
//                                              -> dihedral multi/harmonic with LAMMPS's
//                                                 phi = omega + 180 deg: A_n = (-1)^(n-1) C_(n-1)
//   E_LJ    = 4 eps ((s/r)^12 - (s/r)^6), r < r_c, not shifted, no tail correction
//                                              -> pair lj/cut
// Non-bonded exclusions: special_bonds lj 0 0 0 (1-2, 1-3, 1-4 excluded; decision D14).
#include "pnc/core/units.hpp"
#include <array>
#include <string>
#include <vector>

namespace pnc::md {

constexpr double kcal_per_kJ = units::joule_per_kj / units::joule_per_kcal;
constexpr double pa_per_atm = units::pa_per_atm;
/// N_A * 1e-24 (g/cm3 <-> g/mol/A^3)
constexpr double avogadro_per_A3_cm3 = units::avogadro * 1e-24;

struct PolymerForceField {
  double bead_mass = 21.0;              ///< g/mol
  double k_l = 346.0 * kcal_per_kJ;     ///< kcal/mol/A^2 (printed 346 kJ/mol/A^2)
  double l0 = 1.53;                     ///< A
  double k_theta = 520.0 * kcal_per_kJ; ///< kcal/mol (printed "520 J/mol", read kJ/mol)
  double theta0_deg = 112.813;          ///< deg
  std::array<double, 4> C = {8.832 * kcal_per_kJ, 18.087 * kcal_per_kJ, 4.880 * kcal_per_kJ,
                             -31.800 * kcal_per_kJ}; ///< kcal/mol (printed "8, 832 J/mol")
  double epsilon = 0.498 * kcal_per_kJ; ///< kcal/mol (printed "0.498 J/mol", read kJ/mol)
  double sigma = 2.95;                  ///< A
  double cutoff_sigma = 2.5;            ///< LJ cutoff in units of sigma
  double cutoff() const { return cutoff_sigma * sigma; }

  /// Coefficients exactly as LAMMPS takes them (real units).
  double lammps_bond_K() const { return 0.5 * k_l; }
  double lammps_angle_K() const { return 0.5 * k_theta; }
  std::array<double, 5> lammps_dihedral_A() const; ///< A1..A5 of multi/harmonic

  /// Throws pnc::InputError (source `source`, field names as in recipes) for non-physical values.
  void validate(const std::string& source) const;
};

/// LAMMPS commands defining the polymer force field for atom type `type` (bond/angle/
/// dihedral type 1). `pair_style` is hybrid-free lj/cut; the clay (clay.hpp) adds types.
std::vector<std::string> polymer_forcefield_commands(const PolymerForceField& ff);

} // namespace pnc::md
