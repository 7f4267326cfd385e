#pragma once
// pnc/gimp_coupler/escm.hpp: concurrent GIMP-MD coupling by the embedded statistical coupling
// method (ESCM) of the source, docs/theory.md §6; docs/escm.md;
// decisions D70-D79 in docs/decisions.md.
//
// The continuum is the 2-D uGIMP solver (plane strain, SI, per metre of thickness); the MD
// region is a LAMMPS instance in this process (C library API, units `real`: Angstrom, fs,
// kcal/mol, g/mol, K), a block of atoms with a thin periodic z extent (the slab) and
// non-periodic x, y. Every continuum extensive quantity is converted to the slab by the slab
// thickness L_z: F_slab = F_per_metre * L_z[m] (D74).
//
// Volume cells (D70): the continuum particles are one per grid cell (half-length h/2) where
// the atoms are. Counting cell rings from the outside of the atom block inwards, the first
// `svc_rings` rings are surface volume cells (SVC), the next `ivc_rings` rings internal volume
// cells (IVC), the rest the interior (INT). Each atom belongs to the cell that contains it.
// Continuum particles of INT cells are removed (the continuum has a hole there); SVC particles
// stay ordinary continuum particles; IVC particles become zero-stress "probe" material points
// (a tiny mass fraction) whose positions follow the IVC atoms (docs/theory.md §6.2, D73).
//
// One coupled step of length dt (continuum) = N MD substeps of dtau = dt / N:
//  1. the corner nodes of the IVC cells (Gamma, fixed at setup) get the velocity of the IVC
//     cells sharing them (equal weights w_ip = 1 / (number of IVC cells at node i)); continuum
//     step with those nodes prescribed; their reactions R_i give the force of the continuum
//     on each IVC cell, f_p = sum_i w_ip (-R_i) (a partition of unity, so
//     sum_p f_p = sum_i (-R_i) exactly; docs/theory.md §6.2, D71);
//  2. MD: IVC atoms get f_p / N_p each (fix external callback) and a zero-temperature
//     Langevin damping; INT atoms a Langevin thermostat at T (both docs/theory.md §6.2);
//     SVC atoms move with the grid velocity v* interpolated at each atom (docs/theory.md §6.2,
//     D72);
//  3. IVC cell centroids are time-averaged over the N substeps (docs/theory.md §6.2); the IVC
//  material
//     point moves by the change of that average between blocks (D73).
// Modes (D71): `neumann` (default): the MD region is driven by the IVC forces; pair forces
// between SVC atoms and the other atoms are excluded so the continuum's stress is not
// transmitted twice. `schwarz`: SVC atoms interact with the MD region (they shield its
// surface) and the IVC forces are zero: displacement coupling both ways.
//
// LAMMPS is built without C++ exceptions: a LAMMPS error terminates the process with the
// message in the LAMMPS log (Config::lammps_log). Coupler::setup() validates everything it
// generates itself before any LAMMPS command; the user's md_setup commands are passed on
// unchecked (run them once in a separate process, e.g. `lmp -in`, when in doubt).
#include "pnc/core/units.hpp"
#include "pnc/core/vtu.hpp"
#include "pnc/gimp_coupler/solver.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pnc::gimp::escm {

/// LAMMPS `real` units in SI.
namespace units {
constexpr double m_per_A = pnc::units::m_per_angstrom;
constexpr double s_per_fs = pnc::units::s_per_fs;
constexpr double avogadro = pnc::units::avogadro;
constexpr double J_per_kcalmol = pnc::units::joule_per_kcal_mol;
constexpr double N_per_kcalmolA = J_per_kcalmol / m_per_A;
constexpr double kg_per_gmol = pnc::units::kg_per_g_mol;
constexpr double mps_per_Afs = pnc::units::m_per_s_per_angstrom_per_fs;
} // namespace units

enum class Zone : std::int8_t { none = -1, interior = 0, ivc = 1, svc = 2 };
enum class Mode { neumann, schwarz };

struct Config {
  /// LAMMPS commands that create the MD region: `units real`, `dimension 3`, boundary
  /// non-periodic in x and y and periodic in z (e.g. `boundary s s p`), the box, atoms (ids
  /// 1..n) and the force field. Nothing else (no fixes, no runs, no timestep).
  std::vector<std::string> md_setup;
  /// Continuum position (m) of the LAMMPS origin: x_SI = md_offset + 1e-10 x_A.
  Eigen::Vector2d md_offset = Eigen::Vector2d::Zero();
  int svc_rings = 1;                 ///< rings of SVC cells (>= 1)
  int ivc_rings = 1;                 ///< rings of IVC cells (>= 1)
  int substeps = 50;                 ///< N, MD steps per continuum step
  double dt = 0.0;                   ///< continuum step, s (> 0); dtau = dt / N
  double interior_temperature = 0.0; ///< K
  double interior_damp_fs = 100.0;   ///< Langevin damping time of INT, fs (<= 0: plain NVE)
  double ivc_damp_fs = 100.0;        ///< zero-temperature Langevin damping of IVC, fs (> 0)
  int seed = 48271;                  ///< Langevin seed (> 0)
  Mode mode = Mode::neumann;
  /// Mass-proportional damping of the continuum particle velocities, 1/s (v *= exp(-c dt));
  /// 0 for dynamics, > 0 only for quasi-static runs (D75).
  double continuum_damping = 0.0;
  double probe_mass_fraction = 1e-6; ///< IVC material point mass / ordinary mass (D70)
  std::string lammps_log = "none";   ///< LAMMPS log file ("none": no log)
};

/// One volume cell (an SVC or IVC continuum particle and its atoms).
struct Cell {
  Zone zone = Zone::none;
  std::size_t particle = 0; ///< index into solver.particles (after setup)
  std::array<int, 2> ij{};  ///< grid cell index
  std::vector<int> atoms;   ///< LAMMPS atom ids
  Eigen::Vector2d c0_A;     ///< initial centroid of its atoms, Angstrom (LAMMPS frame)
  Eigen::Vector2d mean_A; ///< IVC: time-averaged centroid of the last block (docs/theory.md §6.2)
  Eigen::Vector2d prev_mean_A;  ///< IVC: the block before
  Eigen::Vector2d force_N;      ///< IVC: continuum force on the cell, N per m thickness
  Eigen::Vector2d atom_force;   ///< IVC: force per atom, kcal/mol/A (slab)
  Eigen::Vector2d velocity_mps; ///< IVC: cell velocity given to Gamma nodes, m/s
};

/// Energy accounting of the coupled system, J for the slab thickness, since setup().
struct EnergyRow {
  long step = 0;
  double time_s = 0.0;
  double cont_kinetic = 0.0, cont_strain = 0.0; ///< continuum (SVC + outer particles)
  double md_kinetic = 0.0;                      ///< IVC + INT atoms
  double md_potential = 0.0;                    ///< IVC + INT atoms, minus its value at setup
  double work_boundary = 0.0;                   ///< work of the continuum's velocity BCs and loads
  double work_cont_on_md = 0.0;   ///< work of the IVC forces on the atoms (measured in MD)
  double work_md_on_cont = 0.0;   ///< work of the Gamma reactions on the continuum
  double heat_removed_int = 0.0;  ///< energy taken out by the INT thermostat
  double heat_removed_ivc = 0.0;  ///< energy taken out by the IVC damping
  double heat_removed_cont = 0.0; ///< energy taken out by continuum_damping
  /// Total energy now - at start - work in + heat out. Equals the energy the handshake
  /// creates, work_cont_on_md + work_md_on_cont, up to the time-integration errors of the two
  /// solvers; 0 for an energy-exact handshake.
  double balance() const {
    return cont_kinetic + cont_strain + md_kinetic + md_potential - work_boundary +
           heat_removed_int + heat_removed_ivc + heat_removed_cont - initial;
  }
  double initial = 0.0; ///< cont_kinetic + cont_strain + md_kinetic at setup
};

/// A named per-point array for the VTU writers (pnc/core/vtu.hpp: the unit in the name and in
/// `unit`; 1, 3, 6 or 9 components per point, point-major).
using PointArray = pnc::vtu::PointArray;
/// A frame's field-data scalar (the physical time "time_s", the "frame_index").
using FieldScalar = pnc::vtu::FieldScalar;

/// Writes a VTU point cloud through pnc/core/vtu.hpp (one VTK_VERTEX cell per point; ASCII,
/// `precision` digits; D236) with the Int32 point array "zone_index" and then `arrays`,
/// atomically; `field`: the frame's field data. Positions in m (3 coordinates per point).
/// Throws pnc::InputError naming an array whose size is not points x components.
void write_point_cloud_vtu(const std::string& path, const std::vector<Eigen::Vector3d>& x,
                           const std::vector<int>& zone, const std::vector<PointArray>& arrays,
                           int precision, const std::vector<FieldScalar>& field = {});

/// Wall-clock split of the coupled steps so far, s.
struct Timing {
  double lammps = 0.0;    ///< inside LAMMPS's `run` command minus the callback time
  double callback = 0.0;  ///< inside the fix external callback (coupling work)
  double continuum = 0.0; ///< Solver::step
  double coupling = 0.0;  ///< everything else of Coupler::step
  double outside_share() const {
    const double tot = lammps + callback + continuum + coupling;
    return tot > 0 ? (callback + continuum + coupling) / tot : 0.0;
  }
};

/// The coupled state between two coupled steps that the continuum solver's own state
/// (particles, time, steps, energies, cracks; GIMP checkpoint) does not hold: the coupler's
/// running averages and accumulators, and the MD atoms. Written by Coupler::checkpoint(),
/// restored by Coupler::restore(); on disk in escm_checkpoint.hpp (docs/formats.md).
struct CouplerState {
  /// Per IVC cell, in the order of the IVC cells in cells(): the block-mean centroid of the
  /// last block and of the one before (A), the cell velocity given to Gamma (m/s), the
  /// continuum force (N per m) and the force per atom (kcal/mol/A).
  std::vector<Eigen::Vector2d> mean_A, prev_mean_A, velocity_mps, force_N, atom_force;
  std::vector<EnergyRow> log; ///< energy log so far
  EnergyRow acc;              ///< running sums (the last row; the initial energy)
  double pe0 = 0.0;           ///< IVC + INT potential energy at setup, kcal/mol
  /// Heat removed by the INT / IVC Langevin fixes before their last re-creation, J (slab).
  double heat_offset_int = 0.0, heat_offset_ivc = 0.0;
  double prescribed_work = 0.0; ///< Solver::prescribed_work, J per m
  int segment = 0;              ///< Langevin re-creations so far (seed of the next segment)
  long md_step = 0;             ///< LAMMPS step counter (information)
  Timing timing;
  /// Atoms by id - 1: positions (A), velocities (A/fs), forces of the last MD substep
  /// (kcal/mol/A; Verlet's first half step of the next block uses them), image flags (3 ints),
  /// types.
  std::vector<double> x, v, f;
  std::vector<int> image, type;
};

class Coupler {
public:
  /// `solver`: a 2-D set-up (grid, particles one per cell of size h with half-length h/2 where
  /// the atoms will be, materials, BCs, tractions) not yet initialised. The coupler keeps a
  /// reference; it removes the INT particles and initialises the solver in setup().
  Coupler(Solver<2>& solver, Config cfg);
  ~Coupler();
  Coupler(const Coupler&) = delete;
  Coupler& operator=(const Coupler&) = delete;

  /// Validates the configuration (throws std::runtime_error naming the field, value and rule),
  /// starts LAMMPS, builds the volume cells and groups, initialises the solver.
  void setup();
  /// One coupled step (continuum dt, N MD substeps).
  void step();

  const std::vector<Cell>& cells() const;
  const Config& config() const;
  double slab_thickness_A() const;
  double md_timestep_fs() const;
  const std::vector<EnergyRow>& energy_log() const;
  const Timing& timing() const;
  /// Number of atoms in each zone (interior, ivc, svc).
  std::array<int, 3> zone_counts() const;
  /// Zone of a LAMMPS atom id.
  Zone zone_of(int id) const;
  /// The LAMMPS handle (for tests and output; do not issue commands that can fail).
  void* lammps() const;
  /// Atom positions (Angstrom, LAMMPS frame) and velocities (A/fs) by id (index id - 1), and
  /// displacements from setup.
  void atoms(std::vector<int>& ids, std::vector<Eigen::Vector3d>& x,
             std::vector<Eigen::Vector3d>& v) const;
  /// Initial atom positions (Angstrom) by id - 1.
  const std::vector<Eigen::Vector3d>& atoms_initial() const;
  /// Continuum position (m) of a LAMMPS position (A).
  Eigen::Vector2d to_continuum(const Eigen::Vector3d& xA) const;
  /// Writes the energy log as CSV (columns in docs/formats.md, "ESCM energy log"), atomically.
  void write_energy_csv(const std::string& path) const;
  /// Writes the atoms as a VTU point cloud (positions in m: the LAMMPS frame's Angstrom times
  /// 1e-10) with point data zone_index (0 INT, 1 IVC, 2 SVC), displacement_m since setup and
  /// velocity_m_per_s, then the `extra` arrays (one entry per atom in id order), and the field
  /// data `field` (e.g. time_s), atomically.
  void write_atoms_vtu(const std::string& path, const std::vector<PointArray>& extra = {},
                       const std::vector<FieldScalar>& field = {}) const;
  /// A restart point (between steps): rebuilds LAMMPS's neighbour lists, box and ghost atoms
  /// from the current positions (`run 0`), puts back the forces of the last substep, re-creates
  /// the Langevin fixes with the seeds of the next segment (their heat tallies carried as
  /// offsets) and returns the state. A run resumed from this state with restore() continues
  /// bit for bit as the run that called checkpoint() (on one MPI rank; atoms are never sorted,
  /// `atom_modify sort 0 0.0`). The rebuild itself changes the continuing run at round-off
  /// level compared with a run without the checkpoint.
  CouplerState checkpoint();
  /// After setup() of a coupler built from the same input, and after the solver's own state
  /// was restored: puts back the state of checkpoint() (cells, accumulators, energy log,
  /// atoms, forces, Langevin segment). Throws std::runtime_error if it does not fit.
  void restore(const CouplerState& st);
  /// Names of the LAMMPS groups: "escm_svc", "escm_ivc", "escm_int", "escm_free" (ivc + int).
  /// The fix IDs: escm_lint (INT Langevin, if any), escm_livc, escm_ext.

private:
  struct Impl;
  std::unique_ptr<Impl> d_;
};

} // namespace pnc::gimp::escm
