#pragma once
// pnc/gimp_coupler/escm_polymer.hpp: the coarse-grained polypropylene MD region of the ESCM
// coupled runs (the source's ESCM cases; docs/escm.md "Polymer MD region"; decisions D100-D108).
//
// A thin polymer slab, periodic in z, with free x/y surfaces, aligned with the continuum grid:
//  1. chains grown with the md/ builder (pnc::md::grow_chains, force field
//     pnc::md::PolymerForceField with its defaults) in a periodic box of nbx x nby cells of
//     `cell_A` and thickness `slab_A` at `density` (D100);
//  2. stage "polymer/relax" (a child process, pnc::md::run_stage): minimisation, optional
//     NPT anneal at `temperature` cooled to 1 K (`anneal_ps`), box relaxation towards zero
//     stress (x, y coupled; z free; bounded, D107); the continuum cell size is the relaxed
//     box length / cells (D101); the static relaxed elastic constants C11, C22, C12, C21 from
//     +-strain_probe box strains with the atoms re-minimised (D102);
//  3. the bonds, angles and dihedrals crossing the x/y periodic faces are cut, and in neumann
//     mode also those joining an SVC atom to a free (IVC/INT) atom (D103); the box becomes
//     `boundary s s p`;
//  4. stage "polymer/surface": minimisation with the SVC atoms held, free surfaces relaxed
//     (D104), repeated with the zones of the relaxed positions until no atom changes zone
//     (D107); every SVC/IVC cell must hold at least `min_beads_per_cell` beads (D105).
//  With interface_row >= 0 (Cases II/III, D114) steps 3 and 4 also cut the bonded terms that
//  cross the line y = interface_row h (by the relaxed positions, repeated with the zones) and
//  type the beads above it 2, weakly bonded to those below.
// The build minimisations use the energy shifted to zero at the cut-off (forces unchanged, as in
// the coupler, D93): with the jump at r_c the CG line searches stop far from a minimum (D107).
// Units: LAMMPS real (Angstrom, g/mol, kcal/mol, K) in and out of LAMMPS; elastic constants Pa,
// density kg/m^3, cell size m.
#include "pnc/md/forcefield.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace pnc::gimp::escm {

struct PolymerBlockSpec {
  int nbx = 10, nby = 10;           ///< block cells along x, y
  int svc_rings = 2, ivc_rings = 1; ///< volume-cell rings (zones for D103/D104)
  bool neumann = true;              ///< D103: cut SVC-free bonded terms (neumann mode)
  double cell_A = 6.0;              ///< cell size at the build density, A
  double slab_A = 16.0;             ///< slab thickness at the build density, A
  double density = -1;              ///< build density g/cm^3 (< 0: md::BuildSpec default)
  int beads_per_chain = -1;         ///< < 0: md::BuildSpec default
  std::uint64_t seed = 1;           ///< builder and velocity seed
  double temperature = 300.0;       ///< K, NPT anneal temperature (if anneal_ps > 0)
  double anneal_ps = 0.0;           ///< NPT anneal at T (half) then cooled to 1 K (half)
  double anneal_timestep_fs = 1.0;  ///< fs
  int min_beads_per_cell = 4;       ///< D105
  double strain_probe = 1e-2;       ///< D102
  bool measure_elastic = true;      ///< D102 (else elastic constants given by the user)
  pnc::md::PolymerForceField ff;    ///< md/ defaults (sigma, epsilon, cutoff_sigma overridable)
  /// Cases II/III (D114): >= 0 puts a weak interface on the line y = interface_row x h across
  /// the whole block: no bonded term crosses it (cut, like the faces) and the beads above it
  /// are atom type 2 with LJ epsilon x interface_fraction to type 1 (the same sigma).
  int interface_row = -1;
  double interface_fraction = 1.0;
};

struct PolymerBlock {
  std::string data_file;             ///< the cut, relaxed block (atom_style molecular)
  std::vector<std::string> md_setup; ///< commands for Config::md_setup (read_data + force field)
  double h_A = 0.0;                  ///< continuum cell size, A (relaxed box length / cells)
  double Lz_A = 0.0;                 ///< slab thickness after relaxation, A
  double density_kg_m3 = 0.0;        ///< of the relaxed periodic box
  double build_density = 0.0;        ///< g/cm^3
  int atoms = 0, chains = 0, beads_per_chain = 0;
  // D102 (Pa): C_ab = d sigma_a / d eps_b of the relaxed periodic box at 0 K
  double C11 = 0, C22 = 0, C33 = 0, C12 = 0, C21 = 0, C31 = 0, C32 = 0;
  double lambda = 0,
         mu = 0; ///< isotropic plane-strain fit: lambda+2mu = (C11+C22)/2, lambda = (C12+C21)/2
  double pressure_atm = 0.0; ///< virial pressure of the relaxed periodic box (0 K)
  double pxx_atm = 0, pyy_atm = 0, pzz_atm = 0;
  int cut_periodic_bonds = 0, cut_periodic_angles = 0, cut_periodic_dihedrals = 0;
  int cut_svc_bonds = 0, cut_svc_angles = 0, cut_svc_dihedrals = 0;
  int cut_interface_bonds = 0, cut_interface_angles = 0, cut_interface_dihedrals = 0; ///< D114
  double interface_y_A = -1.0; ///< the weak interface's y in the block frame (D114), A
  int moved_zone = 0;          ///< atoms whose zone changed in the first surface minimisation
  int moved_zone_last = 0; ///< ... in the last pass (0: the zones are those of the minimum, D107)
  int surface_passes = 0;  ///< surface minimisations run (re-zoned after each, D107)
  double surface_fmax = 0, surface_fnorm = 0; ///< residual force of the block read by the coupler,
                                              ///< kcal/mol/A (max component, 2-norm)
  int min_cell_beads = 0, max_cell_beads = 0; ///< over the SVC/IVC cells
  double mean_cell_beads = 0.0;
  double relax_s = 0.0, surface_s = 0.0, total_s = 0.0; ///< wall time of the stages
};

/// Builds the block in `dir` (files polymer_build.data, polymer_cut.data, polymer_block.data,
/// polymer_relax.log, polymer_surface.log). Errors in the input are pnc::InputError naming
/// `source` and the key `md.<name>`; a failed LAMMPS stage throws std::runtime_error with
/// LAMMPS's ERROR line. Runs LAMMPS only in child processes.
PolymerBlock build_polymer_block(const PolymerBlockSpec& spec, const std::string& dir,
                                 const std::string& source);

/// Mean beads per cell of the spec (density x cell_A^2 x slab_A / bead mass).
double expected_beads_per_cell(const PolymerBlockSpec& spec);

} // namespace pnc::gimp::escm
