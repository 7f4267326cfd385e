#pragma once
// pnc/damage/moduli.hpp: engineering moduli derived from the undamaged stiffness C0 and the
// NDM strengths per deformation case (docs/theory.md §1.5; the published moduli and strength
// tables). Units: those of the constants (Pa for a card); strains dimensionless.
#include "pnc/damage/ndm.hpp"

#include <optional>

namespace pnc::damage {

struct DerivedModuli {
  // By compliance inversion S = C0^-1 (the correct orthotropic moduli).
  double E1, E2, E3;
  double nu12, nu13, nu23, nu21, nu31, nu32; ///< nu_ij = -S_ji / S_ii
  double G23, G13, G12;
  /// The source's closed form for E2 as printed: det(C_n) / (C22 C33 - C23^2). It is
  /// E1 by inversion (docs/theory.md §1.5).
  double E2_as_printed;
  /// The source's isotropic formula (pure polymer, docs/theory.md §1.5): (C22^2 + C12 C22 - 2
  /// C12^2) / (C22 + C12), with C22 -> C11 of the card. Meaningful for the pp model; computed for
  /// both.
  double E_isotropic_formula;
};
DerivedModuli derive_moduli(const NdmParameters& p);

struct CaseStrength {
  int case_id;
  int component; ///< Voigt index of the stress reported
  /// the driven stress (units of the constants) at the first local maximum of its magnitude along
  /// the path, if any: negative for the negative shears 7-9 (D424)
  std::optional<double> peak;
  double strain_at_peak = 0.0; ///< load t of the case at the peak (dimensionless; t >= 0)
  double max_strain_searched;  ///< the path was followed up to this load t
};
/// Strength of the NDM in one deformation case: the first local maximum of the driven stress
/// component (times the case's `driven_sense`) along the monotonic case path (decision D5),
/// searched up to `max_strain` with `points` steps and then refined. No peak (monotonic stress) is
/// reported as such, never invented.
CaseStrength case_strength(const NdmParameters& p, int case_id, double max_strain = 1.0,
                           int points = 4000);

} // namespace pnc::damage
