#pragma once
// pnc/damage/cases.hpp: the deformation cases, one registry row per case (docs/theory.md
// section 2.1; decision D316). Everything that needs to know a case (the MD driver in rve/
// that deforms the box, the fit's labels and active components, the synthetic data, the
// readers' id checks and their messages) reads it from here, so a new case is one row.
//
// A case is driven by a load parameter t (dimensionless: a strain for extension, an
// engineering shear for shear). Its deformation gradient is F(t) = I + t G with G a constant
// 3x3 matrix (`gradient`), imposed on the reference box; the small-strain tensor of F in
// engineering Voigt form (order 11, 22, 33, 23, 13, 12) is `case_strain`.
//
// A row carries the SET of strain components its gradient drives (D360): one for the nine
// registered uniaxial-extension and simple-shear cases (rows 7-9 are the shears of rows 4-6 in
// the negative sense, gamma = -t, D424), two for an equibiaxial extension
// (G = e_1 e_1 + e_2 e_2), and so on. What only deforms the box (md::box_change of F(t), the
// strain path) works for any set; what plots or fits one stress against one strain (the NDM
// fit, strengths, reports, replica slopes) asks for `single_driven`, which refuses a mixed
// case by name instead of silently taking its first component.
#include "pnc/damage/ndm.hpp"

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace pnc::damage {

struct DeformationCase {
  int id;           ///< 1-based id used in files (cases.h5 /case_<id>, CSV `case`)
  const char* name; ///< words for reports, e.g. "simple shear 1-2"
  /// Voigt indices 0..5 of the imposed (driven) strain components, ascending, at least one:
  /// the components whose stresses are reported against t; exactly the non-zero entries of
  /// case_strain(c, 1), each +1 or -1 (`driven_sense`; D360, D424)
  std::vector<int> driven;
  std::vector<int> active; ///< stress components (Voigt 0..5) the model makes non-zero
  int damage_mode;         ///< D index driven (docs/theory.md §2.1, D12): 0=D1, 1=D2, 2=D3
  /// dF/dt, dimensionless; upper triangular (the LAMMPS box tilts xy, xz, yz are the
  /// entries (0,1), (0,2), (1,2)): extension along a is e_a e_a, simple shear a-b is e_a e_b,
  /// its negative sense -e_a e_b
  Eigen::Matrix3d gradient;
};

/// Every registered case, in id order.
const std::vector<DeformationCase>& deformation_cases();
/// The case with this id; throws pnc::InputError naming `source`, the value and the
/// registered ids for any other id.
const DeformationCase& deformation_case(int id, const std::string& source = "<case>");
/// true when `id` names a registered case.
bool is_deformation_case(int id);
/// "deformation case must be an integer 1..9 (1 extension x1 ..., ...)": the rule readers print.
std::string deformation_case_rule();

/// F(t) = I + t G of a case (dimensionless).
Eigen::Matrix3d deformation_gradient(const DeformationCase& c, double t);
/// The small-strain tensor sym(F - I) of case `c` at load t in engineering Voigt form
/// (dimensionless; shear entries are engineering shears).
Voigt case_strain(const DeformationCase& c, double amount);
/// case_strain of the registered case `id`.
Voigt case_strain(int id, double amount);
/// The one driven Voigt component of `c`, for code that relates one stress to one strain
/// (`user` says which: "NDM fit", "case strength", ...). Throws pnc::InputError naming the
/// case id and name, its driven components, `user` and the rule "`user` knows only cases with
/// one driven component (uniaxial extension or simple shear)" when the row drives several (D360).
int single_driven(const DeformationCase& c, const std::string& user);
/// The sense in which t drives the case: +1 when its driven strains grow with t (rows 1-6), -1
/// when they fall (the negative shears 7-9, D424). A quantity read "along the case" (a strength,
/// a stress that must be positive before damage) is the driven stress times this sense.
double driven_sense(const DeformationCase& c);
/// true when every driven component of `c` is a normal strain (a uniaxial or an equibiaxial
/// extension; D360).
bool is_extension(const DeformationCase& c);
/// true when `c` drives exactly one component and it is a normal strain (a uniaxial extension,
/// the cases that give C11/C12 and their damage constants; D362).
bool is_uniaxial_extension(const DeformationCase& c);
/// The cases a model is characterised with: pnc 1..6, pp 2 and 6.
std::vector<int> model_cases(Model m);

} // namespace pnc::damage
