#pragma once
// pnc/thermo/ti.hpp: Helmholtz free energy by thermodynamic integration (TI) over a
// coupling parameter lambda (docs/theory.md §4).
//
// Units: LAMMPS `real` throughout -- kcal/mol (energies, dH/dlambda, Delta A), A, fs, K;
// moduli derived by docs/theory.md §4.4 are reported in Pa.
//
//   Delta A = A(1) - A(0) = int_0^1 < dH/dlambda >_lambda dlambda
//
// Every lambda point runs in its own supervised LAMMPS child (pnc::md::run_stage, so a
// LAMMPS error is reported with LAMMPS's own message): the system is set up at fixed lambda,
// equilibrated for `equil_steps`, then `prod_steps` are run in chunks of `sample_every`
// steps and one sample is taken after each chunk. A sample holds dH/dlambda, the lambda-
// dependent energy U(lambda) and U(lambda') - U(lambda) for the neighbouring nodes lambda'
// (free-energy perturbation, FEP, between adjacent nodes as a cross-check of TI). The point's
// samples and results go to one HDF5 file, written atomically: the checkpoint unit. With
// `resume`, points whose file exists are not recomputed.
//
// The polymer TI (run_ti) ramps the Lennard-Jones parameters linearly,
//   eps(l) = eps0 (1-l) + eps1 l,  sig(l) = sig0 (1-l) + sig1 l,
// with the cut-off held at the full system's r_c (decision D62), by `pair_coeff` at each
// node (the Debian LAMMPS has no FEP package). dH/dlambda is summed by pnc over the pair
// distances of LAMMPS's `compute pair/local dist` (non-bonded pairs inside r_c; excluded
// 1-2/1-3/1-4 pairs are not listed):
//   du/dl = 4 (eps1-eps0) [(s/r)^12 - (s/r)^6] + 4 eps (sig1-sig0) (12 s^11/r^12 - 6 s^5/r^6)
// and is checked once per point, after equilibration, against a central finite difference
// of LAMMPS's own pair energy (evdwl at lambda -+ h on the same configuration).
#include "pnc/core/progress.hpp"
#include "pnc/md/forcefield.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/thermo/analysis.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace pnc::thermo {

/// Linear LJ ramp of docs/theory.md §4.1. Defaults: the dissertation's eps0 = 0.0498,
/// eps1 = 0.498 ("J/mol", read kJ/mol like D13, here in kcal/mol), sig0 = 0.95 A,
/// sig1 = 2.95 A; cut-off 2.5 sig1 at every lambda (D62).
struct LjPath {
  double eps0 = 0.0498 * md::kcal_per_kJ; ///< kcal/mol
  double eps1 = 0.498 * md::kcal_per_kJ;  ///< kcal/mol
  double sig0 = 0.95;                     ///< A
  double sig1 = 2.95;                     ///< A
  double cutoff = 2.5 * 2.95;             ///< A, fixed
  double eps(double l) const { return eps0 * (1 - l) + eps1 * l; }
  double sig(double l) const { return sig0 * (1 - l) + sig1 * l; }
  void validate(const std::string& source) const;
};

/// 4 eps ((s/r)^12 - (s/r)^6), kcal/mol.
double lj_energy(double r, double eps, double sig);
/// d/dlambda of lj_energy along the path at fixed r, kcal/mol.
double lj_dudl(double r, double lambda, const LjPath& p);

struct PairSums {
  double dudl = 0; ///< sum over pairs with r < cutoff of du/dlambda
  double u = 0;    ///< sum of u at lambda
  long pairs = 0;  ///< pairs inside the cut-off
};
PairSums lj_sums(const double* r, long n, double lambda, const LjPath& p);
/// sum over pairs with r < cutoff of u at lambda.
double lj_energy_sum(const double* r, long n, double lambda, const LjPath& p);

/// One sample at a lambda point (kcal/mol). du_prev/du_next: U(lambda') - U(lambda) for the
/// neighbouring nodes (NaN where there is no neighbour).
struct LambdaSample {
  double dhdl = 0, u = 0, du_prev = 0, du_next = 0;
};

/// The system of a TI, as code that runs inside the lambda point's LAMMPS child.
struct LambdaSystem {
  /// Builds/reads the system and sets it to `lambda`, with its integrator and thermostat
  /// (the timestep is set by the engine afterwards).
  std::function<void(md::Lammps&, double lambda, std::uint64_t seed)> setup;
  /// One sample at the current step.
  std::function<LambdaSample(md::Lammps&, double lambda, double lambda_prev, double lambda_next)>
      sample;
  /// Optional, once after equilibration: named scalars stored with the point (e.g. the
  /// finite-difference check, the volume). May run `run 0`; must leave lambda as it was.
  std::function<std::map<std::string, double>(md::Lammps&, double lambda)> checks;
  /// Optional: the whole production phase in one go (`steps` steps, one sample every `every`
  /// steps, returned in order). When set, it replaces the chunked runs + `sample` (which
  /// cost a `run` call per sample).
  std::function<std::vector<LambdaSample>(md::Lammps&, double lambda, double lambda_prev,
                                          double lambda_next, long steps, int every)>
      production;
};

struct SamplingSpec {
  double timestep_fs = 0.5; ///< dissertation 0.5 fs
  long equil_steps = 60000; ///< 30 ps discarded (dissertation: 40 ps per lambda ...)
  long prod_steps = 20000;  ///< ... of which the last 10 ps are averaged
  int sample_every = 100;   ///< steps between samples of dH/dlambda (D64: ~1/3 of its tau_int)
  int blocks = 10;          ///< blocks for the standard errors
  double temperature = 300; ///< K (kT of the FEP estimates)
  void validate(const std::string& source) const;
};

struct PointResult {
  double lambda = 0, lambda_prev = 0, lambda_next = 0;
  Estimate dhdl;                                     ///< block mean of the dH/dlambda samples
  std::vector<double> dhdl_s, u_s, dprev_s, dnext_s; ///< sample series (kcal/mol)
  std::map<std::string, double> checks;
  double seconds = 0;
};

/// Writes/reads one point file (format `pnc-thermo-lambda-point`, docs/formats.md).
PointResult read_point(const std::string& h5);

struct LambdaIntegral {
  Quadrature rule;
  std::vector<PointResult> points; ///< one per node, ascending lambda
  Estimate dA;                     ///< sum w_i <dH/dl>_i, se propagated
  /// Between adjacent nodes i, i+1: FEP forward (from i), backward (from i+1), and their
  /// mean; TI over the same interval by the trapezoid rule of the two node means.
  std::vector<Estimate> fep_forward, fep_backward, ti_trapezoid;
};

/// Progress callback: one pnc::Progress line (core/progress.hpp, D344) per finished point,
/// "pnc thermo ti: <done>/<total> lambda points ..."; the detail names the point and its <dH/dl>.
using Progress = pnc::ProgressSink;

struct PointJob {
  double lambda = 0, lambda_prev = 0, lambda_next = 0; ///< NaN: no neighbour
  std::string h5, label;
  std::uint64_t seed = 1; ///< thermostat seed of this point
};

/// Runs every job whose file is missing (or all when !resume), `jobs` at a time, each in its
/// own child with its LAMMPS log `<h5 without .h5>.log`, LAMMPS on `ranks` MPI ranks
/// (md::StageSpec::ranks, D324); `progress` after each batch.
/// Throws on the first failed point (md::throw_stage_failure: pnc::ToolError with LAMMPS's
/// message; finished points stay).
void run_points(const SamplingSpec& s,
                const std::vector<std::pair<PointJob, LambdaSystem>>& point_jobs, bool resume,
                int jobs, const Progress& progress, int ranks = 1);

/// Jobs for the nodes of `rule` in `dir` (files dir/lambda_<i>.h5), seeds seed + i.
std::vector<PointJob> node_jobs(const Quadrature& rule, const std::string& dir,
                                const std::string& label, std::uint64_t seed);
/// Reads the node files and integrates (and the adjacent-node FEP / trapezoid estimates).
LambdaIntegral collect(const Quadrature& rule, const std::vector<PointJob>& jobs, double kT,
                       int blocks);

// ---------------------------------------------------------------------------------------
// The polymer RVE: free energy of deformation.

/// A deformation state: "vol" F = (1+a) I or "dev" F = I + b (1 - delta_ij)
/// (docs/theory.md §4.2, D63); the unstrained state is "ref".
struct DeformState {
  std::string kind; ///< "ref", "vol", "dev"
  double strain = 0;
  std::string id; ///< directory name, e.g. "vol_0.00125"
};

/// LAMMPS commands applying F of `st` to the current box `box` (Angstrom) with affine remap. A
/// non-triclinic F is turned into LAMMPS's upper-triangular form by a rigid rotation (QR of F H),
/// which changes no free energy (D63). Adds "change_box all triclinic" first for "dev".
std::vector<std::string> deform_commands(const DeformState& st, const md::LmpBox& box);

struct TiSpec {
  LjPath path;
  std::string rule = "gauss"; ///< "gauss" or "trapezoid"
  int points = 3;
  std::vector<double> vol = {0.0, 1.25e-3, 2.5e-3, 3.75e-3, 5.0e-3}; ///< alpha values
  std::vector<double> dev = {0.0, 1.25e-3, 2.5e-3, 3.75e-3, 5.0e-3}; ///< beta values
  SamplingSpec sampling;
  double damp_fs = 100; ///< Langevin damping time
  std::uint64_t seed = 1;
  double fd_h = 1e-4;                 ///< lambda step of the finite-difference check
  std::string dhdl_method = "virial"; ///< "virial" or "pairs" (lj_sampling, D64)
  int jobs = 1;
  int ranks = 1; ///< MPI ranks of LAMMPS per lambda point (D324; not in ti_spec.json)
  std::string atom_style = "molecular";
  void validate(const std::string& source) const;
};

std::vector<DeformState> ti_states(const TiSpec& spec);

/// Sampling of the LJ path. `method` "pairs": after every `sample_every` steps (one `run`
/// per sample), dH/dlambda and U(lambda') are summed by pnc over the pair distances of
/// `compute pair/local dist`. `method` "virial" (default, D64): one uninterrupted run
/// records LAMMPS's pair energy U and pair virial W = sum r.f (fix vector); for one LJ type
/// with a fixed cut-off, U = U12 - U6 and W = 12 U12 - 6 U6 give U12, U6 exactly, so
///   dH/dl = (eps'/eps) U + (sig'/sig) W,  U(l') = (eps(l')/eps) [s^12 U12 - s^6 U6],
///   s = sig(l')/sig
/// -- the same numbers as the pair-distance sums (checked at every point) at no extra cost.
/// `checks` (both methods): on one configuration after equilibration, the pair-distance sum
/// against the virial identity and against a Richardson-extrapolated central difference of
/// LAMMPS's evdwl at lambda -+ h, -+ 2h (with an error estimate), U against evdwl, volume.
/// `setup` is empty: the caller's setup must define `compute pnc_pl all pair/local dist`
/// and a single-type `pair_style lj/cut` whose coefficients are `pair_coeff * * eps sig rc`.
LambdaSystem lj_sampling(const LjPath& path, double fd_h, const std::string& method = "virial");

/// The polymer system of one state (reads `restart`, re-issues `ff`, deforms, sets lambda).
LambdaSystem polymer_system(const TiSpec& spec, const DeformState& st, const std::string& restart,
                            const std::vector<std::string>& ff);

struct StateResult {
  DeformState state;
  LambdaIntegral ti;
  double volume = 0; ///< A^3, of the deformed box
};

/// Moduli from Delta A(strain) (docs/theory.md §4.4): quadratic fit a + b s + c s^2 (weighted by
/// the standard errors) per kind; energy density W = Delta A / V0. Volumetric: eps_kk = 3 alpha, K
/// = d2W/d eps_kk^2 = 2 c / (9 V0); deviatoric: eps_bar:eps_bar = 6 beta^2, W = mu eps_bar:eps_bar,
/// mu = c / (6 V0). Pa. (D65)
struct ResponseFit {
  std::string kind;
  PolyFit fit;        ///< of Delta A (kcal/mol) against the strain parameter
  double modulus = 0; ///< Pa: K (vol) or mu (dev)
  double modulus_se = 0;
  double v0 = 0; ///< A^3
};

struct TiResult {
  TiSpec spec;
  std::vector<StateResult> states;
  std::vector<ResponseFit> fits;
  std::string h5; ///< ti.h5
  double seconds = 0;
};

/// Runs (or resumes) the TI of every state into `dir` (dir/<state id>/lambda_<i>.h5), then
/// writes dir/ti.h5 (every sample series and the results). `source_json` is stored.
TiResult run_ti(const TiSpec& spec, const std::string& restart, const std::vector<std::string>& ff,
                const std::string& dir, bool resume, const std::string& source_json,
                const Progress& progress);

/// The checks run_ti makes before any work: the spec, and that `restart` is a file.
void check_ti_start(const TiSpec& spec, const std::string& restart);
/// D394: refuses (pnc::InputError naming `restart`, the pair style and the rule) a start state
/// (its pair style as md::restart_pair_style reads it, LAMMPS on `ranks` ranks, log in `dir`)
/// whose pair style is not lj/cut: the TI sets `pair_style lj/cut` and ramps it, so a Coulomb
/// pair and its kspace partner would be dropped, not scaled. A file LAMMPS cannot read passes.
void check_ti_pair_style(const std::string& restart, const std::string& dir, int ranks = 1);

/// One (state, lambda node) of a TI: the unit of work of `pnc thermo ti`'s plan (decision
/// D285). Its file is job.h5 = dir/<state id>/lambda_<node>.h5, its seed the one run_ti uses.
struct TiPoint {
  DeformState state;
  std::size_t state_index = 0, node = 0;
  PointJob job;
};
/// Every point of `spec` in `dir`: states in ti_states order, nodes ascending.
std::vector<TiPoint> ti_points(const TiSpec& spec, const std::string& dir);
/// Runs one point (always; its file is replaced atomically) in its supervised LAMMPS child;
/// throws like run_points.
void run_ti_point(const TiSpec& spec, const TiPoint& point, const std::string& restart,
                  const std::vector<std::string>& ff, const Progress& progress);
/// The analysis: collect_ti, then dir/ti.h5 (write_ti_h5); `seconds` is stored as the wall time.
TiResult finish_ti(const TiSpec& spec, const std::string& dir, const std::string& source_json,
                   double seconds);

/// Analysis only (all point files must exist).
TiResult collect_ti(const TiSpec& spec, const std::string& dir);
void write_ti_h5(const std::string& path, const TiResult& r, const std::string& source_json);

} // namespace pnc::thermo
