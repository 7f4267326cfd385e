#pragma once
// pnc/gimp_coupler/solver.hpp: the explicit uGIMP solver, dimension D = 2 (plane strain,
// unit thickness 1 m) or 3.
//
// Units: SI. Positions, half-lengths m; velocity m/s; mass kg; volume m^3 (2-D: area x 1 m);
// stress Pa; force N; energy J; body acceleration m/s^2; time s.
//
// One step (docs/theory.md §5.2; decisions D30, D33-D35):
//  0. P2G with S_ip, grad S_ip at x_p^t: m_i, p_i, f_i^int,t = -sum sigma_p grad S V_p,
//     f_i^ext,t+dt = sum S_ip f_p^ext(t+dt); velocity BCs imposed on p_i.
//  1. v*_i = (p_i + dt/2 (f^int,t + f^ext)) / m_i; BCs on v*.
//  2. grad du_p = dt sum v*_i (x) grad S_ip; F_p <- (I + grad du_p) F_p (LEFT product);
//     V_p = V_p0 det F_p; sigma_p from the material law.
//  3. f_i^int,* = -sum sigma_p* grad S_ip V_p (weights still at x_p^t).
//  4. p_i^t+dt = m_i v*_i + dt/2 (f^int,* + f^ext); BCs; v_i^t+dt = p_i^t+dt / m_i.
//  5. x_p += dt sum S_ip v*_i;  v_p += sum S_ip (v_i^t+dt - v_i^t)  (FLIP form: the particle
//     velocity follows the nodal momentum change, not the source's printed update; decision D33).
// Particle domains: uGIMP, the half-lengths l_p stay fixed (decision D34).
// Threads: std::thread pool; P2G scatters go to per-thread grid copies reduced in node
// blocks, summing the copies in thread order (no races, deterministic for a thread count).
#include "pnc/gimp_coupler/materials.hpp"
#include "pnc/gimp_coupler/weights.hpp"

#include <Eigen/Dense>

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pnc::gimp {

/// Linear ramp of a load or boundary velocity: factor 0 before t0, 1 after t1, linear in
/// between; t1 <= t0 means a step (factor 1 for t >= t0). Times in s.
struct Ramp {
  double t0 = 0.0, t1 = 0.0;
  double operator()(double t) const {
    if (t1 <= t0) return t >= t0 ? 1.0 : 0.0;
    if (t <= t0) return 0.0;
    if (t >= t1) return 1.0;
    return (t - t0) / (t1 - t0);
  }
};

/// Particles in structure-of-arrays form (one std::vector per field).
template <int D> struct Particles {
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  std::vector<Vec> x;        ///< centroid, m
  std::vector<Vec> x0;       ///< initial centroid, m (displacement = x - x0)
  std::vector<Vec> v;        ///< velocity, m/s
  std::vector<Vec> l;        ///< half-lengths, m (uGIMP: fixed)
  std::vector<Vec> fext;     ///< external force of this step (traction + body), N
  std::vector<double> m;     ///< mass, kg
  std::vector<double> V0;    ///< reference volume, m^3
  std::vector<double> V;     ///< current volume V0 det F, m^3
  std::vector<Mat> F;        ///< deformation gradient (in-plane block in 2-D)
  std::vector<Mat3> sigma;   ///< Cauchy stress, Pa (full 3x3; sigma_33 in plane strain)
  std::vector<double> W;     ///< stored-energy density, J/m^3 of reference volume
  std::vector<int> mat;      ///< material index
  std::vector<double> state; ///< material state, state_stride doubles per particle
  int state_stride = 0;

  std::size_t size() const { return x.size(); }
  /// Appends one particle at rest with F = I (state set by Solver::initialize()).
  void add(const Vec& pos, const Vec& half, double mass, double volume, int material,
           const Vec& vel = Vec::Zero());
};

/// Velocity boundary condition on the grid nodes inside a box [lo, hi] (inclusive, with a
/// tolerance of 1e-9 h): components with mask[a] are prescribed to velocity[a] * ramp(t).
/// A fixed wall: all components, velocity 0. A symmetry plane: the normal component only.
template <int D> struct NodeBC {
  using Vec = Eigen::Matrix<double, D, 1>;
  std::string name;
  Vec lo, hi;
  std::array<bool, D> mask{};
  Vec velocity = Vec::Zero(); ///< m/s
  Ramp ramp{0.0, 0.0};
  std::vector<std::int64_t> nodes; ///< filled by Solver::initialize()
  Vec reaction = Vec::Zero();      ///< force the boundary exerts on the body, N (last step)
};

/// Surface traction on a set of particles: force per particle = traction (Pa) x the area of
/// the particle face normal to `axis` (prod of 2 l_b over the other axes; x 1 m in 2-D),
/// times ramp(t).
template <int D> struct Traction {
  using Vec = Eigen::Matrix<double, D, 1>;
  std::string name;
  std::vector<std::size_t> particles;
  int axis = 0;
  Vec traction = Vec::Zero(); ///< Pa
  Ramp ramp{0.0, 0.0};
};

/// Crack growth controls (D40): the crack tip advances by `increment` when
/// G = J >= Gc (GIIc = 0) or G_I/Gc + G_II/GIIc >= 1 (GIIc > 0), at most once per tip per
/// fracture evaluation, in the maximum-hoop-stress direction of the mode mix or along a
/// prescribed direction. 3-D (D43): the same criterion on the front-averaged values; a front
/// advances in the crack plane, normal to itself (`prescribed` and `direction` are 2-D only).
struct CrackGrowth {
  double Gc = 0.0;         ///< critical energy release rate (mode I or total), J/m^2; 0: no growth
  double GIIc = 0.0;       ///< mode II critical value, J/m^2; 0: criterion on the total G
  double increment = 0.0;  ///< crack advance per growth event, m
  bool prescribed = false; ///< direction given (else maximum hoop stress)
  Eigen::Vector2d direction{1.0, 0.0}; ///< prescribed direction (global frame, unit)
  int max_increments = 1000000;        ///< stop growing after this many increments
};

/// A crack (CRAMP, Nairn 2003). 2-D: a polyline of points (m) through the body; 3-D (D42): a
/// planar convex polygon (`corners`) whose front edges are straight. Fixed in space (given in
/// the undeformed configuration). Its faces are traction-free; where they
/// touch they are in frictionless contact. Energy release rates per tip by the J-integral
/// (domain form on the particles, D38) split into G_I, G_II by the crack-opening displacements
/// (D39); growth by `growth` (D40); functions in fracture.hpp.
struct Crack {
  std::string name;
  std::vector<Eigen::Vector2d> points; ///< >= 2 points, m
  /// Per end (0: points.front(), 1: points.back()): 1 = a crack tip inside the material,
  /// 0 = not a tip (e.g. the mouth of an edge crack), -1 = decide in Solver::initialize()
  /// (a tip if a particle centroid lies within h of end + h * outward tangent).
  std::array<int, 2> tip{-1, -1};
  /// J domain (D38): q = 1 within j_inner of the tip, 0 beyond j_outer, smooth in between, m.
  /// j_outer = 0: the defaults j_inner = 1 h, j_outer = 4 h.
  double j_inner = 0.0;
  double j_outer = 0.0;
  CrackGrowth growth;
  int increments = 0; ///< growth increments so far

  // --- 3-D (D42): a planar convex polygon with straight-edge fronts; `points` and `tip` are
  // not used; `growth` moves front edges in the plane (D43). ---
  /// Corners (m, >= 3, in order around the polygon, one plane, convex); edge k runs from
  /// corners[k] to corners[(k + 1) % n].
  std::vector<Eigen::Vector3d> corners;
  /// Per edge: 1 = a crack front (straight, crossing the whole body), 0 = not a front,
  /// -1 = decide in resolve_fronts() (a front if a particle centroid lies within h of the
  /// edge midpoint + h * the outward in-plane normal).
  std::vector<int> front;
  /// Unit normal (right-hand rule of the corner order; set by check_planar_crack()).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};

/// Checks a 3-D crack polygon (D42) and sets its unit normal: >= 3 corners, consecutive
/// corners distinct, no three consecutive corners collinear (a straight edge is one edge),
/// non-zero area, all corners in one plane (to 1e-9 of the polygon's size), convex and simple.
/// Returns "" or the rule broken (e.g. "non-planar: corner 3 is 0.01 m off the plane ...").
std::string check_planar_crack(Crack& c);

/// Unit in-plane normal of edge k of a checked 3-D crack, pointing out of the polygon.
Eigen::Vector3d edge_outward(const Crack& c, std::size_t k);

/// Resolves 3-D front flags marked -1 (a front if material lies just ahead, as the 2-D tip
/// detection) and checks that every front crosses the whole body: returns "" or the rule
/// broken ("front edge k ends inside the material ..."): the front-averaged J (D42) uses a
/// weight constant along the front, which is only valid for fronts that end outside the
/// material (free faces or symmetry planes normal to the front).
std::string resolve_fronts(Crack& c, const Particles<3>& particles, double h);

/// Energies and works since t = 0, J.
struct Energies {
  double initial = 0.0;       ///< kinetic + strain at t = 0
  double kinetic = 0.0;       ///< sum 1/2 m v^2
  double strain = 0.0;        ///< sum V0 W (stored energy)
  double external_work = 0.0; ///< work of body forces and tractions
  double boundary_work = 0.0; ///< work of the reactions of velocity BCs
  double damping_work = 0.0;  ///< work of the grid damping forces (<= 0, D41)
  /// Energy error kinetic + strain - initial - external_work - boundary_work - damping_work
  /// (0 for an exactly conservative elastic run; negative when energy is dissipated, e.g. by
  /// damage or crack growth).
  double balance() const {
    return kinetic + strain - initial - external_work - boundary_work - damping_work;
  }
};

class ThreadPool; // solver_pool.hpp: persistent worker threads with blocking hand-over

template <int D> class Solver {
public:
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;

  Grid<D> grid;
  Particles<D> particles;
  std::vector<std::shared_ptr<const Material>> materials;
  std::vector<NodeBC<D>> bcs;
  std::vector<Traction<D>> tractions;
  /// Cracks (2-D polylines, 3-D planar polygons, D42): nodes whose support a crack cuts carry a
  /// second velocity field; a particle uses field 1 of a node when the segment particle -> node
  /// crosses a crack (segment or polygon).
  std::vector<Crack> cracks;
  Vec gravity = Vec::Zero(); ///< body acceleration, m/s^2
  Ramp gravity_ramp{0.0, 0.0};
  int threads = 1;
  double cfl = 0.5; ///< safety factor on dt = h / (c_max + |v|_max)
  /// Grid velocity damping alpha, 1/s (D41): nodal accelerations get -alpha v (0: none). For
  /// quasi-static loading; its work is energy.damping_work.
  double damping = 0.0;
  /// Reorder the particles by grid cell (a stable counting sort on the cell of the centroid)
  /// before every `sort_every`-th step; 0: never (the default). Locality of the grid
  /// transfers; same answers to round-off (summation order). Off by default because hosts
  /// that keep particle indices (tractions are remapped; ESCM maps are not) would break: see
  /// particle_order() and decision D354.
  int sort_every = 0;

  double time = 0.0; ///< s
  long steps = 0;
  Energies energy;

  /// Checks the set-up, sizes the state arrays, finds BC nodes and computes the initial
  /// stresses. Call once before step() (and again after changing particles or BCs).
  /// `fresh_state`: initialise material states (false when restoring a checkpoint).
  void initialize(bool fresh_state = true);
  /// CFL time step: cfl * h / (max wave speed + max particle speed), s.
  double stable_dt() const;
  /// One explicit step of length dt (s). Throws std::runtime_error naming the particle if a
  /// particle leaves the grid or its law fails.
  void step(double dt);
  /// Recomputes energy.kinetic and energy.strain from the particles.
  void update_energies();
  /// Total reaction of all BCs (N).
  Vec total_reaction() const;
  /// Reorders the particles now by grid cell of the centroid (stable counting sort, D354):
  /// every particle array, the material states and the traction particle lists follow.
  void sort_particles();
  /// particle_order()[p] = the index particle p had at initialize() (identity until a sort).
  const std::vector<std::size_t>& particle_order() const { return order_; }

  // --- Coupling hooks (ESCM, docs/escm.md) ---
  /// Nodes whose velocity (all components, every velocity field) is prescribed to
  /// prescribed_velocity[k] (m/s) at all three constraint stages of step() (after the NodeBCs).
  /// After step(), prescribed_reaction[k] holds the mean force (N) the constraint exerted on the
  /// body during the step, and prescribed_work accumulates its work (J).
  std::vector<std::int64_t> prescribed_nodes;
  std::vector<Vec> prescribed_velocity;
  std::vector<Vec> prescribed_reaction;
  double prescribed_work = 0.0;
  /// Nodal velocities v* of the last step (m/s; they moved the particles from x^t to x^t+dt),
  /// indexed by node (field 0 first); empty before initialize().
  const std::vector<Vec>& grid_velocity_star() const { return gvs_; }
  /// Recomputes the crack bounding box and the nodes near cracks after the crack polylines
  /// changed (growth); decides tips marked -1. Called by initialize().
  void update_crack_geometry();

private:
  struct Buffer { // one thread's grid copy: zero outside the nodes touched_ names (D410)
    std::vector<double> m;
    std::vector<Vec> p, fi, fe;
  };
  struct Scratch { // per-thread chunk buffers of the stress update (solver_step.cpp)
    static constexpr std::size_t kChunk = 64;
    std::vector<Stencil<D>> sts;
    std::vector<Mat3> F0, F1;
    std::array<double, 2> sums{}; // this thread's energy sums of a pass, J (summed in order)
  };
  // The parts of step() (solver_step.cpp): P2G, the nodal velocities v^t and v* (1), the
  // stress update with the internal forces and the strain energy (2, 3), v^t+dt with the
  // damping work (4), the reactions and their work, G2P with the kinetic energy and the
  // external work (5).
  void external_forces(double t);
  void scatter();
  void grid_velocities(double dt);
  void update_stress(double dt);
  double advance_grid(double dt);
  double reactions(double dt, double t);
  void g2p(double dt);
  void reduce_nodes(bool first, std::size_t b, std::size_t e);
  void node_pass_range(std::size_t last_lo, std::size_t last_hi);
  void constrain(std::vector<Vec>& vel, double t, bool with_mass) const;
  void apply_fields(std::size_t p, Stencil<D>& st) const;
  void contact(std::vector<Vec>& vel) const;
  bool crosses(const Vec& a, const Vec& b) const;
  /// Unit normal of the crack nearest to node position X, pointing from X's side across it.
  Vec crack_normal(const Vec& X) const;
  [[noreturn]] void left_grid(std::size_t p) const;
  /// The particle, weight and grid arrays backed by huge pages when together they exceed
  /// 16 MiB (D430; solver_sort.cpp): their spans (address, bytes), the rule, the advice.
  std::vector<std::pair<const void*, std::size_t>> array_spans() const;
  bool huge_pages_wanted() const;
  void advise_huge_pages() const;

  std::vector<Buffer> buf_; // per-thread grid copies
  // D411: the nodes the particles touched in this step's P2G (all threads) and in the last
  // step's; the node passes run over their union, [pass_lo_, pass_hi_)
  std::size_t touch_lo_ = 0, touch_hi_ = 0, pass_lo_ = 0, pass_hi_ = 0;
  // per thread, the nodes [lo, hi) this step's P2G wrote ([0, nodes) until its pass ends); with
  // 2+ threads its grid copy is zero outside them (D410)
  std::vector<std::array<std::size_t, 2>> touched_;
  std::vector<Scratch> scratch_; // per-thread scratch of update_stress
  std::vector<double> gm_;       // node mass, kg
  std::vector<Vec> gp_;          // node momentum, then v_i^t (m/s)
  std::vector<Vec> gfi_, gfe_;   // internal, external force, N
  std::vector<Vec> gfi0_;        // f^int,t kept for the reaction and velocity update
  std::vector<Vec> gvs_, gvn_;   // v*, v^t+dt
  std::vector<unsigned char> active_;
  std::vector<unsigned char> bcmask_; // per node: bit a = component a prescribed by a BC
  std::size_t nnodes_ = 0;            // grid nodes; arrays hold nfields_ x nnodes_ entries
  int nfields_ = 1;                   // 2 with cracks
  std::vector<std::uint32_t> fmask_;  // per particle: bit k = stencil node k uses field 1
  std::vector<Vec> gu_;               // nodal displacement per field (contact gap test), m
  Vec crack_lo_ = Vec::Zero(), crack_hi_ = Vec::Zero(); // crack bounding box + 2 h
  std::vector<std::size_t> crack_nodes_;                // nodes inside that box
  bool near_crack(const Vec& x) const {
    for (int a = 0; a < D; ++a)
      if (x[a] < crack_lo_[a] || x[a] > crack_hi_[a]) return false;
    return true;
  }
  std::vector<std::size_t> order_; // initial index of each particle (sort_particles)
  // per-particle weights at x^t, reused within a step: values with the first node indices,
  // and the derivatives, in two arrays (G2P reads the first only; D422)
  std::vector<AxisValues<D>> wval_;
  std::vector<AxisSlopes<D>> wder_;
  // per-particle scratch of the laws between steps (Material::n_scratch, D416), zero at
  // initialize(); law_scratch_stride_ doubles per particle (the largest n_scratch; 0: none)
  std::vector<double> law_scratch_;
  std::size_t law_scratch_stride_ = 0;
  std::shared_ptr<ThreadPool> pool_; // threads - 1 workers; null for one thread
  bool has_fext_ = false;            // any body force or traction this step
  bool fext_zeroed_ = false;
  double mass_floor_ = 0.0;
};

extern template class Solver<2>;
extern template class Solver<3>;

/// Embeds the in-plane D x D block into a 3x3 (F_33 = 1 for D = 2).
template <int D> Mat3 to3(const Eigen::Matrix<double, D, D>& F) {
  if constexpr (D == 3) {
    return F;
  } else {
    Mat3 r = Mat3::Identity();
    r.template topLeftCorner<2, 2>() = F;
    return r;
  }
}

} // namespace pnc::gimp
