#pragma once
// CoupledRun: the state of one `pnc gimp couple` run between coupled steps (docs/escm.md): the
// continuum (Solver<2>) set up for the load case, the Coupler with its LAMMPS instance, the
// displacement-gradient post-processor (D79) and the observers, each of which owns one output
// (observers.hpp). The driver (escm_run.cpp) reads the input, builds the MD region
// (md_region.hpp), makes a CoupledRun, restores it from a checkpoint or not, calls step() until
// the schedule ends or a stop is requested, and writes checkpoints with save_checkpoint().
//
// Units: continuum SI (m, s, N per m of thickness); atoms in LAMMPS real (Angstrom).
#include "couple_input.hpp"
#include "md_region.hpp"

#include "pnc/gimp_coupler/escm.hpp"
#include "pnc/gimp_coupler/escm_checkpoint.hpp"
#include "pnc/gimp_coupler/escm_gradient.hpp"
#include "pnc/gimp_coupler/fracture.hpp"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace pnc::gimp::escm {

class CoupledRun;

/// One output of a coupled run (energy log, profile, VTU frames, crack record, ...): it sees
/// the run after every coupled step and at every frame, keeps what it needs in checkpoints,
/// writes its own file(s) and its part of summary.json. Every hook is optional.
class Observer {
public:
  virtual ~Observer() = default;
  /// After coupled step `done` (steps so far, 1-based), the gradient updated.
  virtual void on_step(const CoupledRun& run, long done) { (void)run, (void)done; }
  /// At frame `index` (1-based), after on_step() of the same step.
  virtual void on_frame(const CoupledRun& run, long index) { (void)run, (void)index; }
  /// Its bookkeeping into a checkpoint (CoupledCheckpoint::texts, tables).
  virtual void save(CoupledCheckpoint& ck) const { (void)ck; }
  /// Its bookkeeping back from a checkpoint (the file `ckpt_file`, for errors).
  virtual void restore(const CoupledCheckpoint& ck, const std::string& ckpt_file) {
    (void)ck, (void)ckpt_file;
  }
  /// Writes its file(s) (also when the run stopped early) and names them in `r`.
  virtual void write(const CoupledRun& run, CoupleSummary& r) const { (void)run, (void)r; }
  /// Its part of summary.json (a finished run only).
  virtual void summarize(const CoupledRun& run, nlohmann::json& sj) const { (void)run, (void)sj; }
};

/// The loaded edge: BC index, displacement component, specimen length along the load (m) and
/// the wave speed of the fundamental mode (m/s, for the damping of D75).
struct Loading {
  std::size_t bc = 2;
  int comp = 0;
  double length = 0.0, speed = 0.0;
};

/// Grid, calibrated material (D76), one particle per cell, the BCs of the load case (D80; the
/// loaded edge's box includes the padding beyond it, D77) and the pre-crack (D80, D81) with
/// growth criterion Gc (J/m^2).
Loading set_up_continuum(const CoupleInput& p, const LjFcc& lj, double Gc, Solver<2>& s);

/// The coupled steps of a run: continuum step dt (s) and its schedule.
struct Schedule {
  double dt = 0.0;                     ///< coupled step, s
  double t_settle = 0.0, t_load = 0.0; ///< end of the settle phase, length of the load ramp, s
  long nsteps = 0;                     ///< coupled steps of the whole run
  long frame_every = 0;                ///< steps between frames (> nsteps: none)
  long checkpoint_every = 0;           ///< steps between checkpoints (0: only at the end)
};

class CoupledRun {
public:
  /// Sets up the continuum for the calibration of `region` (built, MdRegion::build; kept by
  /// reference), checks the schwarz cut-off (D72) and the CFL step, creates `out_dir`, starts
  /// the coupler (LAMMPS) and the gradient tracker. Throws pnc::InputError (naming `src`) for
  /// an input this set-up cannot run.
  CoupledRun(const CoupleInput& in, MdRegion& region, const std::string& out_dir,
             const std::string& src);
  CoupledRun(const CoupledRun&) = delete;
  CoupledRun& operator=(const CoupledRun&) = delete;

  /// Adds an observer; they are called in the order added.
  void add(std::unique_ptr<Observer> o);
  /// One coupled step: the load ramp on the loaded edge, the coupler's step, the region's
  /// after_step(), the gradient update, with a crack every crack.every steps its J and growth
  /// (D38-D40, stopped by D81), then the observers (on_step, on_frame).
  void step();
  /// Fills `ck` (the coupler's restart point, Coupler::checkpoint(), the run's and the
  /// observers' bookkeeping; the caller sets input_path, input_text, short_mode, step and
  /// wall_s) and writes it (write_coupled_checkpoint). Returns the bytes written.
  std::size_t save_checkpoint(CoupledCheckpoint& ck);
  /// Puts back the state of a checkpoint of the same input (after construction, before any
  /// step). Throws pnc::InputError naming the checkpoint file if it does not fit.
  void restore(const CoupledCheckpoint& ck);
  /// Re-reads the current positions of the particles and atoms (positions(), atoms_x()).
  void gather();

  const CoupleInput& input() const { return in_; }
  const std::string& out_dir() const { return out_; }
  const Schedule& schedule() const { return sched_; }
  const Loading& loading() const { return ld_; }
  const LjFcc& calibration() const { return lj_; }
  double cell_size() const { return h_; } ///< m
  double Gc() const { return Gc_; }       ///< J/m^2, the continuum crack's criterion
  /// The region's work of separation across the crack line, J/m^2 (D83; 0: none).
  double separation_work() const { return wsep_; }
  /// Cases II/III: the first crack tip at the last J evaluation (every crack.every steps),
  /// before that evaluation's growth.
  const TipResult& last_tip() const { return tip_; }
  long steps_done() const { return done_; }
  const Solver<2>& solver() const { return s_; }
  const Coupler& coupler() const { return *cp_; }
  Coupler& coupler() { return *cp_; }
  const GradientTracker& gradient() const { return grad_; }
  double gradient_wall_s() const { return grad_wall_; }
  /// Continuum particles (after removing INT): their number and zone (-1 ordinary, 1 IVC
  /// probe, 2 SVC).
  std::size_t continuum_points() const { return ncont_; }
  const std::vector<int>& particle_zones() const { return pzone_; }
  /// Atom positions (Angstrom, LAMMPS frame, by id - 1) at the last gather().
  const std::vector<Eigen::Vector3d>& atoms_x() const { return gax_; }
  /// Gradient points: continuum particles then atoms (m), at the last gather().
  std::size_t gradient_points() const { return gx_.size(); }
  /// The displacement gradient H = F - I (9 components, row-major H_ij = du_i/dX_j, the z row
  /// and column 0) and the support flag of gradient points [b, e) as VTU point arrays
  /// (displacement_gradient_1, gradient_supported_1).
  std::vector<PointArray> gradient_arrays(std::size_t b, std::size_t e) const;
  const std::vector<std::unique_ptr<Observer>>& observers() const { return obs_; }

private:
  const CoupleInput in_;
  MdRegion& region_;
  const std::string out_, src_;
  LjFcc lj_;
  double h_ = 0.0, wsep_ = 0.0, Gc_ = 0.0;
  Solver<2> s_; // before cp_: the coupler keeps a reference
  Loading ld_;
  Schedule sched_;
  std::unique_ptr<Coupler> cp_;
  std::size_t ncont_ = 0;
  std::vector<int> pzone_;
  GradientTracker grad_;
  double grad_wall_ = 0.0;
  std::vector<Eigen::Vector2d> gx_;
  std::vector<int> gids_;
  std::vector<Eigen::Vector3d> gax_, gav_;
  std::vector<std::unique_ptr<Observer>> obs_;
  TipResult tip_;
  long done_ = 0;
};

/// Columns of the checkpoint table /run/table/crack_log (docs/formats.md "ESCM checkpoint").
constexpr int kCrackLogColumns = 24;

/// Named table / text of a checkpoint (the file `ckpt_file` for errors). A missing table is an
/// error unless rows <= 0 (then empty, rows x cols); rows < 0 accepts any row count.
CheckpointTable checkpoint_table(const CoupledCheckpoint& ck, const std::string& ckpt_file,
                                 const std::string& name, Eigen::Index rows, Eigen::Index cols);
/// "" if absent.
std::string checkpoint_text(const CoupledCheckpoint& ck, const std::string& name);

} // namespace pnc::gimp::escm
