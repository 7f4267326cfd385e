#pragma once
// pnc/gimp_coupler/escm_lj.hpp: zero-temperature elastic constants of a Lennard-Jones FCC
// crystal from lattice sums, used to calibrate the continuum against an LJ crystal MD region
// (ESCM validation, docs/escm.md, decision D76).
//
// phi(r) = 4 eps ((s/r)^12 - (s/r)^6) for r < rc (LAMMPS lj/cut, no shift). The lattice
// constant a0 solves zero pressure, sum_j phi'(r_j) r_j = 0 over the neighbours of one atom;
// the Born constants at a0 (Green strain, 2nd Piola-Kirchhoff) are
//   C_ijkl = 1 / (2 Omega) sum_j (phi''(r) - phi'(r) / r) r_i r_j r_k r_l / r^2,
// Omega = a0^3 / 4 the volume per atom.
// Units: input LAMMPS real (kcal/mol, Angstrom, g/mol); output Pa, Angstrom, kg/m^3.

#include <string>
#include <vector>

namespace pnc::gimp::escm {

struct LjFcc {
  double a0_A = 0.0;    ///< zero-pressure lattice constant, Angstrom
  double C11 = 0.0;     ///< Pa
  double C12 = 0.0;     ///< Pa
  double C44 = 0.0;     ///< Pa
  double density = 0.0; ///< kg/m^3
  /// Plane-strain isotropic calibration matching the in-plane normal stiffnesses:
  /// lambda = C12, mu = (C11 - C12) / 2 (D76). Young's modulus (Pa) and Poisson's ratio.
  double E() const;
  double nu() const;
  /// Small-strain stiffness of a plane-strain strip in uniaxial tension with free lateral
  /// faces: C11 - C12^2 / C11 (Pa).
  double strip_modulus() const { return C11 - C12 * C12 / C11; }
};

/// Lattice sums for the FCC crystal (throws std::invalid_argument for non-positive input or
/// rc below the nearest-neighbour distance).
LjFcc lj_fcc(double eps_kcalmol, double sigma_A, double rc_A, double mass_gmol);

/// LAMMPS commands (units real) that create an nx x ny x nz block of FCC unit cells of lattice
/// constant `lj.a0_A`, sites from -a0/4 on x and y (shrink-wrapped x, y; periodic z, D78),
/// `types` atom types (all atoms type 1; every type of mass `mass_gmol` and every pair lj/cut
/// with `eps_kcalmol`, `sigma_A`, `rc_A`). The commands for the Coupler's `Config::md_setup`;
/// the caller may append commands (e.g. the weak interface of the crack cases, D83).
std::vector<std::string> lj_fcc_block_commands(const LjFcc& lj, int nx, int ny, int nz,
                                               double mass_gmol, double eps_kcalmol, double sigma_A,
                                               double rc_A, int types = 1);

/// Work of separation of the perfect crystal across a (010) plane midway between two atom
/// layers, unrelaxed, J/m^2: -(sum over the pairs crossing it of phi(r)) per unit area (D83).
/// Twice the unrelaxed (010) surface energy.
double lj_fcc_separation_work(const LjFcc& lj, double eps_kcalmol, double sigma_A, double rc_A);

} // namespace pnc::gimp::escm
