#pragma once
// pnc/thermo/persistence.hpp: bending stiffness EI and persistence length xi_p of a short
// chain by steered bending (docs/theory.md §4.5, D66-D68).
//
// Units: LAMMPS `real` inside (A, fs, kcal/mol, K); EI is reported in kcal/mol*A and N m^2,
// xi_p in A.
//
// Protocol (one supervised LAMMPS child per pulling rate): a chain of `beads` beads along
// x, its two end beads fixed ("pinned": both ends fixed in x, y, z, as printed; "roller":
// the last bead free along x, a simply supported beam without axial constraint, D67); the
// interior beads are thermostatted (Langevin). After `hold_steps`, a spring of constant
// `spring_k` pulls the centre of mass of the interior beads along y (normal to the chain's
// plane): its anchor moves at `rate` from y = 0, y_a(t) = rate t, and the spring force
// F = k (y_a - y_cm) is applied every step through `fix addforce` with an equal-style
// variable, split equally over the interior beads (equal masses). This replaces LAMMPS's
// fix smd (EXTRA-FIX, not in the Debian build). F and d = y_cm are sampled every
// `sample_every` steps.
//
// Per rate: EI = L^3/48 * dF/dd, with dF/dd the ratio of the least-squares slopes of F and
// of d against the anchor position (the constant Langevin drag of a steady pull shifts F
// but not the slope; regressing F on the noisy d directly would be biased, D66), with a
// block-averaged standard error; the end-of-pull ratio F L^3/(48 d) as printed in the source (D67)
// is reported too. EI(rate) is fitted by a straight line (weighted) and extrapolated to zero rate,
// with a 95 % confidence interval (Student t, n-2 dof); xi_p = EI / (kB T) (docs/theory.md §4.5).
//
// Chains: "pp" -- the coarse-grained polypropylene of docs/theory.md §3.1 (md/forcefield.hpp),
// built as the all-trans planar zigzag in the xz plane; "harmonic" -- a straight chain
// with `angle harmonic` E = K (theta - 180 deg)^2 and harmonic bonds, no torsion and no
// pair forces, whose bending stiffness is known by construction (validation; D68):
// bend angle phi = pi - theta, E = (k_theta/2) phi^2 with k_theta = 2 K, continuum limit
// EI = k_theta l0, xi_p = k_theta l0 / (kB T); for a finite chain the exact small-deflection
// answer of this loading is discrete_bending_stiffness().
#include "pnc/core/progress.hpp"
#include "pnc/md/forcefield.hpp"
#include "pnc/thermo/analysis.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pnc::thermo {

struct PersistenceSpec {
  std::string chain = "pp";        ///< "pp" or "harmonic"
  int beads = 4;                   ///< dissertation: 4
  double angle_K = 500;            ///< kcal/mol/rad^2, LAMMPS K of the "harmonic" chain
  double bond_K = 300;             ///< kcal/mol/A^2 (LAMMPS K), "harmonic" chain: stiff (D68)
  double l0 = 1.53;                ///< A, bond length of the "harmonic" chain
  std::string supports = "pinned"; ///< "pinned" or "roller" (D67)
  double spring_k = 10;            ///< kcal/mol/A^2 (dissertation)
  std::vector<double> rates = {0.01, 0.025, 0.05, 0.075, 0.1}; ///< A/fs (dissertation)
  double pull_distance = 2.0; ///< A of anchor travel per pull (D66)
  double timestep_fs = 0.5;
  long hold_steps = 2000;
  int sample_every = 1;
  int blocks = 10;
  double temperature = 300;
  double damp_fs = 100;
  std::uint64_t seed = 1;
  md::PolymerForceField ff; ///< the "pp" chain's force field
  void validate(const std::string& source) const;
};

struct RateResult {
  double rate = 0;                  ///< A/fs
  Estimate slope;                   ///< dF/dd, kcal/mol/A^2
  Estimate ei;                      ///< L^3/48 slope, kcal/mol*A
  double ei_end = 0;                ///< F L^3/(48 d) from the means over the last 10 % of the pull
  double d_max = 0;                 ///< A, largest mean deflection (last 10 %)
  std::vector<double> anchor, d, F; ///< samples: A, A, kcal/mol/A
  double seconds = 0;
};

struct PersistenceResult {
  PersistenceSpec spec;
  double length = 0; ///< A, distance between the end beads as built
  std::vector<RateResult> rates;
  PolyFit line;                     ///< EI (kcal/mol*A) = c0 + c1 rate
  Estimate ei0;                     ///< zero-rate EI, kcal/mol*A
  double ei0_ci95 = 0;              ///< half-width of the 95 % interval, kcal/mol*A
  double xi_p = 0, xi_p_ci95 = 0;   ///< A
  double expected_ei = 0;           ///< "harmonic": discrete small-deflection EI, else NaN
  double expected_ei_continuum = 0; ///< "harmonic": k_theta l0, else NaN
  std::string h5;
};

/// F/d of a straight chain of `beads` beads, spacing b, bending constant k_theta (energy
/// k_theta/2 phi^2 per interior joint), both end beads held at y = 0, force F split equally
/// over the interior beads, d = mean interior deflection (small deflections; exact for the
/// discrete chain). kcal/mol/A^2 when k_theta is in kcal/mol and b in A.
double discrete_bending_stiffness(int beads, double b, double k_theta);

/// One pnc::Progress line (core/progress.hpp, D344) per bending rate done or reused.
using RateProgress = pnc::ProgressSink;

/// Runs (or resumes: dir/rate_<i>.h5 reused) every rate, writes dir/persistence.h5.
PersistenceResult run_persistence(const PersistenceSpec& spec, const std::string& dir, bool resume,
                                  const RateProgress& progress);

} // namespace pnc::thermo
