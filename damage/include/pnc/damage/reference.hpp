#pragma once
// pnc/damage/reference.hpp: the dissertation's tabulated NDM constants (Tables 6.6-6.11,
// Nair 2010), converted to SI (Pa), with the choices documented in docs/decisions.md D9.
#include "pnc/damage/cases.hpp" // the deformation cases, formerly declared here
#include "pnc/damage/ndm.hpp"

namespace pnc::damage {

/// The published constant tables as one parameter set (decision D9) (Pa; alpha dimensionless).
/// pnc: C0 as used in the source's E2 formula (docs/theory.md §1.5; which published table each
///      C_ij comes from: D9), C44 (from its table), C55 (case 5 text), A's as labelled (2A1 = -0.99
///      -> A1 = -0.495, ...), A26 = 0 (case 5). Case 6 was not fitted in the dissertation: C66 and
///      A24 are NOT printed and are set to C44 and A22 (decision D9).
/// pp : C11 = C22 = 0.559, C12 = 0.447 (Table 6.10), C44 = C66 = 0.109, damage slopes as
///      printed per row: diagonal 2 B1 = -0.405 (row "2B2", sigma22), off-diagonal B2 = -0.304
///      (row "B1", sigma11), B4 = -0.757 (Table 6.11), alpha = 0.941 (decision D9).
NdmParameters dissertation_parameters(Model m);

} // namespace pnc::damage

namespace pnc::damage {
/// The printed regression of Tables 6.6-6.11 for one (case, stress component): the two
/// properties the dissertation regressed from it, with their printed labels, values (Pa)
/// and R^2 (NaN where not printed). Compare with RegressionLine of the same case/component.
struct PrintedRegression {
  int case_id;
  int component;         ///< Voigt index
  const char* lin_label; ///< as printed, e.g. "C0_22"
  double lin_value, lin_r2;
  const char* dam_label; ///< as printed, e.g. "2A5", "B1"
  double dam_value, dam_r2;
};
const std::vector<PrintedRegression>& printed_regression(Model m);
} // namespace pnc::damage
