#pragma once
// The point driver of `pnc material drive` (docs/drive.md): integrates one material point
// through the plugin's C ABI along a path of strain, stress or mixed control, solving the
// stress-controlled components by Newton with the law's own consistent tangent, and keeps
// the energy account (docs/decisions.md D167, D168).
#include "drive_path.hpp"

#include "pnc/fe_material/material.hpp"

#include <array>
#include <string>
#include <vector>

namespace pnc::app {

/// The point after one step (row 0: the virgin start). SI throughout.
struct DriveRecord {
  int step = 0, segment = 0;        ///< step 0 = start; segments counted from 1
  std::array<double, 6> strain{};   ///< 1, engineering shear; Voigt 11,22,33,23,13,12
  std::array<double, 6> stress{};   ///< Pa
  std::vector<double> state;        ///< the plugin's state variables (names in DriveResult)
  std::array<double, 36> tangent{}; ///< row-major d stress_i / d strain_j, Pa
  double work = 0;           ///< external work density: trapezoidal sum of stress . d strain, J/m^3
  double stored = 0;         ///< stored (elastic) energy density 1/2 stress . strain, J/m^3
  double dissipated = 0;     ///< dissipated energy density: sum of -1/2 eps.dC.eps, J/m^3 (D168)
  int newton_iterations = 0; ///< Newton corrections after the predictor (0: strain control)
  double newton_residual = 0; ///< max |stress - target| over the stress-controlled set, Pa
};

struct DriveResult {
  std::vector<std::string> state_names;
  std::vector<DriveRecord> rows;
  double residual_tolerance = 0; ///< Pa: newton_strain_tol x max |C0_ij|
  bool converged = true;         ///< false: stopped at a step whose Newton solve failed
  std::string failure;           ///< the message then (step, segment, residual, rule)
  int max_newton_iterations = 0;
  bool mixed = false; ///< some component was stress-controlled
};

/// The material actually driven: the card's material, or, when the path turns the platelet
/// frame, one built through the plugin from the card's constants with R = R_card Q.
pnc::fe_material::Material driven_material(const pnc::fe_material::Plugin& plugin,
                                           const pnc::fe_material::Material& card,
                                           const DrivePath& path);

/// Drives `m` along `path`. Never throws for a Newton failure: the rows up to the last good
/// step are returned with converged = false and the reason.
DriveResult drive(const pnc::fe_material::Material& m, const DrivePath& path);

} // namespace pnc::app
