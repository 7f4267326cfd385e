#pragma once
// pnc/md/box.hpp: deforming a LAMMPS simulation box by a deformation gradient F, the one
// routine every MD stage uses (the deformation cases, the equilibration's volume set-up, the
// phase check, the TI states of thermo/; decision D316, docs/theory.md section 3.4).
//
// Units: lengths and tilts in Angstrom (LAMMPS `real`), F dimensionless.
// LAMMPS box form: edges a = (Lx,0,0), b = (xy,Ly,0), c = (xz,yz,Lz) from the lower corner.
#include <Eigen/Dense>

#include <array>
#include <string>
#include <vector>

namespace pnc::md {

/// A LAMMPS box (Angstrom).
struct LmpBox {
  std::array<double, 3> lo{}, hi{};
  double xy = 0, xz = 0, yz = 0;
  /// {xlo, ylo, zlo, xhi, yhi, zhi, xy, xz, yz} as a case checkpoint keeps it; InputError naming
  /// `source` unless it has 9 values.
  static LmpBox from_vector(const std::vector<double>& v, const std::string& source);
  /// Columns a, b, c (Angstrom).
  Eigen::Matrix3d edges() const;
  /// Length along axis a (0, 1, 2), Angstrom.
  double length(int a) const {
    return hi[static_cast<std::size_t>(a)] - lo[static_cast<std::size_t>(a)];
  }
  /// Volume Lx Ly Lz (the tilts do not change it), Angstrom^3.
  double volume() const { return length(0) * length(1) * length(2); }
  /// {xlo, ylo, zlo, xhi, yhi, zhi, xy, xz, yz}: the layout from_vector reads.
  std::vector<double> to_vector() const {
    return {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], xy, xz, yz};
  }
};

/// The `change_box all ... remap units box` command that takes `ref` to the box of edges
/// F a, F b, F c with every length's centre kept, the atoms remapped affinely.
/// - F upper triangular (the box form): lengths F_ii L_i, tilts xy = F11 xy + F12 Ly,
///   xz = F11 xz + F12 yz + F13 Lz, yz = F22 yz + F23 Lz. A length or tilt F leaves unchanged
///   is not named, so it keeps its exact value (a value written back through %.15g could move
///   by one unit in the last place); "" when nothing changes.
/// - any other F: the box F H (H = edges) is brought to the box form by a rigid rotation, the
///   R of the QR factorisation F H = Q R with positive diagonal (no change of free energy or
///   stress invariants; D63); every length and tilt is named.
/// A tilt needs a triclinic box: the caller issues `change_box all triclinic` first.
/// InputError naming `source` for a non-finite F or one with det F <= 0 or a non-positive
/// stretch on the diagonal of an upper triangular F.
std::string box_change(const LmpBox& ref, const Eigen::Matrix3d& F,
                       const std::string& source = "<deformation gradient>");

} // namespace pnc::md
