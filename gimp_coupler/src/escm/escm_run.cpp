// `pnc gimp couple`: the driver of a coupled run (escm_run.hpp, docs/escm.md): the input
// (couple_input.hpp), the MD region from the registry (md_region.hpp), the CoupledRun with its
// observers (coupled_run.hpp, observers.hpp), the step loop with its checkpoint schedule and
// stop requests, and the outputs at the end.
#include "pnc/gimp_coupler/escm_run.hpp"

#include "couple_input.hpp"
#include "coupled_run.hpp"
#include "md_region.hpp"
#include "observers.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/progress.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/gimp_coupler/escm_checkpoint.hpp"

#include <chrono>
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>

namespace pnc::gimp::escm {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPs = 1e-12;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// A stop request (CoupleOptions::stop) ends the run after coupled step `done` when that step
/// is on the checkpoint schedule (every `every` steps): its checkpoint is one the uninterrupted
/// run writes too, so the resumed run is bit for bit that run (the Langevin fixes are re-created
/// at every checkpoint, docs/escm.md). A second request, or no schedule, stops at once.
bool stop_now(const pnc::StopToken* stop, long done, long every, bool progress) {
  if (stop == nullptr || !stop->requested()) return false;
  if (every <= 0 || done % every == 0 || stop->count() >= 2) return true;
  static const pnc::StopToken* told = nullptr;
  if (progress && told != stop) {
    told = stop;
    std::cerr << fmt::format(
        "pnc gimp couple: stop requested: stopping at the next checkpoint (step {}); "
        "signal again to stop now (the resumed run then equals this one to round-off, "
        "not bit for bit)\n",
        (done / every + 1) * every);
  }
  return false;
}

/// Checkpoint and resume: a directory that holds a run needs --resume, and --resume needs the
/// input the run was started with (docs/escm.md "Checkpoint and resume"). Returns the
/// checkpoint to continue from, or null (start at t = 0).
std::unique_ptr<CoupledCheckpoint>
open_resume(const CoupleOptions& o, const std::string& input_text, const std::string& ckpt_file) {
  const std::string& src = o.input;
  std::unique_ptr<CoupledCheckpoint> from;
  if (o.resume && std::filesystem::exists(ckpt_file)) {
    from = std::make_unique<CoupledCheckpoint>(read_coupled_checkpoint(o.out_dir));
    if (from->short_mode != o.short_mode)
      fail(src, "--short", o.short_mode ? "given" : "not given",
           "the run in " + o.out_dir + " was started " + (from->short_mode ? "with" : "without") +
               " --short (" + ckpt_file + "): --resume must repeat it");
    check_same_input(src, from->input_text, input_text, ckpt_file);
  } else if (o.resume) {
    if (o.progress)
      std::cerr << fmt::format(
          "pnc gimp couple: --resume: no checkpoint in {}, starting at t = 0\n", o.out_dir.c_str());
  }
  refuse_existing_run(o.out_dir, o.resume, {"checkpoint.h5", "summary.json"});
  return from;
}

/// Writes the run's checkpoints and counts them in the summary.
class Checkpointer {
public:
  Checkpointer(CoupledRun& run, const CoupleOptions& o, std::string input_text, CoupleSummary& r)
      : run_(run), o_(o), input_text_(std::move(input_text)), r_(r) {}
  void write(long done, double wall_s) {
    const auto t0 = Clock::now();
    CoupledCheckpoint ck;
    ck.input_path = o_.input;
    ck.input_text = input_text_;
    ck.short_mode = o_.short_mode;
    ck.step = done;
    ck.wall_s = wall_s;
    r_.checkpoint_bytes = run_.save_checkpoint(ck);
    ++r_.checkpoints;
    r_.checkpoint_s += since(t0);
  }

private:
  CoupledRun& run_;
  const CoupleOptions& o_;
  const std::string input_text_;
  CoupleSummary& r_;
};

/// The run's numbers and the observers' files, written whether it finished or stopped.
void collect(const CoupledRun& run, long steps, CoupleSummary& r) {
  const Solver<2>& s = run.solver();
  r.steps = steps;
  r.time_s = s.time;
  r.outside_share = run.coupler().timing().outside_share();
  r.atoms = run.coupler().zone_counts();
  r.particles = s.particles.size();
  r.energy = run.coupler().energy_log().back();
  r.reaction_left = s.bcs[0].reaction[run.loading().comp];
  r.lammps_log = run.out_dir() + "/lammps.log";
  for (const auto& ob : run.observers())
    ob->write(run, r); // frames, profile.csv, energy.csv, crack.csv
}

/// The coupled steps from the run's current step to the end of the schedule, or to a stop
/// (a stop request, CoupleOptions::stop_after_steps) with a checkpoint; checkpoints on the
/// schedule. Returns the wall time of the steps in this session, s.
double run_steps(CoupledRun& run, const CoupleOptions& o, Checkpointer& ckpt, double wall_before,
                 CoupleSummary& r) {
  const Schedule& sc = run.schedule();
  const long k0 = run.steps_done(), nsteps = sc.nsteps;
  const auto w0 = Clock::now();
  ProgressOptions po; // a line every 2 s and the last; steps before a resume not in the rate
  po.every_s = 2.0;
  po.enabled = o.progress;
  Progress bar("pnc gimp couple", static_cast<double>(nsteps), "steps", po); // D344, D345
  bar.skip(static_cast<double>(k0));
  for (long k = k0; k < nsteps; ++k) {
    run.step();
    bar.set(static_cast<double>(k + 1), fmt::format("t = {:.2f} ps", run.solver().time / kPs));
    const long done = k + 1;
    const bool stop = stop_now(o.stop, done, sc.checkpoint_every, o.progress);
    if (done < nsteps && (stop || (o.stop_after_steps > 0 && done >= o.stop_after_steps))) {
      ckpt.write(done, wall_before + since(w0));
      r.signal = stop ? o.stop->signal() : 0;
      r.interrupted = stop ? "signal " + std::to_string(r.signal) : "max_steps";
      break;
    }
    if (sc.checkpoint_every > 0 && done % sc.checkpoint_every == 0 && done < nsteps)
      ckpt.write(done, wall_before + since(w0));
  }
  return since(w0);
}

} // namespace

CoupleSummary run_couple(const CoupleOptions& o) {
  const std::string& src = o.input;
  const CoupleInput p = read_couple_input(src, o.short_mode);
  const std::string ckpt_file = checkpoint_path(o.out_dir);
  const std::string input_text = read_input_as_json_text(src); // D357
  const std::unique_ptr<CoupledCheckpoint> resume_from = open_resume(o, input_text, ckpt_file);
  // The MD region and the continuum's calibration to it: the LJ crystal's lattice sums (D76) or
  // the measured (or given) constants of the built polymer block (D101, D102).
  const std::unique_ptr<MdRegion> region = make_md_region(p.md_type, src);
  region->build(p, o.out_dir, src, o.progress);
  CoupledRun run(p, *region, o.out_dir, src);
  run.add(make_frames());
  run.add(make_profile(run));
  run.add(make_energy_log());
  if (p.crack) run.add(make_crack_record(run, region->bond_monitor(run.coupler(), p), o.progress));

  CoupleSummary r;
  r.checkpoint = ckpt_file;
  double wall_before = 0.0;
  if (resume_from) {
    run.restore(*resume_from);
    wall_before = resume_from->wall_s;
    r.resumed = true;
    r.start_step = run.steps_done();
    if (o.progress)
      std::cerr << fmt::format("pnc gimp couple: resumed from {} at step {}/{} (t = {:.2f} ps)\n",
                               ckpt_file.c_str(), run.steps_done(), run.schedule().nsteps,
                               run.solver().time / kPs);
  }
  Checkpointer ckpt(run, o, input_text, r);
  r.wall_s = wall_before + run_steps(run, o, ckpt, wall_before, r);
  if (!r.interrupted.empty()) { // stopped with a checkpoint: the CSVs so far, no summary
    collect(run, run.solver().steps, r);
    if (o.progress)
      std::cerr << fmt::format(
          "pnc gimp couple: stopped ({}) after step {}/{} (t = {:.2f} ps); checkpoint "
          "{}: continue with --resume\n",
          r.interrupted.c_str(), r.steps, run.schedule().nsteps, run.solver().time / kPs,
          ckpt_file.c_str());
    return r;
  }
  ckpt.write(run.schedule().nsteps, r.wall_s);
  collect(run, run.schedule().nsteps, r);
  write_couple_summary(run, *region, o, r);
  if (o.plot) { // announced: no silent seconds after the last step's ETA (D344)
    Phase phase("pnc gimp couple", "plotting profile.png, energy.png", o.progress);
    plot_couple(o.out_dir, p.crack, r);
    phase.done("plotting done");
  }
  return r;
}

} // namespace pnc::gimp::escm
