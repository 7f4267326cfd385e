#pragma once
// pnc/gimp_coupler/escm_crack.hpp: ESCM Cases II and III (the source's crack
// cases; docs/escm.md "Cases II and III"; decisions D80-D84 in docs/decisions.md): an edge
// pre-crack in the continuum on the line through the centre of the atom block, growing toward
// the block by the J-integral criterion of the GIMP solver (D38-D40) and stopped at the outer
// boundary of the SVC ring (D81), and the atomistic separation of the MD region across the
// same line (D82).
//
// Units: continuum SI (m); the atomistic quantities in LAMMPS `real` (Angstrom) as their names
// say (_A), in the LAMMPS frame of the Coupler.
#include "pnc/gimp_coupler/escm.hpp"

#include <Eigen/Core>

#include <vector>

namespace pnc::gimp::escm {

/// Edge pre-crack of Cases II/III (D80, D81): a straight crack along +x at height y_line (m)
/// from the mouth x = -h (outside the body, not a tip) to the tip x_tip (m), growing along +x
/// (prescribed direction, D80) by increments of h when J >= Gc (J/m^2), and stopped after
/// `max_increments` increments (the last tip position lies in the cell column just before the
/// SVC ring, D81).
Crack line_edge_crack(double y_line, double x_tip, double h, double Gc, int max_increments);

/// Atomistic separation across the crack line at one instant (D82), Angstrom.
struct AtomisticCrack {
  int bonds = 0;             ///< nearest-neighbour bonds of free atoms (IVC, INT) across the line
  int broken = 0;            ///< those longer than the LJ inflection distance
  int columns = 0;           ///< cell columns of the free region along the line
  int separated_columns = 0; ///< contiguous from the entry side, >= half of their bonds broken
  double length_A = 0.0;     ///< separated_columns x cell size
  double entry_opening_A = 0.0;   ///< opening of the atom rows next to the line, entry column
  double entry_sliding_A = 0.0;   ///< sliding (upper - lower, x) of the same rows, entry column
  double max_opening_A = 0.0;     ///< largest column opening
  double max_abs_sliding_A = 0.0; ///< largest column |sliding|
  /// Contiguous from the entry side, |sliding| of the column >= the slip distance (D91: a0/2,
  /// halfway between equivalent registries of the (010) layers along x, past the saddle).
  int slipped_columns = 0;
};

/// Watches the atom pairs across the crack line (D82). The line y_line_A and the cell columns
/// (width cell_A from x_entry_A, the entry side of the free region) are in the LAMMPS frame.
/// Bonds: pairs of free atoms (zones IVC or INT) whose initial positions lie on opposite sides
/// of the line within r_bond_A (minimum image through the periodic slab). A bond is broken when
/// it is longer than r_break_A. Rows: the free atoms within half a row spacing (a0/4) of the
/// line on either side; their mean displacements per column give the opening and sliding. A
/// column has slipped when |sliding| >= slip_A (D91; 0: never).
class BondMonitor {
public:
  BondMonitor(const Coupler& cp, double y_line_A, double x_entry_A, double cell_A, double r_bond_A,
              double r_break_A, double slip_A = 0.0);
  /// The state for atom positions x (Angstrom, index id - 1, as Coupler::atoms()).
  AtomisticCrack measure(const std::vector<Eigen::Vector3d>& x) const;

private:
  struct Bond {
    int a = 0, b = 0, column = 0;
  };
  std::vector<Bond> bonds_;
  std::vector<int> row_atom_, row_side_, row_column_; // +1 above, -1 below
  std::vector<Eigen::Vector3d> x0_;
  int columns_ = 0;
  double Lz_ = 0.0, r_break_ = 0.0, cell_ = 0.0, slip_ = 0.0;
};

/// The LJ pair's inflection distance (26/7)^(1/6) sigma: beyond it the pair force falls with
/// stretch (D82).
double lj_inflection(double sigma_A);

} // namespace pnc::gimp::escm
