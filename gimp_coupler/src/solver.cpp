// The explicit uGIMP solver (solver.hpp). SI units.
#include "pnc/gimp_coupler/solver.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace pnc::gimp {

/// A persistent pool of T - 1 worker threads with blocking (not spinning) hand-over, so that
/// it behaves on a machine whose cores are shared with other jobs. run(fn) calls fn(t) for
/// t = 0..T-1 (t = 0 on the calling thread) and rethrows the first exception (lowest t).
class ThreadPool {
public:
  explicit ThreadPool(int T) : T_(T), err_(static_cast<std::size_t>(T)) {
    for (int t = 1; t < T; ++t)
      workers_.emplace_back([this, t] { work(t); });
  }
  ~ThreadPool() {
    {
      std::lock_guard<std::mutex> lk(mu_);
      stop_ = true;
      ++gen_;
    }
    cv_.notify_all();
    for (auto& w : workers_)
      w.join();
  }
  int size() const { return T_; }
  void run(const std::function<void(int)>& fn) {
    {
      std::lock_guard<std::mutex> lk(mu_);
      fn_ = &fn;
      pending_ = T_ - 1;
      ++gen_;
    }
    cv_.notify_all();
    call(fn, 0);
    {
      std::unique_lock<std::mutex> lk(mu_);
      done_.wait(lk, [this] { return pending_ == 0; });
      fn_ = nullptr;
    }
    for (auto& e : err_)
      if (e) {
        auto x = e;
        for (auto& f : err_)
          f = nullptr;
        std::rethrow_exception(x);
      }
  }

private:
  void call(const std::function<void(int)>& fn, int t) {
    try {
      fn(t);
    } catch (...) {
      err_[static_cast<std::size_t>(t)] = std::current_exception();
    }
  }
  void work(int t) {
    unsigned long seen = 0;
    while (true) {
      const std::function<void(int)>* fn;
      {
        std::unique_lock<std::mutex> lk(mu_);
        cv_.wait(lk, [&] { return gen_ != seen; });
        seen = gen_;
        if (stop_) return;
        fn = fn_;
      }
      call(*fn, t);
      {
        std::lock_guard<std::mutex> lk(mu_);
        if (--pending_ == 0) done_.notify_one();
      }
    }
  }
  int T_;
  std::vector<std::exception_ptr> err_;
  std::vector<std::thread> workers_;
  std::mutex mu_;
  std::condition_variable cv_, done_;
  const std::function<void(int)>* fn_ = nullptr;
  int pending_ = 0;
  unsigned long gen_ = 0;
  bool stop_ = false;
};

namespace {

/// Runs fn(t) for t = 0..T-1 on the pool (or fn(0) without one).
template <class Fn> void par(ThreadPool* pool, Fn&& fn) {
  if (!pool) {
    fn(0);
    return;
  }
  const std::function<void(int)> f = std::ref(fn);
  pool->run(f);
}

/// Static block partition of [0, n) among T threads.
inline std::pair<std::size_t, std::size_t> block(int t, int T, std::size_t n) {
  const auto tt = static_cast<std::size_t>(t), TT = static_cast<std::size_t>(T);
  return {n * tt / TT, n * (tt + 1) / TT};
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
  if (!(grid.h > 0.0)) throw std::runtime_error("gimp: grid cell size must be > 0");
  for (int a = 0; a < D; ++a)
    if (grid.n[a] < 3) throw std::runtime_error("gimp: the grid needs >= 3 nodes per axis");
  if (materials.empty()) throw std::runtime_error("gimp: no materials");
  if (threads < 1) threads = 1;
  const std::size_t n = P.size();
  if (n == 0) throw std::runtime_error("gimp: no particles");
  int stride = 0;
  for (const auto& mptr : materials)
    stride = std::max(stride, mptr->n_state());
  double msum = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    if (P.mat[p] < 0 || P.mat[p] >= static_cast<int>(materials.size()))
      throw std::runtime_error("gimp: particle " + std::to_string(p) + " has no material");
    for (int a = 0; a < D; ++a)
      if (!(P.l[p][a] > 0.0) || P.l[p][a] > 0.5 * grid.h * (1 + 1e-12))
        throw std::runtime_error("gimp: particle " + std::to_string(p) +
                                 ": half-length must be in (0, h/2] (uGIMP)");
    if (!(P.m[p] > 0.0) || !(P.V0[p] > 0.0))
      throw std::runtime_error("gimp: particle " + std::to_string(p) +
                               ": mass and volume must be > 0");
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
    throw std::runtime_error("gimp: restored state arrays do not match the materials");
  }
  for (std::size_t p = 0; p < n; ++p) {
    Stencil<D> st;
    if (!compute_stencil(grid, P.x[p], P.l[p], st)) left_grid(p);
  }
  nnodes_ = static_cast<std::size_t>(grid.nodes());
  for (auto& c : cracks) {
    if constexpr (D == 2) {
      if (c.points.size() < 2)
        throw std::runtime_error("gimp: crack '" + c.name + "' needs at least 2 points");
    } else {
      const std::string why = check_planar_crack(c);
      if (!why.empty()) throw std::runtime_error("gimp: crack '" + c.name + "': " + why);
      if (c.growth.Gc > 0.0 && c.growth.prescribed) // D43: fronts advance in the plane
        throw std::runtime_error("gimp: crack '" + c.name +
                                 "': a prescribed growth direction is 2-D only; a 3-D front "
                                 "advances in the crack plane, normal to itself (D43)");
    }
  }
  nfields_ = cracks.empty() ? 1 : 2;
  const std::size_t nn = nnodes_ * static_cast<std::size_t>(nfields_);
  fmask_.assign(cracks.empty() ? 0 : n, 0u);
  gu_.assign(cracks.empty() ? 0 : nn, Vec::Zero());
  update_crack_geometry();
  if (!(damping >= 0.0)) throw std::runtime_error("gimp: damping must be >= 0");
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
  wcache_.resize(n);
  if (threads > 1 && (!pool_ || pool_->size() != threads))
    pool_ = std::make_shared<ThreadPool>(threads);
  if (threads == 1) pool_.reset();
  buf_.resize(threads > 1 ? static_cast<std::size_t>(threads) : 0);
  for (auto& b : buf_) {
    b.m.assign(nn, 0.0);
    b.p.assign(nn, Vec::Zero());
    b.fi.assign(nn, Vec::Zero());
    b.fe.assign(nn, Vec::Zero());
  }
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
      if (!why.empty()) throw std::runtime_error("gimp: crack '" + c.name + "': " + why);
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
  s << "gimp: particle " << p << " at (";
  for (int a = 0; a < D; ++a)
    s << (a ? ", " : "") << particles.x[p][a];
  s << ") m left the background grid (step " << steps << ", t = " << time
    << " s): enlarge the grid";
  throw std::runtime_error(s.str());
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

// P2G of m, p, f^int (sigma^t, V^t), f^ext at x^t. (The f^int,* scatter happens in the stress
// update of step().)
template <int D> void Solver<D>::scatter() {
  auto& P = particles;
  const int T = threads;
  par(pool_.get(), [&](int t) {
    double* m = T > 1 ? buf_[t].m.data() : gm_.data();
    Vec* pp = T > 1 ? buf_[t].p.data() : gp_.data();
    Vec* fi = T > 1 ? buf_[t].fi.data() : gfi_.data();
    Vec* fe = T > 1 ? buf_[t].fe.data() : gfe_.data();
    const std::size_t nn = gm_.size();
    std::fill(m, m + nn, 0.0);
    std::fill(pp, pp + nn, Vec::Zero());
    std::fill(fi, fi + nn, Vec::Zero());
    if (has_fext_ || T > 1) std::fill(fe, fe + nn, Vec::Zero());
    const auto [b, e] = block(t, T, P.size());
    Stencil<D> st;
    for (std::size_t p = b; p < e; ++p) {
      AxisWeights<D>& aw = wcache_[p];
      if (!compute_axis_weights(grid, P.x[p], P.l[p], aw)) left_grid(p);
      assemble_stencil(grid, aw, st);
      if (nfields_ > 1 && !near_crack(P.x[p])) {
        fmask_[p] = 0;
      } else if (nfields_ > 1) {
        std::uint32_t mask = 0;
        for (int k = 0; k < Stencil<D>::size; ++k)
          if (st.S[k] > 0.0 && crosses(P.x[p], grid.position(st.node[k]))) mask |= 1u << k;
        fmask_[p] = mask;
        apply_fields(p, st);
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
  });
  reduce(true);
  if (nfields_ > 1) { // nodal displacements per field for the contact gap test (serial)
    std::fill(gu_.begin(), gu_.end(), Vec::Zero());
    Stencil<D> st;
    for (std::size_t p = 0; p < P.size(); ++p) {
      if (!near_crack(P.x[p])) continue; // only nodes near the crack are tested for contact
      assemble_stencil(grid, wcache_[p], st);
      apply_fields(p, st);
      const Vec mu = P.m[p] * (P.x[p] - P.x0[p]);
      for (int k = 0; k < Stencil<D>::size; ++k)
        gu_[st.node[k]] += st.S[k] * mu;
    }
  }
}

template <int D> void Solver<D>::reduce(bool first) {
  const int T = threads;
  if (T <= 1) return;
  par(pool_.get(), [&](int t) {
    const auto [b, e] = block(t, T, gm_.size());
    for (std::size_t i = b; i < e; ++i) {
      Vec fi = buf_[0].fi[i];
      for (int s = 1; s < T; ++s)
        fi += buf_[s].fi[i];
      gfi_[i] = fi;
      if (first) {
        double m = buf_[0].m[i];
        Vec pp = buf_[0].p[i], fe = buf_[0].fe[i];
        for (int s = 1; s < T; ++s) {
          m += buf_[s].m[i];
          pp += buf_[s].p[i];
          fe += buf_[s].fe[i];
        }
        gm_[i] = m;
        gp_[i] = pp;
        gfe_[i] = fe;
      }
    }
  });
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

template <int D> bool Solver<D>::crosses(const Vec& a, const Vec& b) const {
  if constexpr (D == 2) {
    auto orient = [](const Vec& p, const Vec& q, const Vec& r) {
      return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
    };
    for (const auto& c : cracks)
      for (std::size_t k = 0; k + 1 < c.points.size(); ++k) {
        const Vec& p = c.points[k];
        const Vec& q = c.points[k + 1];
        const double o1 = orient(a, b, p), o2 = orient(a, b, q);
        const double o3 = orient(p, q, a), o4 = orient(p, q, b);
        if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) &&
            ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
          return true;
      }
    return false;
  } else {
    // D42: a and b strictly on opposite sides of the plane, and the piercing point strictly
    // inside the convex polygon (ties count as no crossing, as in 2-D).
    for (const auto& c : cracks) {
      const Vec& n = c.normal;
      const double da = n.dot(a - c.corners[0]), db = n.dot(b - c.corners[0]);
      if (!((da > 0 && db < 0) || (da < 0 && db > 0))) continue;
      const Vec x = a + (da / (da - db)) * (b - a);
      const std::size_t m = c.corners.size();
      bool in = true;
      for (std::size_t k = 0; k < m && in; ++k) {
        const Vec& p = c.corners[k];
        in = (c.corners[(k + 1) % m] - p).cross(x - p).dot(n) > 0.0;
      }
      if (in) return true;
    }
    return false;
  }
}

template <int D> typename Solver<D>::Vec Solver<D>::crack_normal(const Vec& X) const {
  double best = 1e300;
  Vec n = Vec::Zero();
  // Squared distance from X to segment p-q and the closest point.
  auto seg = [&](const Vec& p, const Vec& q, Vec& cp) {
    const Vec d = q - p;
    const double tt = std::clamp((X - p).dot(d) / d.squaredNorm(), 0.0, 1.0);
    cp = p + tt * d;
    return (X - cp).squaredNorm();
  };
  for (const auto& c : cracks) {
    if constexpr (D == 2) {
      for (std::size_t k = 0; k + 1 < c.points.size(); ++k) {
        Vec cp;
        const double dist = seg(c.points[k], c.points[k + 1], cp);
        if (dist < best) {
          best = dist;
          const Vec d = c.points[k + 1] - c.points[k];
          n = Vec(-d[1], d[0]).normalized();
          if ((X - cp).dot(n) > 0) n = -n;
        }
      }
    } else {
      // Distance to the polygon: to its plane if X projects inside, else to the nearest edge.
      const double dn = c.normal.dot(X - c.corners[0]);
      const Vec xp = X - dn * c.normal;
      const std::size_t m = c.corners.size();
      bool in = true;
      double dist = 1e300;
      for (std::size_t k = 0; k < m; ++k) {
        const Vec& p = c.corners[k];
        const Vec& q = c.corners[(k + 1) % m];
        in = in && (q - p).cross(xp - p).dot(c.normal) >= 0.0;
        Vec cp;
        dist = std::min(dist, seg(p, q, cp));
      }
      if (in) dist = dn * dn;
      if (dist < best) {
        best = dist;
        n = dn > 0 ? Vec(-c.normal) : Vec(c.normal);
      }
    }
  }
  return n;
}

// With cracks: node indices of the stencil entries that use field 1 are shifted by nnodes_.
template <int D> void Solver<D>::apply_fields(std::size_t p, Stencil<D>& st) const {
  const std::uint32_t mask = fmask_[p];
  if (!mask) return;
  for (int k = 0; k < Stencil<D>::size; ++k)
    if (mask & (1u << k)) st.node[k] += static_cast<std::int64_t>(nnodes_);
}

// Frictionless contact of crack faces at nodes with two active fields: if the faces touch or
// overlap ((u0 - u1) . n >= 0 within 1e-6 h) and approach ((v0 - v1) . n > 0), both fields
// get the normal velocity of their centre of mass; tangential velocities are left free.
// n: unit normal of the nearest crack segment, pointing from the node's side across it.
template <int D> void Solver<D>::contact(std::vector<Vec>& vel) const {
  for (std::size_t i : crack_nodes_) {
    const std::size_t j = i + nnodes_;
    if (!active_[i] || !active_[j]) continue;
    const Vec n = crack_normal(grid.position(static_cast<std::int64_t>(i)));
    const Vec u0 = gu_[i] / gm_[i], u1 = gu_[j] / gm_[j];
    if ((u0 - u1).dot(n) < -1e-6 * grid.h) continue; // open
    const double rel = (vel[i] - vel[j]).dot(n);
    if (rel <= 0.0) continue; // separating
    const double vn = (gm_[i] * vel[i].dot(n) + gm_[j] * vel[j].dot(n)) / (gm_[i] + gm_[j]);
    vel[i] += (vn - vel[i].dot(n)) * n;
    vel[j] += (vn - vel[j].dot(n)) * n;
  }
}

template <int D> void Solver<D>::step(double dt) {
  auto& P = particles;
  const std::size_t n = P.size();
  const std::size_t nn = gm_.size();
  const int T = threads;
  const double t = time;

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
  par(pool_.get(), [&](int th) {
    const auto [b, e] = block(th, T, nn);
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
  if (nfields_ > 1) contact(gp_); // as NairnMPM: on the P2G velocities too
  constrain(gp_, t, true);
  if (nfields_ > 1) contact(gvs_);
  constrain(gvs_, t + 0.5 * dt, true);

  // 2. F, stress (weights at x^t), and 3. f^int,* = -sum sigma* grad S V^t in the same pass.
  par(pool_.get(), [&](int th) {
    const auto [b, e] = block(th, T, n);
    Vec* fi = T > 1 ? buf_[th].fi.data() : gfi_.data();
    std::fill(fi, fi + nn, Vec::Zero());
    Stencil<D> st;
    const int stride = P.state_stride;
    std::vector<double> s1(static_cast<std::size_t>(std::max(stride, 1)));
    for (std::size_t p = b; p < e; ++p) {
      assemble_stencil(grid, wcache_[p], st); // weights at x^t from the P2G pass
      if (nfields_ > 1) apply_fields(p, st);
      // grad v* = sum v*_i (x) grad S_ip, with scalar accumulators (an Eigen outer-product
      // temporary here caused store-forwarding stalls that cost half of the 3-D step).
      double g[D][D] = {};
      for (int k = 0; k < Stencil<D>::size; ++k) {
        const Vec& vi = gvs_[st.node[k]];
        const Vec& dS = st.dS[k];
        for (int a = 0; a < D; ++a)
          for (int c = 0; c < D; ++c)
            g[a][c] += vi[a] * dS[c];
      }
      Mat grad;
      for (int a = 0; a < D; ++a)
        for (int c = 0; c < D; ++c)
          grad(a, c) = g[a][c];
      const Mat Fnew = (Mat::Identity() + dt * grad) * P.F[p];
      const Material& mt = *materials[static_cast<std::size_t>(P.mat[p])];
      double* s = P.state.data() + p * static_cast<std::size_t>(stride);
      try {
        mt.update(to3<D>(P.F[p]), to3<D>(Fnew), s, s1.data(), P.sigma[p], P.W[p]);
      } catch (const std::exception& ex) {
        throw std::runtime_error("gimp: particle " + std::to_string(p) + " (step " +
                                 std::to_string(steps) + "): " + ex.what());
      }
      std::copy(s1.begin(), s1.begin() + stride, s);
      double sV[D][D]; // V^t
      for (int a = 0; a < D; ++a)
        for (int c = 0; c < D; ++c)
          sV[a][c] = P.sigma[p](a, c) * P.V[p];
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
      P.F[p] = Fnew;
      P.V[p] = P.V0[p] * Fnew.determinant();
    }
  });
  reduce(false);

  // 4. p^t+dt, v^t+dt, reactions.
  par(pool_.get(), [&](int th) {
    const auto [b, e] = block(th, T, nn);
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
    for (std::size_t i = 0; i < nn; ++i)
      if (active_[i]) wdamp += dw(i);
    for (std::int64_t i0 : prescribed_nodes) // fully prescribed by a coupling: not damped
      for (int fld = 0; fld < nfields_; ++fld) {
        const std::size_t i =
            static_cast<std::size_t>(i0) + static_cast<std::size_t>(fld) * nnodes_;
        if (active_[i]) wdamp -= dw(i);
      }
  }
  if (nfields_ > 1) contact(gvn_);
  constrain(gvn_, t + dt, true);
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

  // 5. G2P: positions with v*, velocities with the nodal change (FLIP), energies.
  std::vector<std::array<double, 3>> part(static_cast<std::size_t>(T), {0.0, 0.0, 0.0});
  par(pool_.get(), [&](int th) {
    const auto [b, e] = block(th, T, n);
    Stencil<D> st;
    double wext = 0.0, ke = 0.0, se = 0.0;
    for (std::size_t p = b; p < e; ++p) {
      assemble_stencil(grid, wcache_[p], st);
      if (nfields_ > 1) apply_fields(p, st);
      double ddx[D] = {}, ddv[D] = {};
      for (int k = 0; k < Stencil<D>::size; ++k) {
        const std::int64_t i = st.node[k];
        const double S = st.S[k];
        for (int a = 0; a < D; ++a) {
          ddx[a] += S * gvs_[i][a];
          ddv[a] += S * (gvn_[i][a] - gp_[i][a]);
        }
      }
      Vec dx, dv;
      for (int a = 0; a < D; ++a) {
        dx[a] = dt * ddx[a];
        dv[a] = ddv[a];
      }
      wext += P.fext[p].dot(dx);
      P.x[p] += dx;
      P.v[p] += dv;
      ke += 0.5 * P.m[p] * P.v[p].squaredNorm();
      se += P.V0[p] * P.W[p];
    }
    part[static_cast<std::size_t>(th)] = {wext, ke, se};
  });
  double wext = 0.0, ke = 0.0, se = 0.0;
  for (const auto& q : part) {
    wext += q[0];
    ke += q[1];
    se += q[2];
  }
  energy.external_work += wext;
  energy.boundary_work += wbc;
  energy.damping_work += wdamp;
  energy.kinetic = ke;
  energy.strain = se;
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

std::string check_planar_crack(Crack& c) {
  using V3 = Eigen::Vector3d;
  const std::size_t m = c.corners.size();
  if (m < 3) return "needs >= 3 corners [x, y, z] (a planar polygon)";
  double size = 0.0;
  for (std::size_t k = 0; k < m; ++k)
    for (std::size_t l = k + 1; l < m; ++l)
      size = std::max(size, (c.corners[k] - c.corners[l]).norm());
  for (std::size_t k = 0; k < m; ++k)
    if (!((c.corners[(k + 1) % m] - c.corners[k]).norm() > 1e-12 * size))
      return "degenerate: corners " + std::to_string(k) + " and " + std::to_string((k + 1) % m) +
             " coincide (consecutive corners must differ)";
  // Newell's normal: twice the vector area.
  V3 a = V3::Zero();
  V3 ctr = V3::Zero();
  for (std::size_t k = 0; k < m; ++k) {
    a += c.corners[k].cross(c.corners[(k + 1) % m]);
    ctr += c.corners[k] / static_cast<double>(m);
  }
  if (!(a.norm() > 1e-12 * size * size))
    return "degenerate: the polygon has zero area (or crosses itself)";
  const V3 n = a.normalized();
  for (std::size_t k = 0; k < m; ++k) {
    const double off = std::abs(n.dot(c.corners[k] - ctr));
    if (off > 1e-9 * size) {
      std::ostringstream o;
      o << "non-planar: corner " << k << " is " << off
        << " m off the polygon's mean plane (a crack must be planar, to 1e-9 of its size)";
      return o.str();
    }
  }
  double turn = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const V3 e0 = c.corners[k] - c.corners[(k + m - 1) % m];
    const V3 e1 = c.corners[(k + 1) % m] - c.corners[k];
    const double s = e0.cross(e1).dot(n);
    if (std::abs(s) <= 1e-9 * e0.norm() * e1.norm())
      return "degenerate: corner " + std::to_string(k) +
             " is collinear with its neighbours (a straight edge or front is one edge: give "
             "its two end corners only)";
    if (s < 0)
      return "not convex: the polygon turns the other way at corner " + std::to_string(k) +
             " (give a convex polygon, corners in order)";
    turn += std::atan2(s, e0.dot(e1));
  }
  if (std::abs(turn - 2.0 * 3.14159265358979323846) > 1e-6)
    return "self-intersecting: the corners must go once around a convex polygon";
  c.normal = n;
  if (c.front.size() != m) c.front.assign(m, -1);
  return "";
}

Eigen::Vector3d edge_outward(const Crack& c, std::size_t k) {
  const std::size_t m = c.corners.size();
  const Eigen::Vector3d e = c.corners[(k + 1) % m] - c.corners[k];
  return e.cross(c.normal).normalized(); // counter-clockwise corners about n: e x n points out
}

std::string resolve_fronts(Crack& c, const Particles<3>& P, double h) {
  const std::size_t m = c.corners.size();
  auto material_near = [&](const Eigen::Vector3d& probe) {
    for (std::size_t p = 0; p < P.size(); ++p)
      if ((P.x0[p] - probe).squaredNorm() <= h * h) return true;
    return false;
  };
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector3d a = c.corners[k], b = c.corners[(k + 1) % m];
    if (c.front[k] < 0) c.front[k] = material_near(0.5 * (a + b) + h * edge_outward(c, k)) ? 1 : 0;
    if (c.front[k] != 1) continue;
    const Eigen::Vector3d e = (b - a).normalized();
    for (const Eigen::Vector3d& end : {Eigen::Vector3d(a - h * e), Eigen::Vector3d(b + h * e)})
      if (material_near(end)) {
        std::ostringstream o;
        o << "front edge " << k << " (corners " << k << " to " << (k + 1) % m
          << ") ends inside the material near (" << end[0] << ", " << end[1] << ", " << end[2]
          << ") m: only straight fronts that cross the whole body are supported (extend the "
             "polygon beyond the body's faces; D42)";
        return o.str();
      }
  }
  return "";
}

template struct Particles<2>;
template struct Particles<3>;
template class Solver<2>;
template class Solver<3>;

} // namespace pnc::gimp
