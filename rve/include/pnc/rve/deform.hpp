#pragma once
// pnc/rve/deform.hpp: the stepwise strain-controlled deformation driver (docs/theory.md §3.4, D17).
//
// Units: LAMMPS `real` inside (A, fs, kcal/mol, atm, K); the stresses this header returns
// and stores are in Pa (tension positive: sigma = -P).
//
// Case numbering as docs/theory.md §2.1 / damage/reference.hpp: 1-3 extension along
// x1..x3 with the lateral box lengths held, 4 simple shear 2-3 (tilt yz = gamma Lz),
// 5 simple shear 1-3 (tilt xz = gamma Lz), 6 simple shear 1-2 (tilt xy = gamma Ly), in a
// triclinic box. The pure polymer uses cases 2 and 6.
//
// Per row k = 0..steps (strain t_k = k * strain_max / steps, measured from the reference
// box of the start state; row 0 is a hold at zero strain that measures the reference stress):
//   * the state after row k-1 (row 0: the start state) is read from its LAMMPS restart file into a
//   fresh instance
//     (the uninterrupted run and a resumed run therefore execute identical commands);
//   * the box is set to F_k applied to the reference box, atoms remapped (change_box remap);
//   * hold: NVE + Langevin (T, damp, seed + k, zero yes) and fix momentum (linear, every
//     `momentum_every` steps), `hold_steps` of `timestep_fs` (row 0, the zero-strain hold that
//     measures the reference stress: `reference_holds` x `hold_steps`, decision D131);
//   * every `sample_every` steps the six stress components are sampled twice: virial only
//     (compute pressure NULL virial, docs/theory.md §3.5) and with the kinetic term (thermo_temp);
//   * per step: mean of the samples and its standard error by block averaging (`blocks`
//     contiguous blocks, s.e. = sd(block means)/sqrt(blocks)), checked against the integrated
//     autocorrelation time of the samples (statistics.hpp, decision D132): blocks shorter than
//     5 statistical inefficiencies are flagged and their error inflated;
//   * the state is written (restart k), then checkpoint.h5 is replaced atomically with all
//     finished steps, then the restart of step k-1 is removed. A kill at any moment leaves
//     a consistent checkpoint; `resume` continues after its last finished step.
#include "pnc/md/runner.hpp"

#include <Eigen/Dense>

#include <cstdint>
#include <string>
#include <vector>

namespace pnc::rve {

struct DeformSpec {
  int case_id = 2;
  double strain_max = 0.1; ///< final engineering strain (or gamma); may be negative
  /// final engineering shear gamma of the shear cases (those whose registry row drives a
  /// shear component, damage/cases.hpp); 0 = strain_max (decision D12m)
  double shear_strain_max = 0;
  /// the final strain of this spec's case: shear_strain_max for a shear case when set (the
  /// case's row says whether it drives a shear component, D362)
  double amplitude() const;
  int steps = 40; ///< strain steps
  double timestep_fs = 0.5;
  long hold_steps = 10000; ///< MD steps per strain step (5 ps at 0.5 fs)
  int sample_every = 10;   ///< 5 fs at 0.5 fs
  int blocks = 10;         ///< blocks for the standard error
  int reference_holds = 4; ///< row 0 lasts reference_holds x hold_steps (decision D131)
  /// K; 0 = static deformation (decision D120): per row the affine remap, an optional energy
  /// minimisation at fixed box (`minimize`), the stress of `run 0`; no hold, no standard errors
  /// (stored as NaN in checkpoint.h5, absent from cases.h5)
  double temperature = 300;
  bool minimize = true; ///< static deformation only: relax the atoms at fixed box per row
  double damp_fs = 100; ///< Langevin damping time
  int momentum_every = 100;
  std::uint64_t seed = 1;
  std::string atom_style = "molecular";
  std::string start_state; ///< LAMMPS restart file of the equilibrated (unstrained) RVE
  std::vector<std::string> force_field; ///< commands re-issued after every read_restart
  std::string recipe_json;              ///< stored with the results
  int abort_after_step = -1;            ///< testing only: the child dies (SIGKILL) after this row
  void validate(const std::string& source) const;
};

struct CaseResult {
  int case_id = 0;
  int rows_done = 0; ///< finished rows: row 0 = hold at zero strain, row k = strain step k
  Eigen::Matrix<double, Eigen::Dynamic, 6> strain;           ///< engineering, k x 6
  Eigen::Matrix<double, Eigen::Dynamic, 6> stress_virial;    ///< Pa, docs/theory.md §3.5
  Eigen::Matrix<double, Eigen::Dynamic, 6> stress_virial_se; ///< Pa
  Eigen::Matrix<double, Eigen::Dynamic, 6> stress_total;     ///< Pa, with kinetic term
  Eigen::Matrix<double, Eigen::Dynamic, 6> stress_total_se;  ///< Pa
  Eigen::Matrix<double, Eigen::Dynamic, 4>
      thermo; ///< per step: T (K), PE (kcal/mol), V (A^3), density (g/cm3)
  /// Integrated autocorrelation time of the stress samples (fs) and whether the block error
  /// was inflated because the blocks were too short (1) or not (0); NaN in rows written by a
  /// pnc before decision D132 (not measured).
  Eigen::Matrix<double, Eigen::Dynamic, 6> stress_virial_tau_fs, stress_total_tau_fs;
  Eigen::Matrix<double, Eigen::Dynamic, 6> stress_virial_inflated, stress_total_inflated;
};

/// Runs (or resumes, when `resume` and `dir`/checkpoint.h5 exists) one case in a child
/// process; results in `dir`/checkpoint.h5, LAMMPS log in `dir`/lammps.log. The child prints
/// one pnc::Progress line per strain step on stderr (core/progress.hpp, D344: the strain points
/// done, elapsed, ETA; then the step, strain and stress).
md::StageOutcome run_case(const DeformSpec& spec, const std::string& dir, bool resume);
/// The body that run_case runs in the child (exposed for run_stages / --jobs).
md::StageBody case_body(const DeformSpec& spec, const std::string& dir, bool resume);
md::StageSpec case_stage(const DeformSpec& spec, const std::string& dir, int ranks = 1);

/// Reads `dir`/checkpoint.h5. Throws InputError when absent or malformed.
CaseResult read_case(const std::string& dir);

/// Centred moving average over `points` (odd) rows, window truncated at the ends.
Eigen::Matrix<double, Eigen::Dynamic, 6>
moving_average(const Eigen::Matrix<double, Eigen::Dynamic, 6>& m, int points);

} // namespace pnc::rve
