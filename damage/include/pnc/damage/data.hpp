#pragma once
// pnc/damage/data.hpp: stress-strain curves of the deformation cases, in memory and on disk.
//
// In memory: SI units (stress in Pa), strain dimensionless with engineering shear.
// On disk:
//  * CSV  header `case,e11,e22,e33,g23,g13,g12,s11_Pa,s22_Pa,s33_Pa,s23_Pa,s13_Pa,s12_Pa`
//    (extra columns `sd11_Pa..sd12_Pa` with the standard error of each stress are optional);
//    strain dimensionless, shear as engineering gamma; a stress column's name ends with its
//    unit (D342): `_Pa` (written), `_MPa` or `_GPa` (read too); the bare `s11`, `sd11` of
//    files written before the rule are read as MPa with a warning (StressStrainData::warnings);
//    two spellings of one column or another suffix are refused. `case` 1..9 as in
//    docs/theory.md §2.1. Rows of one case must be in loading order.
//  * HDF5 `cases.h5` (written by rve/ and by `pnc synth`): /case_<n>/strain (k x 6, 1),
//    /case_<n>/stress (k x 6, Pa), optional /case_<n>/stress_stderr (k x 6, Pa); each
//    dataset has a `units` attribute and a `columns` attribute naming its six columns
//    (kStrainColumns, kStressColumns: the CSV names); the root has `stress_definition` and
//    the provenance block (pnc/core/hdf5_io.hpp).
#include <Eigen/Dense>

#include <string>
#include <vector>

namespace pnc::damage {

using PathMatrix = Eigen::Matrix<double, Eigen::Dynamic, 6>;

/// Names of the six Voigt columns of strain and stress matrices (the HDF5 `columns`
/// attribute; the CSV header adds the unit suffix `_Pa` to the stresses, D342):
/// normal strains e, engineering shear strains g, stresses s.
inline constexpr const char* kStrainColumns = "e11,e22,e33,g23,g13,g12";
inline constexpr const char* kStressColumns = "s11,s22,s33,s23,s13,s12";

struct CaseCurve {
  int id = 0;
  PathMatrix strain;        ///< dimensionless, engineering shear
  PathMatrix stress;        ///< Pa
  PathMatrix stress_stderr; ///< Pa; empty (0 rows) when unknown
};

struct StressStrainData {
  std::string source;                ///< file it came from
  std::string stress_definition;     ///< e.g. "virial (no kinetic term)", "synthetic"
  std::vector<CaseCurve> cases;      ///< sorted by id, at most one per id
  std::vector<std::string> warnings; ///< for the user, one line each (legacy CSV columns, D342)
  const CaseCurve* find(int id) const;
  std::size_t points() const;
};

/// Reads CSV or HDF5 by file extension (.csv, .h5/.hdf5). Errors name file, field, value.
StressStrainData read_stress_strain(const std::string& path);
StressStrainData read_stress_strain_csv(const std::string& path);
StressStrainData read_stress_strain_h5(const std::string& path);
/// Writers are atomic (temporary file + rename).
void write_stress_strain_csv(const std::string& path, const StressStrainData& d);
void write_stress_strain_h5(const std::string& path, const StressStrainData& d);

} // namespace pnc::damage
