// CoupledRun (coupled_run.hpp): set-up, one coupled step, checkpoint and restore of a
// `pnc gimp couple` run (docs/escm.md).
#include "coupled_run.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/gimp_coupler/escm_crack.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace pnc::gimp::escm {

namespace {

NodeBC<2> edge_bc(const std::string& name, Eigen::Vector2d lo, Eigen::Vector2d hi, bool x, bool y) {
  NodeBC<2> b;
  b.name = name;
  b.lo = lo;
  b.hi = hi;
  b.mask = {x, y};
  return b;
}

/// The region's calibration, after the schwarz-mode check of D72 (the SVC rings must be at
/// least as wide as the cut-off).
const LjFcc& checked_calibration(const CoupleInput& p, const MdRegion& region,
                                 const std::string& src) {
  const LjFcc& lj = region.calibration();
  if (p.mode == "schwarz" && p.svc * lj.a0_A < region.cutoff_A())
    fail(src, "svc_rings", std::to_string(p.svc),
         "in schwarz mode the SVC rings must be at least as wide as the cut-off (D72)");
  return lj;
}

} // namespace

/// Grid, calibrated material (D76), one particle per cell, the BCs of the load case (D80; the
/// loaded edge's box includes the padding beyond it, D77) and the pre-crack (D80, D81).
Loading set_up_continuum(const CoupleInput& p, const LjFcc& lj, double Gc, Solver<2>& s) {
  const double h = lj.a0_A * units::m_per_A;
  s.grid.h = h;
  // Two cells of padding; in shear (Case III) the left and right edges travel |strain| H along
  // x, so the x padding grows by that many cells (D90).
  const int padx =
      2 + (p.load == "shear" ? static_cast<int>(std::ceil(std::abs(p.strain) * p.ncy)) : 0);
  s.grid.origin = Eigen::Vector2d(-padx * h, -2 * h);
  s.grid.n = {p.ncx + 2 * padx + 1, p.ncy + 5};
  s.materials.push_back(std::make_shared<LinearElastic>(lj.density, lj.E(), lj.nu())); // D76
  for (int jy = 0; jy < p.ncy; ++jy)
    for (int ix = 0; ix < p.ncx; ++ix)
      s.particles.add(Eigen::Vector2d((ix + 0.5) * h, (jy + 0.5) * h),
                      Eigen::Vector2d::Constant(0.5 * h), lj.density * h * h, h * h, 0);
  const double W = p.ncx * h, H = p.ncy * h, t = 0.1 * h;
  const Eigen::Vector2d corner_lo(-t, -t), corner_hi(t, t);
  Loading ld;
  if (p.load == "tension_x") { // Case I: left x-fixed, right pulled in x
    s.bcs = {edge_bc("left", {-t, -10 * h}, {t, H + 10 * h}, true, false),
             edge_bc("corner", corner_lo, corner_hi, false, true),
             edge_bc("right", {W - t, -10 * h}, {W + h + t, H + 10 * h}, true, false)};
    ld = {2, 0, W, std::sqrt(lj.strip_modulus() / lj.density)};
  } else if (p.load == "tension_y") { // Case II: bottom y-fixed, top pulled in y
    s.bcs = {edge_bc("bottom", {-10 * h, -t}, {W + 10 * h, t}, false, true),
             edge_bc("corner", corner_lo, corner_hi, true, false),
             edge_bc("top", {-10 * h, H - t}, {W + 10 * h, H + h + t}, false, true)};
    ld = {2, 1, H, std::sqrt(lj.strip_modulus() / lj.density)};
  } else { // Case III: bottom fixed, top moved along x (simple shear). D90: with the crack's
    // mouth on the left edge, strain < 0 (top moved in -x) presses the faces together (closed,
    // frictionless contact, D37: pure mode II); strain > 0 opens them (mixed mode).
    s.bcs = {edge_bc("bottom", {-10 * h, -t}, {W + 10 * h, t}, true, true),
             edge_bc("top", {-10 * h, H - t}, {W + 10 * h, H + h + t}, true, false)};
    ld = {1, 0, H, std::sqrt(0.5 * (lj.C11 - lj.C12) / lj.density)};
  }
  if (p.crack) {
    const int bx0 = (p.ncx - p.nbx) / 2, by0 = (p.ncy - p.nby) / 2;
    // D80: 0.01 h above the node line (ties count as no crossing, D37); D81: the last
    // increment puts the tip in the middle of the cell column just before the block.
    s.cracks.push_back(line_edge_crack((by0 + p.nby / 2 + 0.01) * h, (p.crack_cells + 0.5) * h, h,
                                       Gc, bx0 - 1 - p.crack_cells));
  }
  return ld;
}

CoupledRun::CoupledRun(const CoupleInput& in, MdRegion& region, const std::string& out_dir,
                       const std::string& src)
    : in_(in), region_(region), out_(out_dir), src_(src), lj_(checked_calibration(in, region, src)),
      h_(lj_.a0_A * units::m_per_A),
      // D83: the crack line is a weak interface in both models: LJ epsilon x f across it in the
      // MD, and by default the continuum's Gc is its work of separation, f W_sep.
      wsep_(region.separation_work()), Gc_(in.crack_Gc > 0 ? in.crack_Gc : in.crack_f * wsep_),
      ld_(set_up_continuum(in_, lj_, Gc_, s_)), grad_(s_.grid.origin, in.gradient_cells * h_) {
  const CoupleInput& p = in_;
  const double omega1 = M_PI * ld_.speed / ld_.length;
  const double damping = 2 * p.damping_fraction * omega1; // D75
  Config c;
  c.md_setup = region.md_setup(p);
  // D93: the LJ energy shifted to zero at the cut-off (forces unchanged): otherwise every pair
  // crossing r_c changes the logged MD potential by -V(r_c) = 0.0163 epsilon with no work done
  // (the fifth FCC shell lies 2 % inside 2.5 sigma), and the energy log does not close.
  c.md_setup.push_back("pair_modify shift yes");
  c.md_offset = region.md_offset(p, h_);
  c.svc_rings = p.svc;
  c.ivc_rings = p.ivc;
  c.substeps = p.substeps;
  c.dt = p.substeps * p.dtau_fs * units::s_per_fs;
  c.mode = p.mode == "schwarz" ? Mode::schwarz : Mode::neumann;
  c.interior_temperature = p.temperature;
  c.interior_damp_fs = damping > 0 ? 1.0 / damping / units::s_per_fs : 0.0;
  c.ivc_damp_fs = damping > 0 ? c.interior_damp_fs : 1000.0;
  if (p.temperature > 0 && c.interior_damp_fs <= 0) c.interior_damp_fs = 1000.0;
  c.continuum_damping = damping;
  const double cfl_dt = 0.5 * h_ / std::sqrt(lj_.C11 / lj_.density);
  if (c.dt > cfl_dt)
    fail(src, "substeps", std::to_string(p.substeps),
         "substeps x md_timestep_fs exceeds the continuum CFL step " +
             std::to_string(cfl_dt / units::s_per_fs) + " fs");
  pnc::make_output_directory(out_);
  c.lammps_log = out_ + "/lammps.log";
  cp_ = std::make_unique<Coupler>(s_, c);
  cp_->setup();

  // Displacement gradients (docs/escm.md "Displacement gradient", D79): all continuum particles and
  // all atoms (projected on x, y) on a bilinear grid aligned with the continuum grid, updated at
  // every coupled step. IVC probes receive gradients but do not enter the nodal fit (their position
  // is a block-averaged copy of their atoms, D73).
  ncont_ = s_.particles.size();
  pzone_.assign(ncont_, static_cast<int>(Zone::none));
  for (const Cell& cell : cp_->cells())
    pzone_[cell.particle] = static_cast<int>(cell.zone);
  gather();
  {
    std::vector<char> contributes(gx_.size(), 1);
    for (std::size_t k = 0; k < ncont_; ++k)
      contributes[k] = pzone_[k] != static_cast<int>(Zone::ivc);
    grad_.reset(gx_, contributes);
  }

  // The schedule: settle, load ramp, hold; frames; checkpoints every checkpoint_every_ps of
  // simulated time (and at the end and when stopped).
  const double ps = 1e-12;
  sched_.dt = c.dt;
  sched_.t_settle = p.settle_ps * ps;
  sched_.t_load = p.load_ps * ps;
  const double t_end = sched_.t_settle + sched_.t_load + p.hold_ps * ps;
  sched_.nsteps = std::max(1L, std::lround(t_end / c.dt));
  sched_.frame_every = p.frames > 0 ? std::max(1L, sched_.nsteps / p.frames) : sched_.nsteps + 1;
  sched_.checkpoint_every =
      p.checkpoint_ps > 0 ? std::max(1L, std::lround(p.checkpoint_ps * ps / c.dt)) : 0;
}

void CoupledRun::add(std::unique_ptr<Observer> o) {
  obs_.push_back(std::move(o));
}

void CoupledRun::gather() {
  cp_->atoms(gids_, gax_, gav_);
  gx_.resize(ncont_ + gax_.size());
  for (std::size_t k = 0; k < ncont_; ++k)
    gx_[k] = s_.particles.x[k];
  for (std::size_t k = 0; k < gax_.size(); ++k)
    gx_[ncont_ + k] = cp_->to_continuum(gax_[k]);
}

std::vector<PointArray> CoupledRun::gradient_arrays(std::size_t b, std::size_t e) const {
  std::vector<PointArray> a = {{"displacement_gradient_1", "1", 9, {}, {}},
                               {"gradient_supported_1", "1", 1, {}, {}}};
  for (std::size_t k = b; k < e; ++k) {
    const Eigen::Matrix2d H = grad_.H(k); // in-plane; the z row and column are 0
    a[0].values.insert(a[0].values.end(),
                       {H(0, 0), H(0, 1), 0.0, H(1, 0), H(1, 1), 0.0, 0.0, 0.0, 0.0});
    a[1].values.push_back(grad_.supported()[k]);
  }
  return a;
}

void CoupledRun::step() {
  const CoupleInput& p = in_;
  const double tl = s_.time + 0.5 * sched_.dt - sched_.t_settle;
  s_.bcs[ld_.bc].velocity[ld_.comp] =
      (tl > 0 && tl < sched_.t_load)
          ? p.strain * ld_.length / sched_.t_load * (1 - std::cos(2 * M_PI * tl / sched_.t_load))
          : 0.0;
  cp_->step();
  region_.after_step(s_, sched_.t_settle, sched_.dt, ld_.comp);
  {
    const auto g0 = std::chrono::steady_clock::now();
    gather();
    grad_.update(gx_);
    grad_wall_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - g0).count();
  }
  ++done_;
  if (p.crack && done_ % p.crack_every == 0) { // D38-D40; the tip stops before the block (D81)
    const auto tips = crack_tips(s_);
    tip_ = tips.empty() ? TipResult{} : tips.front();
    grow_cracks(s_, tips);
  }
  for (const auto& o : obs_)
    o->on_step(*this, done_);
  if (done_ % sched_.frame_every == 0)
    for (const auto& o : obs_)
      o->on_frame(*this, done_ / sched_.frame_every);
}

std::size_t CoupledRun::save_checkpoint(CoupledCheckpoint& ck) {
  ck.coupler = cp_->checkpoint();
  ck.nsteps = sched_.nsteps;
  ck.time_s = s_.time;
  const auto gn = static_cast<Eigen::Index>(grad_.size());
  CheckpointTable gF(gn, 4), gs(gn, 1), gsc(1, 2), bcr(static_cast<Eigen::Index>(s_.bcs.size()), 2);
  for (Eigen::Index i = 0; i < gn; ++i) {
    const Eigen::Matrix2d& F = grad_.F()[static_cast<std::size_t>(i)];
    gF.row(i) << F(0, 0), F(0, 1), F(1, 0), F(1, 1);
    gs(i, 0) = grad_.supported()[static_cast<std::size_t>(i)];
  }
  gsc << static_cast<double>(grad_.increments()), grad_wall_;
  for (std::size_t b = 0; b < s_.bcs.size(); ++b)
    bcr.row(static_cast<Eigen::Index>(b)) = s_.bcs[b].reaction.transpose();
  ck.tables = {
      {"gradient_F", gF}, {"gradient_supported", gs}, {"gradient", gsc}, {"bc_reaction", bcr}};
  ck.texts.clear();
  for (const auto& o : obs_)
    o->save(ck);
  // docs/formats.md "ESCM checkpoint": the crack entries are always there (empty without a
  // crack), whoever writes them.
  ck.texts.emplace("crack_csv", "");
  ck.texts.emplace("frame_log", "[]");
  ck.tables.emplace("crack_log", CheckpointTable(0, kCrackLogColumns));
  return write_coupled_checkpoint(out_, s_, ck);
}

void CoupledRun::restore(const CoupledCheckpoint& ck) {
  const std::string ckpt_file = checkpoint_path(out_);
  if (ck.nsteps != sched_.nsteps)
    fail(ckpt_file, "/run/nsteps", std::to_string(ck.nsteps),
         "the input gives " + std::to_string(sched_.nsteps) + " coupled steps");
  restore_continuum(out_, ck, s_);
  cp_->restore(ck.coupler);
  gather();
  const auto gn = static_cast<Eigen::Index>(gx_.size());
  const CheckpointTable gF = checkpoint_table(ck, ckpt_file, "gradient_F", gn, 4),
                        gs = checkpoint_table(ck, ckpt_file, "gradient_supported", gn, 1),
                        gsc = checkpoint_table(ck, ckpt_file, "gradient", 1, 2);
  std::vector<Eigen::Matrix2d> F(gx_.size());
  std::vector<char> sup(gx_.size());
  for (Eigen::Index i = 0; i < gn; ++i) {
    F[static_cast<std::size_t>(i)] << gF(i, 0), gF(i, 1), gF(i, 2), gF(i, 3);
    sup[static_cast<std::size_t>(i)] = static_cast<char>(gs(i, 0));
  }
  grad_.restore(gx_, F, sup, static_cast<long>(gsc(0, 0)));
  grad_wall_ = gsc(0, 1);
  const CheckpointTable bcr =
      checkpoint_table(ck, ckpt_file, "bc_reaction", static_cast<Eigen::Index>(s_.bcs.size()), 2);
  for (std::size_t b = 0; b < s_.bcs.size(); ++b)
    s_.bcs[b].reaction = bcr.row(static_cast<Eigen::Index>(b)).transpose();
  for (const auto& o : obs_)
    o->restore(ck, ckpt_file);
  done_ = ck.step;
}

CheckpointTable checkpoint_table(const CoupledCheckpoint& ck, const std::string& ckpt_file,
                                 const std::string& name, Eigen::Index rows, Eigen::Index cols) {
  const auto it = ck.tables.find(name);
  if (it == ck.tables.end()) {
    if (rows <= 0) return CheckpointTable(0, cols); // e.g. no crack records yet
    fail(ckpt_file, "/run/table/" + name, "<missing>", "needed to resume");
  }
  if ((rows >= 0 && it->second.rows() != rows) || it->second.cols() != cols)
    fail(ckpt_file, "/run/table/" + name,
         std::to_string(it->second.rows()) + " x " + std::to_string(it->second.cols()),
         "does not fit this set-up");
  return it->second;
}

std::string checkpoint_text(const CoupledCheckpoint& ck, const std::string& name) {
  const auto it = ck.texts.find(name);
  return it == ck.texts.end() ? std::string() : it->second;
}

} // namespace pnc::gimp::escm
