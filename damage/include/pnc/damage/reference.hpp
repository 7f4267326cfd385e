#pragma once
// pnc/damage/reference.hpp: the dissertation's tabulated NDM constants (Tables 6.6-6.11,
// Nair 2010), converted to SI (Pa), with the choices documented in docs/decisions.md D9.
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

/// Deformation cases of docs/theory.md §2.1 (numbered as there):
/// 1-3 extension along x1..x3 with the lateral dimensions held, 4-6 simple shear 2-3, 1-3,
/// 1-2. For a case and an amount t (strain or engineering shear), the small-strain tensor
/// in engineering Voigt form.
struct DeformationCase {
  int id;
  const char* name;
  int driven;              ///< Voigt index 0..5 of the imposed strain component
  std::vector<int> active; ///< stress components the model makes non-zero
  int damage_mode;         ///< D index driven (docs/theory.md §2.1, D12): 0=D1, 1=D2, 2=D3
};
/// Throws pnc::InputError (naming `source`) for an id outside 1..6.
const DeformationCase& deformation_case(int id, const std::string& source = "<case>");
Voigt case_strain(int id, double amount);
/// The cases a model is characterised with: pnc 1..6, pp 2 and 6.
std::vector<int> model_cases(Model m);

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
