#pragma once
// The path file of `pnc material drive` (docs/drive.md): a sequence of segments, each
// driving every Voigt component either in strain or in stress to a target in a number of
// equal steps. TOML, JSON or CSV; SI units (strain dimensionless with engineering shear
// g23 g13 g12, stress in Pa). docs/decisions.md D166.
#include <array>
#include <string>
#include <vector>

namespace pnc::app {

/// Component names: strain e11 e22 e33 g23 g13 g12 (engineering shear), stress s11 s22 s33
/// s23 s13 s12; Voigt order 11, 22, 33, 23, 13, 12.
extern const std::array<const char*, 6> kStrainNames;
extern const std::array<const char*, 6> kStressNames;

struct DriveSegment {
  int steps = 1;                  ///< equal increments from the current values to the target
  std::array<char, 6> kind{};     ///< 'e' strain-controlled, 's' stress-controlled
  std::array<double, 6> target{}; ///< strain (1) or stress (Pa) at the end of the segment
  std::string label;              ///< optional name from the file
};

struct DrivePath {
  std::string source;
  std::vector<DriveSegment> segments;
  /// Q: turns the card's platelet frame; the driven material has R = R_card Q
  /// (x_local = R x_driver). Identity when the file has no rotation.
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};
  bool rotated = false;
  double newton_strain_tol = 1e-12; ///< residual tolerance = this x largest |C0_ij| (Pa)
  int newton_max_iterations = 25;
  long long total_steps() const;
};

/// Reads and validates a path file (.toml, .json or .csv); every refusal is a
/// pnc::InputError naming the file, the field, the value and the rule.
DrivePath read_drive_path(const std::string& path);

} // namespace pnc::app
