#pragma once
// pnc/rve/equilibrate.hpp: the equilibration protocol of docs/theory.md §3.3 (D19) for the
// polymer RVE, one supervised child process per stage.
//
// Units: LAMMPS `real` (A, fs, kcal/mol, atm, K); densities in g/cm^3.
//
// Stages (each reads the previous stage's restart, writes `<dir>/<stage>.restart`,
// `<dir>/<stage>.h5` (result + end criterion) and `<dir>/<stage>.log` (LAMMPS log)):
//  1 pushoff  soft push-off: pair soft, A ramped 0 -> A_max (fix adapt), NVE with
//             displacement limit (fix nve/limit) + Langevin; repeated (up to `pushoff_max_rounds`)
//             until no two non-excluded beads are closer than `pushoff_min_distance_sigma` sigma.
//  2 hot      LJ on; energy minimisation (removes the remaining soft-core strain), then
//             `hot_steps` at `hot_temperature` with velocity rescaling (fix temp/rescale).
//  2b clay    (composite only) clay relaxes with the polymer fixed, see equilibrate()
//  3 cool     Langevin with the target ramped hot_temperature -> temperature.
//  4 langevin Langevin at `temperature` in chunks until the mean potential energy of two
//             successive chunks differs by less than `steady_tolerance` of its magnitude
//             (or `langevin_max_chunks` are run; the criterion's outcome is logged either way).
//  5 ensemble "nvt": Langevin at the build density; "npt": Nose-Hoover NPT at `pressure`
//             (iso), then the box is set to the mean volume of the second half and held
//             at NVT (Langevin) for `final_steps` (the start state of the deformation cases).
//  6 final    measurement (no dynamics): density, virial-only and total pressure (means over
//             the last NVT hold), void fraction (fraction of the points of a 1 A grid farther
//             than sigma from every bead centre), minimum non-excluded pair distance.
// A stage whose `.h5` exists is skipped on resume.
#include "pnc/md/forcefield.hpp"
#include "pnc/md/runner.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace pnc::rve {

struct EquilibrateSpec {
  double timestep_fs = 1.0;
  double temperature = 300;
  double damp_fs = 100;
  long pushoff_steps = 5000;
  int pushoff_max_rounds = 5;
  double pushoff_A_max = 40;                ///< kcal/mol, pair soft prefactor at the end
  double pushoff_min_distance_sigma = 0.75; ///< end criterion of the push-off
  long hot_steps = 20000;
  double hot_temperature = 1000;
  long clay_steps = 5000; ///< with clay: clay relaxation with the polymer fixed (stage "clay")
  long cool_steps = 20000;
  long langevin_chunk_steps = 10000;
  int langevin_max_chunks = 10;
  double steady_tolerance = 0.01;
  std::string ensemble = "npt"; ///< "npt" (set pressure) or "nvt" (set density)
  double pressure_atm = 0;
  double pdamp_fs = 1000;
  long npt_steps = 40000;
  long final_steps = 10000;
  std::uint64_t seed = 1;
  void validate(const std::string& source) const;
};

struct EquilibratedState {
  std::string restart;        ///< start state of the deformation cases
  double density = 0;         ///< g/cm^3
  double pressure_virial = 0; ///< atm (virial only), mean of the final hold
  double pressure_total = 0;  ///< atm (with kinetic term)
  double pressure_total_se = 0;
  double temperature = 0;            ///< K
  double void_fraction = 0;          ///< fraction of grid points farther than sigma from any bead
  double min_distance = 0;           ///< A, smallest non-excluded pair distance at the end
  std::vector<std::string> criteria; ///< one line per stage: what ended it
};

/// Runs the protocol from a LAMMPS data file into `dir`. Stages with results are skipped
/// when `resume`. Throws pnc::InputError naming the stage (and LAMMPS's ERROR line) on failure.
/// `with_clay` (composite data file of clay.hpp; docs/theory.md §3.3, D25): the clay (group
/// pnc_clay) is frozen in pushoff and hot (not integrated; fix setforce 0 during the minimisation),
/// then stage "clay" minimises and runs the clay (NVE + Langevin at `temperature`, `clay_steps`)
/// with the polymer fixed; cool/langevin/final move everything, and the NPT barostat acts on
/// x2 and x3 only (coupled), x1 (along the platelet) keeps its build length (decision D24).
/// `ranks`: MPI ranks of LAMMPS per stage (StageSpec::ranks).
EquilibratedState equilibrate(const std::string& data_file, const md::PolymerForceField& ff,
                              const EquilibrateSpec& spec, const std::string& dir, bool resume,
                              const std::string& recipe_json, bool with_clay = false,
                              int ranks = 1);

/// Reads `dir`/final.h5.
EquilibratedState read_equilibrated(const std::string& dir);

/// Fraction of the points of a grid (spacing `h`) in the orthogonal box farther than `probe`
/// from every position (periodic). x: n x 3 flattened.
double void_fraction(const std::vector<double>& x, const double lo[3], const double hi[3],
                     double probe, double h);

} // namespace pnc::rve
