// The grid transfers of one explicit uGIMP step (solver.hpp, Solver::step): P2G, nodal
// velocities, stress update with the internal forces, the nodal update with its damping work,
// the reactions, G2P. SI units.
#include "pnc/core/error.hpp"
#include "pnc/gimp_coupler/solver.hpp"
#include "pnc/gimp_coupler/stencil_weights.hpp"

#include "solver_pool.hpp"
#include "tensor_passes.hpp"

#include <algorithm>
#include <array>
#include <exception>
#include <limits>
#include <stdexcept>

namespace pnc::gimp {

using detail::block;
using detail::par;

namespace {
constexpr std::size_t kWeightChunk = 64; // particles per ugimp_weights call in P2G (D376)

/// The doubles of an array of Eigen fixed-size vectors (D per node, no padding), as the row
/// kernels take them (tensor_passes.hpp).
template <class V> double* lanes(V* v) {
  static_assert(sizeof(V) == V::SizeAtCompileTime * sizeof(double), "unpadded vectors");
  return reinterpret_cast<double*>(v);
}
template <class V> const double* lanes(const V* v) {
  static_assert(sizeof(V) == V::SizeAtCompileTime * sizeof(double), "unpadded vectors");
  return reinterpret_cast<const double*>(v);
}
} // namespace

// P2G of m, p, f^int (sigma^t, V^t), f^ext at x^t. (The f^int,* scatter happens in the stress
// update of step().)
template <int D> void Solver<D>::scatter() {
  auto& P = particles;
  const int T = threads;
  // the nodes the last step's P2G touched (D411); until this pass ends, every node counts as
  // touched (a particle that leaves the grid throws part-way)
  const std::size_t last_lo = touch_lo_, last_hi = touch_hi_;
  touch_lo_ = 0;
  touch_hi_ = gm_.size();
  // One thread: the global arrays are non-zero only there, and at the nodes where constrain()
  // wrote velocities into gp_ (boundary conditions; their constrained components are written
  // again after each use, but the sums start clean), zeroed here; every node with cracks or
  // nodes prescribed by a coupling (D411).
  const bool one_range = T == 1 && nfields_ == 1 && prescribed_nodes.empty();
  if (one_range)
    for (const auto& bc : bcs)
      for (std::int64_t i : bc.nodes)
        gp_[static_cast<std::size_t>(i)].setZero();
  par(pool_.get(), [&](int t) {
    double* m = T > 1 ? buf_[t].m.data() : gm_.data();
    Vec* pp = T > 1 ? buf_[t].p.data() : gp_.data();
    Vec* fi = T > 1 ? buf_[t].fi.data() : gfi_.data();
    Vec* fe = T > 1 ? buf_[t].fe.data() : gfe_.data();
    const std::size_t nn = gm_.size();
    // A thread's copy is zeroed where the last step wrote it, not over the whole grid (D410);
    // until this pass ends, the whole copy counts as written (a particle that leaves the grid
    // throws part-way).
    auto& touched = touched_[static_cast<std::size_t>(t)];
    std::size_t z0 = one_range ? last_lo : 0, z1 = one_range ? last_hi : nn;
    if (T > 1) {
      z0 = touched[0];
      z1 = touched[1];
    }
    touched = {0, nn};
    std::fill(m + z0, m + z1, 0.0);
    std::fill(pp + z0, pp + z1, Vec::Zero());
    std::fill(fi + z0, fi + z1, Vec::Zero());
    if (has_fext_ || T > 1) std::fill(fe + z0, fe + z1, Vec::Zero());
    const auto [b, e] = block(t, T, P.size());
    Stencil<D> st;
    const detail::RowKernels<D>& rk = detail::row_kernels<D>();
    const detail::NodeArrays nodes{m, lanes(pp), lanes(fi), lanes(fe)};
    // the first nodes of the particles' stencils, lowest and highest (linear node index)
    std::int64_t first_lo = std::numeric_limits<std::int64_t>::max(), first_hi = -1;
    for (std::size_t p = b; p < e; ++p) {
      if ((p - b) % kWeightChunk == 0) { // the weights of the next chunk, SIMD (D376)
        const std::size_t n = std::min(kWeightChunk, e - p);
        const std::size_t ok = compute_axis_weights_many(grid, n, P.x.data() + p, P.l.data() + p,
                                                         wval_.data() + p, wder_.data() + p);
        if (ok < n) left_grid(p + ok);
        if (nfields_ == 1)
          for (std::size_t q = p; q < p + n; ++q) {
            const std::int64_t i = grid.index(wval_[q].i0);
            first_lo = std::min(first_lo, i);
            first_hi = std::max(first_hi, i);
          }
      }
      if (nfields_ == 1 || !near_crack(P.x[p])) { // field 0 at every node: by rows (D404)
        if (nfields_ > 1) fmask_[p] = 0;
        const detail::P2GParticle<D> in{P.m[p], P.V[p], P.v[p].data(), P.sigma[p].data(),
                                        P.fext[p].data()};
        rk.scatter(grid, wval_[p], wder_[p], in, has_fext_, nodes);
        continue;
      }
      // Scalar loops: Eigen temporaries of small fixed-size products spilled to the stack and
      // caused store-forwarding stalls in this hot loop.
      double sV[D][D], mv[D];
      for (int a = 0; a < D; ++a) {
        mv[a] = P.m[p] * P.v[p][a];
        for (int c = 0; c < D; ++c)
          sV[a][c] = P.sigma[p](a, c) * P.V[p];
      }
      const double mp = P.m[p];
      assemble_stencil(grid, split_view(wval_[p], wder_[p]), st);
      std::uint32_t mask = 0;
      for (int k = 0; k < Stencil<D>::size; ++k)
        if (st.S[k] > 0.0 && crosses(P.x[p], grid.position(st.node[k]))) mask |= 1u << k;
      fmask_[p] = mask;
      apply_fields(p, st);
      for (int k = 0; k < Stencil<D>::size; ++k) {
        const std::int64_t i = st.node[k];
        const double S = st.S[k];
        const Vec& dS = st.dS[k];
        m[i] += S * mp;
        for (int a = 0; a < D; ++a) {
          double f = 0.0;
          for (int c = 0; c < D; ++c)
            f += sV[a][c] * dS[c];
          pp[i][a] += S * mv[a];
          fi[i][a] -= f;
        }
      }
      if (has_fext_)
        for (int k = 0; k < Stencil<D>::size; ++k)
          fe[st.node[k]] += st.S[k] * P.fext[p];
    }
    if (nfields_ == 1) {          // else (cracks: field copies) all of it
      std::size_t lo = 0, hi = 0; // no particle: nothing written
      if (first_hi >= 0) {
        // a stencil spans nodes first .. first + 2 (1 + n0 [+ n0 n1]) of the linear index
        std::int64_t span = 0;
        for (int a = D - 1; a >= 0; --a)
          span = span * grid.n[a] + 2;
        lo = static_cast<std::size_t>(first_lo);
        hi = std::min(nn, static_cast<std::size_t>(first_hi + span + 1));
      }
      touched = {lo, hi};
    }
  });
  node_pass_range(last_lo, last_hi);
  // The per-thread copies are summed by grid_velocities (D355); the displacement scatter
  // below reads only wval_, the particles and gu_.
  if (nfields_ > 1) { // nodal displacements per field for the contact gap test (serial)
    std::fill(gu_.begin(), gu_.end(), Vec::Zero());
    Stencil<D> st;
    for (std::size_t p = 0; p < P.size(); ++p) {
      if (!near_crack(P.x[p])) continue; // only nodes near the crack are tested for contact
      assemble_stencil_weights(grid, wval_[p], st); // S only (D378)
      apply_fields(p, st);
      const Vec mu = P.m[p] * (P.x[p] - P.x0[p]);
      for (int k = 0; k < Stencil<D>::size; ++k)
        gu_[st.node[k]] += st.S[k] * mu;
    }
  }
}

// Sums the per-thread grid copies of nodes [b, e) in thread order (f^int; with `first` also m,
// p, f^ext). Called inside the node-block passes that use the sums (grid_velocities,
// advance_grid) on the same blocks, so that the reduction costs no extra hand-over (D355).
// Each copy is read only where it may be non-zero, touched_ (D410): from zero, the copies added
// in thread order give the sums of all copies bit for bit but for the sign of a zero.
template <int D> void Solver<D>::reduce_nodes(bool first, std::size_t b, std::size_t e) {
  const int T = threads;
  std::fill(gfi_.begin() + static_cast<std::ptrdiff_t>(b),
            gfi_.begin() + static_cast<std::ptrdiff_t>(e), Vec::Zero());
  if (first) {
    std::fill(gm_.begin() + static_cast<std::ptrdiff_t>(b),
              gm_.begin() + static_cast<std::ptrdiff_t>(e), 0.0);
    std::fill(gp_.begin() + static_cast<std::ptrdiff_t>(b),
              gp_.begin() + static_cast<std::ptrdiff_t>(e), Vec::Zero());
    std::fill(gfe_.begin() + static_cast<std::ptrdiff_t>(b),
              gfe_.begin() + static_cast<std::ptrdiff_t>(e), Vec::Zero());
  }
  for (int s = 0; s < T; ++s) {
    const Buffer& c = buf_[static_cast<std::size_t>(s)];
    const auto& r = touched_[static_cast<std::size_t>(s)];
    const std::size_t i0 = std::max(b, r[0]), i1 = std::min(e, r[1]);
    for (std::size_t i = i0; i < i1; ++i)
      gfi_[i] += c.fi[i];
    if (first)
      for (std::size_t i = i0; i < i1; ++i) {
        gm_[i] += c.m[i];
        gp_[i] += c.p[i];
        gfe_[i] += c.fe[i];
      }
  }
}

template <int D> void Solver<D>::constrain(std::vector<Vec>& vel, double t, bool) const {
  for (const auto& bc : bcs) {
    const double f = bc.ramp(t);
    for (std::int64_t i0 : bc.nodes)
      for (int fld = 0; fld < nfields_; ++fld) {
        const auto i = static_cast<std::size_t>(i0) + static_cast<std::size_t>(fld) * nnodes_;
        for (int a = 0; a < D; ++a)
          if (bc.mask[a]) vel[i][a] = bc.velocity[a] * f;
      }
  }
  for (std::size_t k = 0; k < prescribed_nodes.size(); ++k) // coupling hook (ESCM)
    for (int fld = 0; fld < nfields_; ++fld)
      vel[static_cast<std::size_t>(prescribed_nodes[k]) + static_cast<std::size_t>(fld) * nnodes_] =
          prescribed_velocity[k];
}

// The nodes of this step's node passes (D411): those the particles touched now or in the last
// step (a node that had mass then must be reset). Outside them every node had no mass in
// either step, so the passes would write what it holds: zero, or a boundary condition's
// velocity that constrain() writes every step. Every node with cracks (field copies) or
// with nodes prescribed by a coupling.
template <int D> void Solver<D>::node_pass_range(std::size_t last_lo, std::size_t last_hi) {
  const std::size_t nn = gm_.size();
  std::size_t lo = nn, hi = 0;
  for (const auto& r : touched_)
    if (r[1] > r[0]) {
      lo = std::min(lo, r[0]);
      hi = std::max(hi, r[1]);
    }
  if (hi <= lo) lo = hi = 0;
  const bool all = nfields_ > 1 || !prescribed_nodes.empty();
  pass_lo_ = all ? 0 : std::min(lo, last_lo);
  pass_hi_ = all ? nn : std::max(hi, last_hi);
  if (last_hi <= last_lo) { // nothing touched in the last step
    pass_lo_ = all ? 0 : lo;
    pass_hi_ = all ? nn : hi;
  }
  touch_lo_ = lo;
  touch_hi_ = hi;
}

// Step 1: the P2G sums of the thread copies, nodal velocities v^t (kept in gp_) and v*.
template <int D> void Solver<D>::grid_velocities(double dt) {
  const int T = threads;
  par(pool_.get(), [&](int th) {
    const auto [b0, e0] = block(th, T, pass_hi_ - pass_lo_);
    const std::size_t b = pass_lo_ + b0, e = pass_lo_ + e0;
    if (T > 1) reduce_nodes(true, b, e);
    for (std::size_t i = b; i < e; ++i) {
      active_[i] = gm_[i] > mass_floor_;
      if (active_[i]) {
        gp_[i] /= gm_[i];
        gfi0_[i] = gfi_[i];
        gvs_[i] =
            gp_[i] + (0.5 * dt / gm_[i]) * (gfi_[i] + gfe_[i]) - (0.5 * dt * damping) * gp_[i];
      } else {
        gp_[i].setZero();
        gvs_[i].setZero();
        gfi0_[i].setZero();
      }
    }
  });
}

// Steps 2 and 3: F, stress (weights at x^t), and f^int,* = -sum sigma* grad S V^t in the same
// pass.
template <int D> void Solver<D>::update_stress(double dt) {
  auto& P = particles;
  const std::size_t n = P.size();
  const int T = threads;
  par(pool_.get(), [&](int th) {
    const auto [b, e] = block(th, T, n);
    double se = 0.0; // this thread's strain energy, J
    Vec* fi = T > 1 ? buf_[th].fi.data() : gfi_.data();
    // (this pass writes the nodes of scatter()'s pass, same particles and weights: D410)
    if (T > 1)
      std::fill(fi + touched_[static_cast<std::size_t>(th)][0],
                fi + touched_[static_cast<std::size_t>(th)][1], Vec::Zero());
    else // (gfi_ holds the P2G forces there only; D411)
      std::fill(fi + touch_lo_, fi + touch_hi_, Vec::Zero());
    const detail::RowKernels<D>& rk = detail::row_kernels<D>();
    const auto stride = static_cast<std::size_t>(P.state_stride);
    // the laws' scratch (D416): sized at initialize(), none if the particles changed since
    const std::size_t ls = law_scratch_.size() == n * law_scratch_stride_ ? law_scratch_stride_ : 0;
    // Particles in chunks (D264): F of the chunk, then the laws over each run of particles of
    // one material (Material::update_many, the plugin's batched entry for a damage card), then
    // the forces in particle order as before.
    // Per-thread scratch kept between steps (no allocation per step, D355).
    Scratch& sc = scratch_[static_cast<std::size_t>(th)];
    constexpr std::size_t kChunk = Scratch::kChunk;
    auto& sts = sc.sts;
    auto& F0 = sc.F0;
    auto& F1 = sc.F1;
    for (std::size_t c0 = b; c0 < e; c0 += kChunk) {
      const std::size_t c1 = std::min(e, c0 + kChunk);
      for (std::size_t p = c0; p < c1; ++p) {
        // grad v* = sum v*_i (x) grad S_ip, with scalar accumulators (an Eigen outer-product
        // temporary here caused store-forwarding stalls that cost half of the 3-D step).
        double g[D][D];
        if (nfields_ == 1 || !fmask_[p]) { // weights at x^t from the P2G pass, by rows (D404)
          rk.gradient(grid, wval_[p], wder_[p], lanes(gvs_.data()), g);
        } else {
          Stencil<D>& st = sts[p - c0];
          assemble_stencil(grid, split_view(wval_[p], wder_[p]), st);
          apply_fields(p, st);
          for (int a = 0; a < D; ++a)
            for (int c = 0; c < D; ++c)
              g[a][c] = 0.0;
          for (int k = 0; k < Stencil<D>::size; ++k) {
            const Vec& vi = gvs_[st.node[k]];
            const Vec& dS = st.dS[k];
            for (int a = 0; a < D; ++a)
              for (int c = 0; c < D; ++c)
                g[a][c] += vi[a] * dS[c];
          }
        }
        // F^t+dt = (I + dt grad v*) F^t in scalars: Eigen's product of temporaries wrote them
        // as scalars and read them back as vectors (store-forwarding stalls, D404).
        double A[D][D];
        for (int a = 0; a < D; ++a)
          for (int c = 0; c < D; ++c)
            A[a][c] = (a == c ? 1.0 : 0.0) + dt * g[a][c];
        const Mat& Ft = P.F[p];
        Mat3& f0 = F0[p - c0];
        Mat3& f1 = F1[p - c0];
        f0.setIdentity();
        f1.setIdentity();
        for (int a = 0; a < D; ++a)
          for (int c = 0; c < D; ++c) {
            double q = A[a][0] * Ft(0, c);
            for (int k = 1; k < D; ++k)
              q += A[a][k] * Ft(k, c);
            f1(a, c) = q;
            f0(a, c) = Ft(a, c);
          }
      }
      for (std::size_t r0 = c0; r0 < c1;) {
        std::size_t r1 = r0 + 1;
        while (r1 < c1 && P.mat[r1] == P.mat[r0])
          ++r1;
        const Material& mt = *materials[static_cast<std::size_t>(P.mat[r0])];
        try {
          mt.update_many_cached(r1 - r0, &F0[r0 - c0], &F1[r0 - c0], P.state.data() + r0 * stride,
                                stride, ls ? law_scratch_.data() + r0 * ls : nullptr, ls,
                                &P.sigma[r0], &P.W[r0]);
        } catch (const pnc::InputError&) {
          throw; // a material that refuses its configuration: the user's input
        } catch (const PointFailure& ex) {
          // the law cannot take this deformation (det F <= 0, a plugin's failed point): the
          // simulation failed at this particle, exit code 6
          pnc::fail_simulation("gimp: particle " + std::to_string(r0 + ex.index()), steps, time,
                               "s", ex.what());
        } catch (const std::exception& ex) {
          pnc::fail_simulation("gimp: particle " + std::to_string(r0), steps, time, "s", ex.what());
        }
        r0 = r1;
      }
      for (std::size_t p = c0; p < c1; ++p) {
        if (nfields_ == 1 || !fmask_[p]) { // V^t
          rk.scatter_force(grid, wval_[p], wder_[p], P.sigma[p].data(), P.V[p], lanes(fi));
        } else {
          double sV[D][D]; // V^t
          for (int a = 0; a < D; ++a)
            for (int c = 0; c < D; ++c)
              sV[a][c] = P.sigma[p](a, c) * P.V[p];
          const Stencil<D>& st = sts[p - c0];
          for (int k = 0; k < Stencil<D>::size; ++k) {
            const Vec& dS = st.dS[k];
            Vec& f = fi[st.node[k]];
            for (int a = 0; a < D; ++a) {
              double q = 0.0;
              for (int c = 0; c < D; ++c)
                q += sV[a][c] * dS[c];
              f[a] -= q;
            }
          }
        }
        const Mat Fnew = F1[p - c0].template topLeftCorner<D, D>();
        P.F[p] = Fnew;
        P.V[p] = P.V0[p] * Fnew.determinant();
        se += P.V0[p] * P.W[p]; // while V0 and W are in the cache
      }
    }
    sc.sums[0] = se;
  });
  double se = 0.0; // the threads' sums in thread order
  for (int th = 0; th < T; ++th)
    se += scratch_[static_cast<std::size_t>(th)].sums[0];
  energy.strain = se;
}

// Step 4: the f^int,* sums of the thread copies, v^t+dt at the nodes; returns the work of the
// damping forces (D41).
template <int D> double Solver<D>::advance_grid(double dt) {
  const int T = threads;
  par(pool_.get(), [&](int th) { // the nodes of grid_velocities (D411)
    const auto [b0, e0] = block(th, T, pass_hi_ - pass_lo_);
    const std::size_t b = pass_lo_ + b0, e = pass_lo_ + e0;
    if (T > 1) reduce_nodes(false, b, e);
    for (std::size_t i = b; i < e; ++i)
      gvn_[i] = active_[i] ? Vec(gvs_[i] + (0.5 * dt / gm_[i]) * (gfi_[i] + gfe_[i]) -
                                 (0.5 * dt * damping) * gvs_[i])
                           : Vec::Zero();
  });
  // D41: work of the damping forces -alpha m v on the free components, v^t, v* and v^t+dt
  // weighted as in the two half steps (the trapezoidal rule over the step).
  double wdamp = 0.0;
  if (damping > 0.0) {
    auto dw = [&](std::size_t i) {
      double w = 0.0;
      const unsigned char bm = bcmask_[i % nnodes_];
      for (int a = 0; a < D; ++a)
        if (!(bm & (1u << a)))
          w -= 0.5 * dt * damping * gm_[i] *
               (0.5 * (gp_[i][a] + gvs_[i][a]) * gp_[i][a] +
                0.5 * (gvs_[i][a] + gvn_[i][a]) * gvs_[i][a]);
      return w;
    };
    for (std::size_t i = pass_lo_; i < pass_hi_; ++i) // (no active node outside, D411)
      if (active_[i]) wdamp += dw(i);
    for (std::int64_t i0 : prescribed_nodes) // fully prescribed by a coupling: not damped
      for (int fld = 0; fld < nfields_; ++fld) {
        const std::size_t i =
            static_cast<std::size_t>(i0) + static_cast<std::size_t>(fld) * nnodes_;
        if (active_[i]) wdamp -= dw(i);
      }
  }
  return wdamp;
}

// Reactions of the BCs and of the prescribed nodes (coupling hook, ESCM); returns the work of
// the BC reactions over the step.
template <int D> double Solver<D>::reactions(double dt, double t) {
  double wbc = 0.0;
  for (auto& bc : bcs) {
    bc.reaction.setZero();
    const double f = bc.ramp(t + 0.5 * dt);
    for (std::size_t q = 0; q < bc.nodes.size() * static_cast<std::size_t>(nfields_); ++q) {
      const std::size_t i =
          static_cast<std::size_t>(bc.nodes[q % bc.nodes.size()]) + (q / bc.nodes.size()) * nnodes_;
      if (!active_[i]) continue;
      const Vec fmean = 0.5 * (gfi0_[i] + gfi_[i]) + gfe_[i];
      const Vec R = gm_[i] * (gvn_[i] - gp_[i]) / dt - fmean;
      for (int a = 0; a < D; ++a)
        if (bc.mask[a]) {
          bc.reaction[a] += R[a];
          wbc += dt * R[a] * bc.velocity[a] * f;
        }
    }
  }

  // Reactions of the prescribed nodes (coupling hook, ESCM).
  prescribed_reaction.assign(prescribed_nodes.size(), Vec::Zero());
  for (std::size_t k = 0; k < prescribed_nodes.size(); ++k)
    for (int fld = 0; fld < nfields_; ++fld) {
      const std::size_t i =
          static_cast<std::size_t>(prescribed_nodes[k]) + static_cast<std::size_t>(fld) * nnodes_;
      if (!active_[i]) continue;
      const Vec R = gm_[i] * (gvn_[i] - gp_[i]) / dt - (0.5 * (gfi0_[i] + gfi_[i]) + gfe_[i]);
      prescribed_reaction[k] += R;
      prescribed_work += dt * R.dot(prescribed_velocity[k]);
    }
  return wbc;
}

// Step 5: G2P: positions with v*, velocities with the nodal change (FLIP), energies.
template <int D> void Solver<D>::g2p(double dt) {
  auto& P = particles;
  const std::size_t n = P.size();
  const int T = threads;
  par(pool_.get(), [&](int th) {
    const auto [b, e] = block(th, T, n);
    Stencil<D> st;
    const detail::RowKernels<D>& rk = detail::row_kernels<D>();
    double wext = 0.0, ke = 0.0;
    for (std::size_t p = b; p < e; ++p) {
      double ddx[D], ddv[D];
      if (nfields_ == 1 || !fmask_[p]) { // by rows (D404)
        rk.velocities(grid, wval_[p], lanes(gvs_.data()), lanes(gvn_.data()), lanes(gp_.data()),
                      ddx, ddv);
      } else {
        assemble_stencil_weights(grid, wval_[p], st); // S only (D378)
        apply_fields(p, st);
        for (int a = 0; a < D; ++a)
          ddx[a] = ddv[a] = 0.0;
        for (int k = 0; k < Stencil<D>::size; ++k) {
          const std::int64_t i = st.node[k];
          const double S = st.S[k];
          for (int a = 0; a < D; ++a) {
            ddx[a] += S * gvs_[i][a];
            ddv[a] += S * (gvn_[i][a] - gp_[i][a]);
          }
        }
      }
      // scalars: Eigen vectors written by component and read back whole stalled (D404)
      double wx = 0.0, v2 = 0.0;
      for (int a = 0; a < D; ++a) {
        const double dx = dt * ddx[a];
        if (has_fext_) wx += P.fext[p][a] * dx; // (else f^ext = 0: not read, less traffic)
        P.x[p][a] += dx;
        const double v = P.v[p][a] + ddv[a];
        P.v[p][a] = v;
        v2 += v * v;
      }
      wext += wx;
      ke += 0.5 * P.m[p] * v2;
    }
    scratch_[static_cast<std::size_t>(th)].sums = {wext, ke};
  });
  double wext = 0.0, ke = 0.0; // in thread order (the strain energy: update_stress)
  for (int th = 0; th < T; ++th) {
    wext += scratch_[static_cast<std::size_t>(th)].sums[0];
    ke += scratch_[static_cast<std::size_t>(th)].sums[1];
  }
  energy.external_work += wext;
  energy.kinetic = ke;
}

template void Solver<2>::scatter();
template void Solver<3>::scatter();
template void Solver<2>::reduce_nodes(bool, std::size_t, std::size_t);
template void Solver<3>::reduce_nodes(bool, std::size_t, std::size_t);
template void Solver<2>::node_pass_range(std::size_t, std::size_t);
template void Solver<3>::node_pass_range(std::size_t, std::size_t);
template void Solver<2>::constrain(std::vector<Vec>&, double, bool) const;
template void Solver<3>::constrain(std::vector<Vec>&, double, bool) const;
template void Solver<2>::grid_velocities(double);
template void Solver<3>::grid_velocities(double);
template void Solver<2>::update_stress(double);
template void Solver<3>::update_stress(double);
template double Solver<2>::advance_grid(double);
template double Solver<3>::advance_grid(double);
template double Solver<2>::reactions(double, double);
template double Solver<3>::reactions(double, double);
template void Solver<2>::g2p(double);
template void Solver<3>::g2p(double);

} // namespace pnc::gimp
