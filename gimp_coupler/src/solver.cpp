// The explicit uGIMP solver (solver.hpp): set-up, the step's sequence, energies. SI units. The
// grid transfers of a step are in solver_step.cpp, the crack geometry and contact in
// solver_crack.cpp, the thread pool in solver_pool.hpp.
#include "pnc/gimp_coupler/solver.hpp"
#include "pnc/core/error.hpp"

#include "solver_pool.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace pnc::gimp {

namespace {
/// The source named by a refused solver set-up (a host that fills Solver itself; `pnc gimp
/// run` checks its input file before).
constexpr const char* kSetup = "<gimp solver set-up>";
std::string num(double v) {
  return fmt::format("{:g}", v);
}
} // namespace

template <int D>
void Particles<D>::add(const Vec& pos, const Vec& half, double mass, double volume, int material,
                       const Vec& vel) {
  x.push_back(pos);
  x0.push_back(pos);
  v.push_back(vel);
  l.push_back(half);
  fext.push_back(Vec::Zero());
  m.push_back(mass);
  V0.push_back(volume);
  V.push_back(volume);
  F.push_back(Mat::Identity());
  sigma.push_back(Mat3::Zero());
  W.push_back(0.0);
  mat.push_back(material);
}

template <int D> void Solver<D>::initialize(bool fresh_state) {
  auto& P = particles;
  if (!(grid.h > 0.0)) fail(kSetup, "grid.h", num(grid.h), "the grid cell size must be > 0 (m)");
  for (int a = 0; a < D; ++a)
    if (grid.n[a] < 3)
      fail(kSetup, "grid.n", std::to_string(grid.n[a]), "the grid needs >= 3 nodes per axis");
  if (materials.empty()) fail(kSetup, "materials", "none", "at least one material is needed");
  if (threads < 1) threads = 1;
  const std::size_t n = P.size();
  if (n == 0) fail(kSetup, "particles", "none", "at least one particle is needed");
  int stride = 0;
  for (const auto& mptr : materials)
    stride = std::max(stride, mptr->n_state());
  double msum = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    if (P.mat[p] < 0 || P.mat[p] >= static_cast<int>(materials.size()))
      fail(kSetup, "particle " + std::to_string(p) + " material", std::to_string(P.mat[p]),
           "must name one of the " + std::to_string(materials.size()) + " materials (0-based)");
    for (int a = 0; a < D; ++a)
      if (!(P.l[p][a] > 0.0) || P.l[p][a] > 0.5 * grid.h * (1 + 1e-12))
        fail(kSetup, "particle " + std::to_string(p) + " half-length", num(P.l[p][a]),
             "must be in (0, h/2] (uGIMP), h = " + num(grid.h) + " m");
    if (!(P.m[p] > 0.0) || !(P.V0[p] > 0.0))
      fail(kSetup, "particle " + std::to_string(p) + " mass, volume",
           num(P.m[p]) + " kg, " + num(P.V0[p]) + " m^3", "mass and volume must be > 0");
    msum += P.m[p];
  }
  mass_floor_ = 1e-10 * msum / static_cast<double>(n);
  if (fresh_state) {
    P.state_stride = stride;
    P.state.assign(n * static_cast<std::size_t>(stride), 0.0);
    std::vector<double> s1(static_cast<std::size_t>(std::max(stride, 1)));
    for (std::size_t p = 0; p < n; ++p) {
      const Material& mt = *materials[static_cast<std::size_t>(P.mat[p])];
      double* s = P.state.data() + p * static_cast<std::size_t>(stride);
      mt.init_state(s);
      const Mat3 F3 = to3<D>(P.F[p]);
      std::copy(s, s + stride, s1.begin());
      mt.update(F3, F3, s, s1.data(), P.sigma[p], P.W[p]);
      std::copy(s1.begin(), s1.begin() + stride, s);
      P.V[p] = P.V0[p] * P.F[p].determinant();
    }
  } else if (P.state_stride != stride || P.state.size() != n * static_cast<std::size_t>(stride)) {
    fail(kSetup, "particle state", std::to_string(P.state.size()) + " values",
         "restored state arrays must match the materials (" + std::to_string(stride) +
             " per particle)");
  }
  for (std::size_t p = 0; p < n; ++p) {
    Stencil<D> st;
    if (!compute_stencil(grid, P.x[p], P.l[p], st)) left_grid(p);
  }
  nnodes_ = static_cast<std::size_t>(grid.nodes());
  for (auto& c : cracks) {
    if constexpr (D == 2) {
      if (c.points.size() < 2)
        fail(kSetup, "crack '" + c.name + "' points", std::to_string(c.points.size()),
             "a 2-D crack needs at least 2 points");
    } else {
      const std::string why = check_planar_crack(c);
      if (!why.empty()) fail(kSetup, "crack '" + c.name + "'", "", why);
      if (c.growth.Gc > 0.0 && c.growth.prescribed) // D43: fronts advance in the plane
        fail(kSetup, "crack '" + c.name + "' growth direction", "prescribed",
             "a prescribed growth direction is 2-D only; a 3-D front advances in the crack "
             "plane, normal to itself (D43)");
    }
  }
  nfields_ = cracks.empty() ? 1 : 2;
  const std::size_t nn = nnodes_ * static_cast<std::size_t>(nfields_);
  fmask_.assign(cracks.empty() ? 0 : n, 0u);
  gu_.assign(cracks.empty() ? 0 : nn, Vec::Zero());
  update_crack_geometry();
  if (!(damping >= 0.0)) fail(kSetup, "damping", num(damping), "must be >= 0 (1/s)");
  const double tol = 1e-9 * grid.h;
  bcmask_.assign(nnodes_, 0);
  for (auto& bc : bcs) {
    bc.nodes.clear();
    for (std::size_t i = 0; i < nnodes_; ++i) {
      const Vec X = grid.position(static_cast<std::int64_t>(i));
      bool in = true;
      for (int a = 0; a < D; ++a)
        in = in && X[a] >= bc.lo[a] - tol && X[a] <= bc.hi[a] + tol;
      if (in) {
        bc.nodes.push_back(static_cast<std::int64_t>(i));
        for (int a = 0; a < D; ++a)
          if (bc.mask[a]) bcmask_[i] |= static_cast<unsigned char>(1u << a);
      }
    }
  }
  gm_.assign(nn, 0.0);
  gp_.assign(nn, Vec::Zero());
  gfi_.assign(nn, Vec::Zero());
  gfe_.assign(nn, Vec::Zero());
  gfi0_.assign(nn, Vec::Zero());
  gvs_.assign(nn, Vec::Zero());
  gvn_.assign(nn, Vec::Zero());
  active_.assign(nn, 0);
  wval_.resize(n);
  wder_.resize(n);
  law_scratch_stride_ = 0;
  for (const auto& mt : materials)
    law_scratch_stride_ =
        std::max(law_scratch_stride_, static_cast<std::size_t>(std::max(mt->n_scratch(), 0)));
  law_scratch_.assign(n * law_scratch_stride_, 0.0); // (D416: nothing carried over)
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), std::size_t{0});
  if (threads > 1 && (!pool_ || pool_->size() != threads))
    pool_ = std::make_shared<ThreadPool>(threads);
  if (threads == 1) pool_.reset();
  buf_.resize(threads > 1 ? static_cast<std::size_t>(threads) : 0);
  scratch_.resize(static_cast<std::size_t>(threads)); // D355: no allocation per step
  for (auto& sc : scratch_) {
    sc.sts.resize(Scratch::kChunk);
    sc.F0.resize(Scratch::kChunk);
    sc.F1.resize(Scratch::kChunk);
  }
  for (auto& b : buf_) {
    b.m.assign(nn, 0.0);
    b.p.assign(nn, Vec::Zero());
    b.fi.assign(nn, Vec::Zero());
    b.fe.assign(nn, Vec::Zero());
  }
  touched_.assign(static_cast<std::size_t>(threads), {0, nn}); // (the first P2G zeroes it all)
  advise_huge_pages();                                         // D430
  touch_lo_ = 0; // the first step's node passes: every node (D411)
  touch_hi_ = nn;
  update_energies();
  if (fresh_state) {
    energy.initial = energy.kinetic + energy.strain;
    energy.external_work = energy.boundary_work = energy.damping_work = 0.0;
  }
}

template <int D> void Solver<D>::update_crack_geometry() {
  crack_nodes_.clear();
  if (cracks.empty()) return;
  const double h = grid.h;
  crack_lo_ = Vec::Constant(1e300);
  crack_hi_ = Vec::Constant(-1e300);
  auto extend = [&](const Vec& q) {
    crack_lo_ = crack_lo_.cwiseMin(q);
    crack_hi_ = crack_hi_.cwiseMax(q);
  };
  for (auto& c : cracks) {
    if constexpr (D == 2) {
      for (const auto& q : c.points)
        extend(q);
      // Tips marked -1: an end is a tip if material lies just ahead of it (D38).
      for (int end = 0; end < 2; ++end) {
        if (c.tip[static_cast<std::size_t>(end)] >= 0) continue;
        const std::size_t m = c.points.size();
        const Vec q = end == 0 ? c.points[0] : c.points[m - 1];
        const Vec prev = end == 0 ? c.points[1] : c.points[m - 2];
        const Vec probe = q + h * (q - prev).normalized();
        bool inside = false;
        for (std::size_t p = 0; p < particles.size() && !inside; ++p)
          inside = (particles.x0[p] - probe).squaredNorm() <= h * h;
        c.tip[static_cast<std::size_t>(end)] = inside ? 1 : 0;
      }
    } else {
      for (const auto& q : c.corners)
        extend(q);
      const std::string why = resolve_fronts(c, particles, h); // D42
      if (!why.empty()) fail(kSetup, "crack '" + c.name + "'", "", why);
    }
  }
  crack_lo_.array() -= 2.0 * h;
  crack_hi_.array() += 2.0 * h;
  for (std::size_t i = 0; i < nnodes_; ++i)
    if (near_crack(grid.position(static_cast<std::int64_t>(i)))) crack_nodes_.push_back(i);
}

template <int D> double Solver<D>::stable_dt() const {
  double c = 0.0;
  for (const auto& m : materials)
    c = std::max(c, m->wave_speed());
  double v2 = 0.0;
  for (const auto& v : particles.v)
    v2 = std::max(v2, v.squaredNorm());
  return cfl * grid.h / (c + std::sqrt(v2));
}

template <int D> void Solver<D>::left_grid(std::size_t p) const {
  std::ostringstream s;
  s << "at (";
  for (int a = 0; a < D; ++a)
    s << (a ? ", " : "") << particles.x[p][a];
  s << ") m it left the background grid: enlarge the grid";
  pnc::fail_simulation("gimp: particle " + std::to_string(p), steps, time, "s", s.str());
}

template <int D> void Solver<D>::external_forces(double t) {
  auto& P = particles;
  const Vec g = gravity * gravity_ramp(t);
  has_fext_ = !tractions.empty() || g.squaredNorm() > 0.0;
  if (!has_fext_) return;
  for (std::size_t p = 0; p < P.size(); ++p)
    P.fext[p] = P.m[p] * g;
  for (const auto& tr : tractions) {
    const double f = tr.ramp(t);
    // decision D44: the traction acts on the surface the selected strip spans. Its force,
    // traction x (projected area of the strip), is shared among the strip's particles in
    // proportion to their volume: particle p gets V_p / depth, with depth the strip's extent
    // along `axis` in the reference configuration (particle faces). A strip one particle deep
    // gives each particle its face area; a deeper strip the same total force at any resolution.
    if (tr.particles.empty()) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t p : tr.particles) {
      lo = std::min(lo, P.x0[p][tr.axis] - P.l[p][tr.axis]);
      hi = std::max(hi, P.x0[p][tr.axis] + P.l[p][tr.axis]);
    }
    const double depth = hi - lo;
    for (std::size_t p : tr.particles) {
      double volume = 1.0;
      for (int a = 0; a < D; ++a)
        volume *= 2.0 * P.l[p][a];
      P.fext[p] += f * (volume / depth) * tr.traction;
    }
  }
}

template <int D> void Solver<D>::step(double dt) {
  auto& P = particles;
  const double t = time;

  if (sort_every > 0 && steps % sort_every == 0) sort_particles(); // D354

  // 0. P2G at x^t with f^ext(t + dt).
  external_forces(t + dt);
  if (!has_fext_ && !fext_zeroed_) {
    std::fill(P.fext.begin(), P.fext.end(), Vec::Zero());
    std::fill(gfe_.begin(), gfe_.end(), Vec::Zero());
    fext_zeroed_ = true;
  }
  if (has_fext_) fext_zeroed_ = false;
  scatter();
  // 1. nodal velocities v^t (kept in gp_) and v*.
  grid_velocities(dt);
  if (nfields_ > 1) contact(gp_); // as NairnMPM: on the P2G velocities too
  constrain(gp_, t, true);
  if (nfields_ > 1) contact(gvs_);
  constrain(gvs_, t + 0.5 * dt, true);

  // 2. F, stress (weights at x^t), and 3. f^int,* = -sum sigma* grad S V^t in the same pass.
  update_stress(dt);

  // 4. p^t+dt, v^t+dt (with the damping work, D41), reactions.
  const double wdamp = advance_grid(dt);
  if (nfields_ > 1) contact(gvn_);
  constrain(gvn_, t + dt, true);
  const double wbc = reactions(dt, t);

  // 5. G2P: positions with v*, velocities with the nodal change (FLIP), energies.
  g2p(dt);
  energy.boundary_work += wbc;
  energy.damping_work += wdamp;
  time = t + dt;
  ++steps;
}

template <int D> void Solver<D>::update_energies() {
  double ke = 0.0, se = 0.0;
  const auto& P = particles;
  for (std::size_t p = 0; p < P.size(); ++p) {
    ke += 0.5 * P.m[p] * P.v[p].squaredNorm();
    se += P.V0[p] * P.W[p];
  }
  energy.kinetic = ke;
  energy.strain = se;
}

template <int D> typename Solver<D>::Vec Solver<D>::total_reaction() const {
  Vec r = Vec::Zero();
  for (const auto& bc : bcs)
    r += bc.reaction;
  return r;
}

template struct Particles<2>;
template struct Particles<3>;
template class Solver<2>;
template class Solver<3>;

} // namespace pnc::gimp
