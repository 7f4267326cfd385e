// examples/dealii_fracture/fracture_problem.h
//
// The declarations of the deal.II fracture tutorial (dealii_fracture.cc, which defines all of
// them and explains them): the parameters, the material set-up, the per-point history, the
// linear solver and the FractureProblem class. Shared by the tutorial program and the tests
// in tests/dealii_fracture/, which link the same code (library pnc_dealii_fracture).
//
// Units: lengths in mm, stresses in MPa (the plugin works in Pa), forces N (3-D) or N/mm of
// thickness (2-D plane strain), energies mJ or mJ/mm, times s.
#ifndef PNC_EXAMPLES_DEALII_FRACTURE_FRACTURE_PROBLEM_H
#define PNC_EXAMPLES_DEALII_FRACTURE_FRACTURE_PROBLEM_H

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/component_mask.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <nlohmann/json.hpp>
#include <pnc/fe_material/material.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#ifndef PNC_MATERIAL_PLUGIN_PATH
#define PNC_MATERIAL_PLUGIN_PATH "libpnc_material.so.1"
#endif

namespace pncdemo {
using namespace dealii;
using Voigt6 = std::array<double, 6>; // 11 22 33 23 13 12, engineering shear strain
using Tangent36 = std::array<double, 36>;
using Clock = std::chrono::steady_clock;

constexpr double kPaToMPa = 1e-6;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Every option of the program; `declare_parameters` documents each (with its units) and
/// `dealii_fracture --print-parameters` prints them (examples/dealii_fracture/parameters.prm).
struct Params {
  // Material
  std::string plugin = PNC_MATERIAL_PLUGIN_PATH;
  std::string card;                       // HDF5 card, read inside the plugin
  std::string constants_json;             // output of `pnc card show CARD --json` (fallback route)
  double platelet_angle = 0;              // degrees, rotation of the platelet about x3
  std::string material_entry = "batched"; // | point: the assembly's plugin entry (D311)
  // Geometry
  unsigned dim = 2;
  std::string geometry = "single-edge-notch"; // | compact-tension | bar
  double width = 4, height = 8, thickness = 1, notch_length = 2, cell_size = 0.5;
  double pin_width = 0.5;
  // Mesh
  unsigned global_refinements = 1, tip_refinements = 0;
  double tip_radius = 1.0;
  bool adaptive = false;
  unsigned max_adaptive_levels = 2;
  double refine_threshold = 0.8;
  double distortion = 0; // random distortion of interior vertices (patch tests)
  // Loading
  std::string path = "0, 0.4"; // displacement waypoints, mm
  double step = 0.02;          // displacement increment, mm
  unsigned max_cuts = 6;
  std::string control = "displacement"; // | dissipation (D55)
  double dissipation_step = 0.02;       // mJ/mm (2-D) or mJ (3-D)
  double stop_fraction = 0;             // stop when F < this * peak after the peak
  std::string integration = "implicit"; // | impl-ex (D110)
  double implex_tolerance = 0.05;       // target change of stiffness fraction per step (D111)
  // Newton
  unsigned max_iterations = 15;
  double tolerance = 1e-8;
  std::string nonlocal_tangent = "exact"; // | local (D51, D56)
  bool line_search = false;
  // Linear solver of each Newton iteration (D250-D252)
  std::string solver = "direct";  // | iterative
  std::string krylov = "auto";    // | cg | gmres | bicgstab
  double solver_tolerance = 1e-8; // relative residual of the Krylov solve
  unsigned solver_max_iterations = 200;
  unsigned gmres_restart = 100;
  unsigned amg_sweeps = 2;
  double amg_threshold = 1e-4;
  std::string amg_reuse = "step"; // "step": one AMG hierarchy per load step; "never" (D423)
  bool solver_fallback = true;
  // Fracture closure (D54)
  std::string fracture = "none"; // | stability-limit
  double stability_margin = 0.95;
  double softening_stretch = 0.05;
  double residual_stiffness = 1e-6;
  // Regularisation
  std::string regularisation = "nonlocal"; // | none
  double length = 0.25;                    // mm
  double cutoff = 2.0;                     // in units of the length
  // Output
  std::string directory = "dealii_fracture_out";
  unsigned vtu_every = 1; // 0: no VTU
  bool plot = true;
  bool quiet = false;
};

/// Declares every entry (type, default, range, text) in `prm`.
void declare_parameters(ParameterHandler& prm);
/// Reads the entries into Params and checks the rules that span several entries.
Params read_parameters(ParameterHandler& prm);
/// The waypoints of 'Loading/Path' (mm).
std::vector<double> parse_path(const std::string& s);
/// Applies one command-line override "Section/Entry=value" (sections may be nested).
void set_parameter(ParameterHandler& prm, const std::string& assignment);
/// Declares the entries, reads `file` (a .prm, ParameterHandler syntax) if not empty, applies
/// the overrides "Section/Entry=value" in order and returns the parameters.
Params load_parameters(const std::string& file, const std::vector<std::string>& overrides = {});

/// The plugin and the material made from a card (HDF5, read inside the plugin) or from the
/// constants JSON of `pnc card show --json`, with the platelet rotated by `angle_deg` about x3.
struct MaterialSetup {
  std::unique_ptr<pnc::fe_material::Plugin> plugin;
  std::unique_ptr<pnc::fe_material::Material> material;
  std::string source;
};
MaterialSetup make_material(const std::string& plugin_path, const std::string& card,
                            const std::string& constants_json, double angle_deg);

// @sect3{Quadrature-point history}
//
// "old" is the last converged step, "new" the current Newton iterate. Only kappa (the largest
// mode stretch so far) carries history; the plugin recomputes D from it. eps_bar is the strain
// that drives damage (equal to eps without regularisation).
struct PointHistory {
  std::array<double, 6> state_old{}, state_new{};
  Voigt6 eps_bar_old{}, eps_bar{}, sigma{}, eps{}, eps_old{}; // sigma in MPa
  // IMPL-EX (D110): the converged history of the step before the last one, and the
  // extrapolated history of the current step with its secant stiffness (MPa).
  std::array<double, 6> state_older{}, state_ex{}, state_ex_old{};
  Tangent36 S_ex{};
};

// @sect3{Boundary conditions}
//
// A Dirichlet condition is: on boundary id `id`, the components in `mask` follow
// u_c(x) = load * coef_c(x), where `load` is the controlled displacement.
template <int dim> struct Dirichlet {
  types::boundary_id id;
  ComponentMask mask;
  std::function<double(const Point<dim>&, unsigned)> coef;
};

struct StepRecord {
  double load = 0, force = 0, work = 0, elastic = 0, max_damage = 0;
  unsigned iterations = 0, cuts = 0;
  std::size_t dofs = 0;
  double dissipated = 0;   // sum over points of the dissipation of each step (D52, D57)
  double max_fracture = 0; // largest fracture variable omega (D54)
  double implex_error = 0; // IMPL-EX error indicator of the step (D111)
  bool dissipation_control = false;
};

/// Index of the record with the largest |force| (the peak of the force-displacement curve).
inline std::size_t peak_record(const std::vector<StepRecord>& records) {
  std::size_t peak = 0;
  for (std::size_t i = 0; i < records.size(); ++i)
    if (std::abs(records[i].force) > std::abs(records[peak].force)) peak = i;
  return peak;
}

struct Timing {
  double assembly = 0, plugin = 0, solve = 0, nonlocal = 0;
  unsigned newton_iterations = 0, assemblies = 0;
  // The linear solver (D250): time spent factorising or building the AMG hierarchy (part of
  // `solve`), systems solved, Krylov iterations, CG/GMRES choices, fallbacks to UMFPACK.
  double solver_setup = 0;
  unsigned linear_solves = 0, krylov_iterations = 0, cg_solves = 0, fallbacks = 0;
  // AMG hierarchies built, Newton iterations that reused the step's hierarchy, and rebuilds
  // after a Krylov solve with a reused one did not converge (D423).
  unsigned amg_setups = 0, amg_reuses = 0, amg_rebuilds = 0;
  // Calls of the plugin's batched entry in the assembly ('Material/Entry = batched', D311).
  unsigned batched_calls = 0;
};

/// The linear solver of every Newton iteration (D250-D252): UMFPACK, or a Krylov method (CG
/// for a symmetric tangent, GMRES otherwise) with Trilinos ML algebraic multigrid.
class LinearSolver {
public:
  explicit LinearSolver(const Params& p) : prm_(p) {}
  /// Near null space of the operator for the AMG: the rigid-body modes at the support points
  /// `x` (coordinates in mm) of the dofs with components `comp`.
  void set_rigid_body_modes(unsigned dim, const std::vector<std::array<double, 3>>& x,
                            const std::vector<unsigned>& comp);
  /// Prepares the solves with `matrix` (factorisation or AMG hierarchy); `symmetric` selects
  /// CG under 'Krylov method = auto'. `same_step`: a later Newton iteration of the load step
  /// whose first iteration called initialize (same sparsity); with 'AMG reuse = step' the
  /// hierarchy built then preconditions this matrix too (D423), unless it was built on a
  /// non-symmetric matrix and CG needs a symmetric preconditioner now.
  void initialize(const SparseMatrix<double>& matrix, bool symmetric, Timing& t,
                  bool same_step = false);
  /// x = K^-1 b. Throws if the system could not be solved.
  void solve(const Vector<double>& b, Vector<double>& x, Timing& t);

private:
  void build_amg(const SparseMatrix<double>& matrix, Timing& t);
  /// One Krylov solve with the current hierarchy; false if it did not converge.
  bool krylov(const Vector<double>& b, Vector<double>& x, Timing& t);
  const Params& prm_;
  const SparseMatrix<double>* matrix_ = nullptr;
  bool symmetric_ = false, direct_ready_ = false;
  bool amg_symmetric_ = false, amg_reused_ = false;
  std::size_t amg_n_ = 0; // rows of the matrix the hierarchy was built on; 0: none built yet
  SparseDirectUMFPACK direct_;
  TrilinosWrappers::SparseMatrix trilinos_matrix_;
  TrilinosWrappers::PreconditionAMG amg_;
  unsigned dim_ = 2, n_modes_ = 0;
  std::vector<double> modes_; // column-major, n_dofs x n_modes (ML's layout)
};

template <int dim> class FractureProblem {
public:
  FractureProblem(const Params& p, const pnc::fe_material::Material& mat);

  void make_grid();
  /// Runs the whole load path; returns false if it had to stop (max cuts).
  bool run();
  nlohmann::json summary() const;

  // Public: the tests (tests/dealii_fracture/) look at the solution and the history.
  const Params prm;
  const pnc::fe_material::Material& material;
  Triangulation<dim> triangulation;
  DoFHandler<dim> dof_handler;
  FESystem<dim> fe;
  QGauss<dim> quadrature;
  Vector<double> solution;
  std::vector<PointHistory> history;
  std::vector<Dirichlet<dim>> dirichlet;
  types::boundary_id load_id = 2;
  unsigned load_component = 1;
  std::vector<StepRecord> records;
  Timing timing;
  bool finished = false;
  std::string stop_reason;
  Point<dim> tip;

  /// Solves one step to `load`; false if Newton failed (solution and history untouched).
  bool solve_step(double load, unsigned& iterations);
  /// One dissipation-controlled step (D55): dissipation `dtau` with the load an unknown;
  /// on success current load is in `load`.
  bool solve_step_dissipation(double dtau, double& load, unsigned& iterations);

  // The law split into its linear pieces (D54/D56), all in MPa, global frame:
  // S(D) = C0 + sum_m D_m M_m (exact: C1 is linear in D, D2).
  Tangent36 C0{};
  std::array<Tangent36, 3> M{};
  std::array<double, 3> D_cap{{2, 2, 2}}, kappa_cap{{1e300, 1e300, 1e300}}, D_star{{2, 2, 2}};
  /// Secant stiffness (MPa) including the fracture factor, and omega, of a state.
  Tangent36 secant_of(const double* state, double* omega = nullptr) const;
  double generalised_force() const;

  // IMPL-EX (D110, D111). `implex_ratio` is the ratio of the coming load increment to the last
  // converged one (0: no extrapolation, e.g. the first step or a re-equilibration);
  // extrapolate() sets state_ex and S_ex of every point, implex_error() measures, after a
  // converged step, how far the implicit history moved from the extrapolated one.
  bool impl_ex = false;
  double implex_ratio = 0, implex_max_error = 0;
  mutable double implex_negative = 0; // sum of the negative point-wise dissipations (D112)
  unsigned implex_rejected = 0;
  void extrapolate();
  double implex_error() const;

private:
  void setup_system();
  void make_constraints(double load, bool first, AffineConstraints<double>& c) const;
  bool assemble(const AffineConstraints<double>& c, bool matrix);
  void compute_strains();
  void build_nonlocal();
  void commit();
  void refine();
  double reaction() const;
  double elastic_energy() const;
  double max_damage() const;
  void output(unsigned step) const;
  void write_csv() const;

  void setup_law();
  void make_sparsity(const AffineConstraints<double>& c);
  bool update_candidates();
  void make_load_pattern();
  double commit_dissipation() const;
  void debug_iteration(unsigned it, double g, double lam);

  AffineConstraints<double> hanging;
  SparsityPattern sparsity;
  SparseMatrix<double> matrix;
  Vector<double> rhs, f_int, f_int_old;
  double current_load = 0;
  double onset = 1; // alpha * lambda_c, the plugin's damage_onset_stretch
  int n_state = 6;
  // Damage modes of the law and where each mode's kappa and D sit in the state (plugin
  // queries n_damage_modes and state_index("kappaK"), state_index("DK")).
  int n_modes = 3;
  std::array<int, 3> kappa_at{{0, 1, 2}}, damage_at{{3, 4, 5}};
  Tangent36 C0_secant{};
  /// D of mode m at the largest stretch kappa (one zero-strain plugin call, no tangent).
  double damage_at_kappa(int m, double kappa) const;
  bool composed = false; // the stress is composed here from the law's pieces (D54, D56)
  bool exact_nonlocal = false;
  unsigned switches_back = 0; // dissipation -> displacement control fall-backs
  bool need_border = false;   // assemble k_u and k_f (dissipation control)
  bool predictor = false;     // first iteration: points on the damage surface count as loading
  // Per quadrature point: JxW, and (nonlocal exact tangent) the B matrices and the
  // nonlocal tangent H = d sigma / d eps_bar of the loading points.
  std::vector<double> jxw;
  std::vector<double> Bstore; // n_points x n_dofs_per_cell x 6
  std::vector<Tangent36> Hq;
  std::vector<char> has_H, candidate;
  std::vector<std::vector<types::global_dof_index>> cell_dofs;
  std::size_t n_candidates = 0;
  // Load pattern u_hat (Dirichlet values per unit load), the unconstrained K u_hat and
  // u_hat^T K (for the bordered dissipation-control system, D55).
  Vector<double> u_hat, k_u, k_f;
  // Nonlocal weights, CSR over quadrature points (index = cell * n_q + q).
  std::vector<std::size_t> nl_offsets;
  std::vector<unsigned> nl_index;
  std::vector<double> nl_weight;
  mutable std::vector<std::pair<double, std::string>> pvd;
  // The linear solver (D250) and whether the last assembled tangent is symmetric (D251).
  LinearSolver linear{prm};
  bool tangent_symmetric = true;
  void set_rigid_body_modes();
};

extern template class FractureProblem<2>;
extern template class FractureProblem<3>;
} // namespace pncdemo

#endif // PNC_EXAMPLES_DEALII_FRACTURE_FRACTURE_PROBLEM_H
