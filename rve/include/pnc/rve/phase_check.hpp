#pragma once
// pnc/rve/phase_check.hpp: is the equilibrated RVE a solid on the time scale of one strain
// hold? Run by `pnc characterize` after the equilibration, before the deformation cases
// (docs/rve.md "Phase check", decisions D125-D129).
//
// Units: LAMMPS `real` inside the stage; everything this header returns and phase.h5 holds is
// SI (Pa, s, kg/m^3).
//
// What the stage measures, from the equilibrated restart, at the deformation temperature:
//  1 stress autocorrelation: Langevin re-thermalisation (`hold_steps`/5 steps), then NVE for
//    `steps` steps, total stress (with kinetic term) sampled every `sample_every` steps;
//    G_acf(t) = V/(k_B T) <ds(0) ds(t)> averaged over the three off-diagonal components
//    (ds: deviation from the run mean), lags 0 .. t_hold (decision D125). Standard errors from
//    `blocks` blocks of time origins; the blocks must be longer than kMinBlockOverTau
//    integrated correlation times of the shear stress (checked, reported).
//  2 shear step pair: holds at simple shear +gamma and -gamma (xy, from the start box), as a
//    deformation-case hold (NVE + Langevin, `hold_steps`); G_hold = (s12(+) - s12(-)) /
//    (2 gamma) from the second half of each hold: the shear stress that is still carried at
//    t_hold/2 .. t_hold after a step strain (decision D126).
//  3 bulk pair: holds at isotropic volumetric strain +-bulk_strain; K = -dP/dlnV from the
//    total pressure of the second halves (decision D127).
//  4 cavitation: one hold (`cavitation_steps`) at isotropic volumetric expansion
//    `cavitation_strain`; pressure of the second and the last quarter (the first holds the
//    remap transient), void fraction (equilibrate.hpp void_fraction) after the first quarter
//    and at the end.
//  5 density drift: least-squares slope of the NPT chunk means of the second half of the
//    equilibration's NPT run (equilibrate/final.h5 /trace_npt), when that ensemble was used.
// Classification (decision D128): "solid on the hold time scale" when G_hold > kResolvedSigmas
// standard errors and G_hold >= kSolidFraction * (G_hold + max(0, G_plateau)), G_plateau the mean
// of G_acf over 0.25 .. 0.75 ps; else
// "relaxes within a hold". G(t) = G_eq + G_acf(t) for a solid in a fixed box (the stress
// autocorrelation of a solid decays to zero; its equilibrium modulus G_eq is what the step
// pair measures), so G_hold + G_acf(0.5 ps) is the short-time plateau.
#include "pnc/md/runner.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace pnc::rve {

/// Blocks of the autocorrelation estimate must span at least this many integrated
/// correlation times of the shear stress (decision D125).
inline constexpr double kMinBlockOverTau = 5.0;
/// "Resolved": more than this many standard errors from zero.
inline constexpr double kResolvedSigmas = 3.0;
/// Time of the short-time plateau of G(t) (after the bond and kinetic contributions), s.
inline constexpr double kPlateauTime_s = 0.5e-12;
/// Solid: the modulus still carried after a hold is at least this fraction of the plateau.
inline constexpr double kSolidFraction = 0.5;
/// Cavitation (decision D129): the void fraction grows by more than this (absolute) between
/// the end of the first and the end of the expansion hold, or the tension relaxes toward zero:
/// |P| of the last quarter below |P| of the second quarter (the first holds the transient of
/// the affine remap) by more than kResolvedSigmas standard errors and by more than half.
inline constexpr double kCavitationVoidGrowth = 0.005;

/// Recipe key "phase_check" (all optional; validate() names the dotted field).
struct PhaseCheckSpec {
  bool enabled = false;
  long steps = 20000;              ///< NVE steps of the autocorrelation run
  int sample_every = 5;            ///< steps between stress samples of the autocorrelation run
  int blocks = 10;                 ///< blocks of time origins for the standard errors
  double shear_strain = 0.03;      ///< gamma of the shear step pair
  double bulk_strain = 0.03;       ///< volumetric strain of the bulk pair (+-)
  double cavitation_strain = 0.04; ///< volumetric expansion of the cavitation hold
  long cavitation_steps = 10000;   ///< steps of the cavitation hold
  void validate(const std::string& source) const;
};

/// What one stage run needs besides the spec (filled by the pipeline or a test).
struct PhaseCheckInput {
  std::string start_state; ///< LAMMPS restart (units real)
  std::string atom_style = "molecular";
  std::vector<std::string> force_field; ///< re-issued after read_restart
  double temperature = 300;             ///< K, the deformation temperature
  double damp_fs = 100;                 ///< Langevin damping of the holds
  double timestep_fs = 1.0;
  long hold_steps = 5000;     ///< the recipe's deform.hold_steps
  int hold_sample_every = 10; ///< sampling of the holds
  double probe_A = 0;         ///< void-fraction probe radius (sigma), 0: skip voids
  std::uint64_t seed = 1;
  std::string recipe_json;
  std::string equilibrate_dir; ///< for the density drift (final.h5), may be empty
  double npt_chunk_fs = 0;     ///< duration of one NPT trace chunk (equilibrate.cpp)
};

/// Result of an autocorrelation estimate (value in the square of the input's unit).
struct AcfEstimate {
  std::vector<double> lag;   ///< lag times (unit of dt)
  std::vector<double> value; ///< mean over components of <ds(0) ds(t)>
  std::vector<double> se;    ///< block standard error
  double tau_int = 0;        ///< integrated correlation time (unit of dt), mean over components
  double block_length = 0;   ///< time origins per block x dt
  int blocks = 0;
  bool blocks_ok = false;                        ///< block_length >= kMinBlockOverTau * tau_int
  std::vector<std::vector<double>> block_values; ///< [lag][block]: the block estimates
};

/// Mean of an estimate over lags k0..k1 (inclusive) and its block standard error (the window
/// mean is formed in every block, so correlations between lags are accounted for).
std::pair<double, double> window_mean(const AcfEstimate& e, std::size_t k0, std::size_t k1);

/// <ds(0) ds(k dt)> for k = 0..max_lag averaged over the given series (each a component of
/// the same run, equal length N > max_lag + blocks), deviations from each series' mean. Time
/// origins 0..N-1-max_lag are split into `blocks` contiguous blocks; each block's estimate is
/// the mean over its origins and components; value = mean of the block estimates, se =
/// sd(block estimates)/sqrt(blocks). Throws std::invalid_argument for too short series.
AcfEstimate autocorrelation(const std::vector<std::vector<double>>& series, double dt, int max_lag,
                            int blocks);

/// Integrated autocorrelation time dt (1/2 + sum_k rho(k)) with Sokal's self-consistent
/// window (stop at the first W >= 5 tau); rho from the series' own mean. Unit of dt.
double integrated_time(const std::vector<double>& x, double dt);

/// Mean and standard error of a hold's series (samples equally spaced): block means with
/// blocks of at least kMinBlockOverTau integrated correlation times, at most 10 and at least 4
/// blocks; `ok` false when 4 such blocks do not fit (the error bar may then be too small).
struct MeanSe {
  double mean = 0, se = 0;
  int blocks = 0;
  bool ok = false;
};
MeanSe hold_mean_se(const std::vector<double>& x);

/// Least-squares slope of y(t) and its standard error (residual variance, n-2 dof).
std::pair<double, double> slope_se(const std::vector<double>& t, const std::vector<double>& y);

struct PhaseCheckResult {
  bool done = false;
  double temperature_K = 0, volume_m3 = 0, dt_s = 0;
  /// mean T of the first and the last tenth of the NVE run (K): its energy drift
  double nve_T_first_K = 0, nve_T_last_K = 0;
  double hold_time_s = 0;
  // 1 autocorrelation, Pa
  std::vector<double> acf_t_s, acf_G_Pa, acf_G_se_Pa;
  double G_t0_Pa = 0, G_t0_se_Pa = 0;
  /// plateau: mean of G_acf over kPlateauTime_s/2 .. 3 kPlateauTime_s/2 (bond vibrations
  /// make the point value oscillate); the point value at kPlateauTime_s
  double G_plateau_Pa = 0, G_plateau_se_Pa = 0;
  double G_at_plateau_time_Pa = 0, G_at_plateau_time_se_Pa = 0;
  /// mean of G_acf over t_hold/2 .. t_hold (the window of G_hold)
  double G_acf_late_Pa = 0, G_acf_late_se_Pa = 0;
  double G_acf_hold_Pa = 0, G_acf_hold_se_Pa = 0;
  double tau_int_s = 0, block_s = 0;
  bool blocks_ok = false;
  // 2 shear step pair
  double G_hold_Pa = 0, G_hold_se_Pa = 0;
  /// every hold mean (shear, volume, cavitation) had >= 4 blocks of >= 5 correlation times
  bool holds_blocks_ok = false;
  // 3 bulk pair
  double K_Pa = 0, K_se_Pa = 0;
  // 4 cavitation
  double cav_strain = 0;
  double cav_P_first_Pa = 0, cav_P_first_se_Pa = 0, cav_P_last_Pa = 0, cav_P_last_se_Pa = 0;
  double cav_void_first = 0, cav_void_last = 0;
  bool cavitates = false;
  // 5 density drift (NaN without an NPT run)
  double drift_kg_m3_s = 0, drift_se_kg_m3_s = 0;
  // classification
  bool solid = false;
  std::string phase;   ///< "solid on the hold time scale" or "relaxes within a hold"
  std::string summary; ///< one paragraph in words and numbers
};

/// The classification of D128 from the measured numbers (fills solid, phase, summary).
void classify(PhaseCheckResult& r);

/// Runs the stage in a supervised child (ranks as StageSpec::ranks) into `dir`/phase.h5,
/// `dir`/phase.log; skipped when `resume` and phase.h5 exists. Throws pnc::InputError with
/// LAMMPS's message on failure.
PhaseCheckResult run_phase_check(const PhaseCheckSpec& spec, const PhaseCheckInput& in,
                                 const std::string& dir, bool resume, int ranks = 1);

/// Reads `dir`/phase.h5.
PhaseCheckResult read_phase_check(const std::string& dir);

/// Key numbers for the JSON summary (unit-suffixed keys).
nlohmann::json phase_json(const PhaseCheckResult& r);
/// Markdown section "Phase check" for report.md.
std::string phase_markdown(const PhaseCheckResult& r);

} // namespace pnc::rve
