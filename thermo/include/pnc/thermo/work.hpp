#pragma once
// pnc/thermo/work.hpp: free energy of deformation from the work of the stress along the
// deformation cases that `pnc characterize` ran (`pnc thermo work`, docs/thermo.md "Free
// energy from the stress work", decisions D140-D143).
//
// Physics: for an isothermal, quasi-static, reversible deformation the stress is the strain
// derivative of the Helmholtz free energy per reference volume, so
//   Delta a(eps) = a(eps) - a(0) = integral_0^eps sigma : d eps     (J/m^3)
//   Delta A = V0 Delta a                                            (J; kcal/mol for the RVE)
// The contraction runs over the six Voigt components (engineering shear strain is work
// conjugate to the shear stress), so it is the driven component's work plus whatever the
// other components do (decision D140). With two runs at T1 != T2 the entropic part of the
// stress is sigma_S = T dsigma/dT (= -T dS/deps) and the energetic part sigma_U = sigma -
// sigma_S (= dU/deps), both at the mean temperature (decision D142).
//
// Units: strain dimensionless (engineering shear), stress Pa, energy density J/m^3,
// volume m^3, energy J (and kcal/mol where named), temperature K.
#include "pnc/damage/data.hpp"

#include <string>
#include <vector>

namespace pnc::thermo {

/// One `pnc characterize` output directory as `thermo work` needs it.
struct WorkRun {
  std::string dir;
  double temperature = 0;           ///< K, recipe.json deform.temperature
  double volume = 0;                ///< m^3, V0: mean box volume of equilibrate/final.h5 /trace
  damage::StressStrainData data;    ///< cases.h5 (strain, stress Pa, optional stress_stderr Pa)
  bool reference_subtracted = true; ///< the file's stress is sigma - sigma_0
  bool moving_average = false;      ///< the file's stress is smoothed over strain steps
};

/// Reads `dir`/recipe.json, `dir`/equilibrate/final.h5 and `dir`/cases.h5 (through
/// damage::read_stress_strain_h5). Throws pnc::InputError naming the file, field and rule.
WorkRun read_work_run(const std::string& dir);

/// Cumulative trapezoid of sum_j sigma_j d eps_j along one case path, starting at eps = 0.
/// If the first row is not at zero strain, the point (eps = 0, sigma = 0, exact) is put in
/// front: right for a reference-subtracted stress, which is 0 at zero strain by construction.
/// Strains are imposed (exact); the error comes from the stress.
struct WorkIntegral {
  std::vector<double> value; ///< J/m^3 at every row of the input path
  /// J/m^3: sqrt(sum_k sum_j w_kj^2 se_kj^2), valid when the points' errors are independent
  std::vector<double> se_indep;
  /// J/m^3: sum_k sum_j |w_kj| se_kj, an upper bound on the standard error for any
  /// correlation between the points (triangle inequality of standard deviations)
  std::vector<double> se_bound;
  bool has_se = false; ///< false when the file had no stress_stderr (errors are NaN)
};
/// `se` may have 0 rows (unknown errors). `source`/`field` name the data in errors.
WorkIntegral work_integral(const damage::PathMatrix& strain, const damage::PathMatrix& stress,
                           const damage::PathMatrix& se, const std::string& source,
                           const std::string& field);

/// Result for one deformation case.
struct WorkCase {
  int id = 0;
  damage::PathMatrix strain; ///< 1
  damage::PathMatrix stress; ///< Pa: the single run's, or the mean of the two runs
  WorkIntegral da;           ///< J/m^3 of `stress`
  /// true when the stress of the largest-stress component falls after its peak by more than
  /// max(3 se, 5 % of the peak): yield or damage, the integral is then work, not free energy
  bool softening = false;
  // --- two temperatures only (empty otherwise)
  WorkIntegral da1, da2;                  ///< J/m^3 at T1 and at T2
  damage::PathMatrix sigma_s, sigma_s_se; ///< Pa, T dsigma/dT at the mean temperature
  damage::PathMatrix sigma_u, sigma_u_se; ///< Pa, sigma - sigma_S
  WorkIntegral da_s, da_u; ///< J/m^3: entropic (-T Delta s) and energetic (Delta u) parts
};

struct WorkResult {
  int runs = 1;
  double temperature = 0; ///< K: the run's, or the mean (T1 + T2)/2 of two runs
  double t1 = 0, t2 = 0;  ///< K
  /// m^3: V0 of the run, or the mean of the two runs' V0 (the volume at T_mean to first order),
  /// used for Delta A = V0 Delta a of the total and of the split
  double volume = 0;
  double volume1 = 0, volume2 = 0; ///< m^3: V0 of each run (volume2 = 0 for one run)
  std::vector<WorkCase> cases;
  std::vector<std::string> notes; ///< what the numbers assume, one sentence each
};

/// One run: Delta a per case. Two runs (`second` non-null): same case ids and strains
/// (checked, InputError naming the file, field and rule), T1 != T2, plus the split.
WorkResult stress_work(const WorkRun& first, const WorkRun* second = nullptr);

/// Writes `path` (HDF5, units attribute on every dataset), atomically.
void write_work_h5(const std::string& path, const WorkResult& r);
/// Writes `path` (CSV, unit-suffixed columns, one row per point), atomically.
void write_work_csv(const std::string& path, const WorkResult& r);

} // namespace pnc::thermo
