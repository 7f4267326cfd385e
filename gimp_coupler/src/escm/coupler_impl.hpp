#pragma once
// Coupler::Impl (escm.hpp): the state of the ESCM coupler and its parts, shared by
// escm.cpp (the coupled step), escm_setup.cpp (set-up), escm_state.cpp (checkpoint and
// restore) and escm_output.cpp (CSV, VTU). Private to the coupler library. Units as in
// escm.hpp: continuum SI, LAMMPS real (Angstrom, fs, kcal/mol).
#include "pnc/gimp_coupler/escm.hpp"
#include "pnc/md/runner.hpp"

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pnc::gimp::escm {

using Clock = std::chrono::steady_clock;
inline double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

/// Throws std::runtime_error("escm: config field 'F': value 'V': rule").
[[noreturn]] void bad_config(const std::string& field, const std::string& value,
                             const std::string& rule);

struct Coupler::Impl {
  Solver<2>& solver;
  Config cfg;
  std::unique_ptr<md::Lammps> lmp; // in-process, through md/ only (D346)
  std::vector<Cell> cells;
  std::vector<int> ivc_cells;          // indices into cells
  std::vector<int> cell_of_id;         // id -> cell index or -1 (INT)
  std::vector<Zone> zone_of_id;        // id -> zone
  std::vector<Eigen::Vector3d> x_init; // id - 1 -> initial position, A
  int natoms = 0;
  double Lz_A = 0.0;
  double dtau_fs = 0.0;
  // Gamma nodes
  std::vector<std::int64_t> gamma;
  std::vector<std::vector<std::pair<int, double>>> gamma_cells; // per Gamma node: (ivc k, w)
  // Callback accumulators per IVC cell (index into ivc_cells)
  std::vector<Eigen::Vector2d> csum;
  std::vector<double> fx, fy; // per-atom force by ivc slot, kcal/mol/A
  long block_start = 0;
  int nsub = 0;
  Timing timing;
  std::vector<EnergyRow> log;
  EnergyRow acc; // running sums
  double pe0 = 0.0;
  std::array<int, 3> counts{};
  bool ready = false;
  // Checkpoints (CouplerState): Langevin re-creations so far and the heat their predecessors
  // removed, J (slab).
  int segment = 0;
  double heat_off_int = 0.0, heat_off_ivc = 0.0;

  explicit Impl(Solver<2>& s, Config c) : solver(s), cfg(std::move(c)) {}

  void cmd(const std::string& c) { lmp->cmd(c); }

  // escm.cpp: the coupled step
  /// The fix-external callback (md::ExternalForce): IVC forces, IVC centroid sums.
  void callback(md::Step step, int nlocal, const md::AtomId* ids, double** x, double** fext);
  std::vector<Eigen::Vector2d> centroids() const; ///< of the IVC cells now (A)
  double compute_scalar(const char* id) const;
  double fix_scalar(const char* id) const;
  void step();

  // escm_setup.cpp: set-up
  void validate();
  void setup();
  std::pair<int, int> cell_of(const Eigen::Vector2d& x) const; ///< grid cell of a point (m)
  std::map<std::pair<int, int>, std::size_t> particle_cells() const;
  std::map<std::pair<int, int>, std::vector<int>> start_lammps();
  std::vector<char> build_cells(const std::map<std::pair<int, int>, std::size_t>& cellmap,
                                const std::map<std::pair<int, int>, std::vector<int>>& atoms);
  void remove_interior(const std::vector<char>& remove);
  void gamma_nodes();
  void md_groups_and_fixes();
  void langevin_fixes();

  // escm_state.cpp: checkpoint and restore
  // per-atom arrays by id (md/atoms.hpp: unpacked image flags, every atom local)
  std::vector<double> gather(const char* name, int count) const;
  void scatter(const char* name, const std::vector<double>& v) const;
  void apply_atoms(const std::vector<double>& x, const std::vector<double>& v,
                   const std::vector<double>& f, const std::vector<double>& image);
  CouplerState save() const;
  CouplerState checkpoint();
  void restore(const CouplerState& st);
};

} // namespace pnc::gimp::escm
