// tests/dealii_fracture/test_files_and_solvers.cc: the shipped parameter files of
// examples/dealii_fracture are read by the program's own ParameterHandler (every entry
// declared, every value in its range, the cross-entry rules hold) and parameters.prm lists
// every option as `dealii_fracture --print-parameters` prints it; the direct and the
// iterative linear solver give the same load path (D252).
#include "dealii_test.h"

#include "common/temp_dir.hpp" // slurp

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/numerics/vector_tools.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

namespace pncdemo::test {

TEST(DealiiFracture, ParameterFiles) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(PNC_DEALII_EXAMPLE_DIR))
    if (e.path().extension() == ".prm") files.push_back(e.path().filename().string());
  std::sort(files.begin(), files.end());
  // The four shipped files; a new one is picked up by the loop below as well.
  for (const char* f :
       {"compact_tension.prm", "parameters.prm", "short.prm", "single_edge_notch.prm"})
    EXPECT_NE(std::find(files.begin(), files.end(), f), files.end()) << f;
  for (const auto& f : files) {
    SCOPED_TRACE(f);
    Params p;
    EXPECT_NO_THROW(p = load_parameters(example_file(f))) << f;
    EXPECT_FALSE(parse_path(p.path).empty()) << f;
  }
  // parameters.prm is the documentation of every option: it must be what the program prints.
  ParameterHandler prm;
  declare_parameters(prm);
  std::ostringstream printed;
  prm.print_parameters(printed, ParameterHandler::PRM);
  // The listing names the plugin by its soname, not by this build's path (the default).
  std::string expected = printed.str();
  const std::string build_path = PNC_MATERIAL_PLUGIN_PATH;
  const auto at = expected.find("set Plugin         = " + build_path);
  ASSERT_NE(at, std::string::npos) << "no 'Plugin' entry with the build's default";
  expected.replace(at, 21 + build_path.size(), "set Plugin         = libpnc_material.so.1");
  EXPECT_EQ(pnc::test::slurp(example_file("parameters.prm")), expected)
      << "examples/dealii_fracture/parameters.prm is stale: regenerate it with "
         "`dealii_fracture --print-parameters > parameters.prm` and name the plugin "
         "by its soname (set Plugin = libpnc_material.so.1)";
  // A value out of its range, and an undeclared entry, are refused with the entry's name.
  ParameterHandler bad;
  declare_parameters(bad);
  try {
    set_parameter(bad, "Solver/Relative tolerance=2");
    ADD_FAILURE() << "a relative tolerance of 2 was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("Relative tolerance"), std::string::npos) << e.what();
  }
  EXPECT_ANY_THROW(set_parameter(bad, "Solver/No such entry=1"));
}

// Direct against iterative (D252) on single_edge_notch.prm (nonlocal with the exact tangent of
// D56, fracture closure, dissipation control through the peak: CG before damage, GMRES on the
// unsymmetric tangents, the bordered solves of D55), down to half of the peak force.
//
// Tolerance. Both runs end every step with the nonlinear residual of the free dofs below
// tau |f_int| (tau = Newton tolerance; the Krylov solve only changes how many Newton
// iterations that takes). By the reciprocal theorem an out-of-balance force r changes the
// generalised force by w . r, with w the displacement per unit load (|w_i| <= 1 between the
// clamped and the pulled edge), so |dF| <= |w| |r| <= sqrt(n) * 2 tau |f_int|; at equilibrium
// f_int sits on the n_top pulled dofs (F / n_top each) and the clamped ones, |f_int| <=
// F sqrt(2 / n_top). Per step: |dF| / F <= 2 tau sqrt(2 n / n_top); the history carries the
// difference on, so over N steps the bound is N times that. The dissipated energy, quadratic
// in the strain, gets twice the relative bound.
TEST(DealiiFracture, SolverAgreement) {
  std::map<std::string, std::vector<StepRecord>> rec;
  std::map<std::string, nlohmann::json> sum;
  std::size_t n = 0, n_top = 0;
  double tau = 0;
  // "iterative": the AMG hierarchy kept over a load step's Newton iterations (the default,
  // D423); "iterative_never": rebuilt at every iteration
  for (const std::string solver : {"direct", "iterative", "iterative_never"}) {
    Params p = shipped("single_edge_notch.prm");
    p.solver = solver == "direct" ? "direct" : "iterative";
    p.amg_reuse = solver == "iterative_never" ? "never" : "step";
    p.stop_fraction = 0.5;
    tau = p.tolerance;
    auto m = make_material(context().plugin, context().card, "", p.platelet_angle);
    FractureProblem<2> fp(p, *m.material);
    fp.make_grid();
    fp.run();
    rec[solver] = fp.records;
    sum[solver] = fp.summary();
    n = fp.dof_handler.n_dofs();
    std::map<types::global_dof_index, double> bv;
    std::vector<bool> mask(2, false);
    mask[fp.load_component] = true;
    VectorTools::interpolate_boundary_values(
        fp.dof_handler, fp.load_id, Functions::ZeroFunction<2>(2), bv, ComponentMask(mask));
    n_top = bv.size();
  }
  const auto& d = rec["direct"];
  ASSERT_TRUE(sum["direct"]["finished"].get<bool>());
  for (const std::string name : {"iterative", "iterative_never"}) {
    const auto& it = rec[name];
    ASSERT_TRUE(sum[name]["finished"].get<bool>()) << name;
    ASSERT_EQ(d.size(), it.size()) << name << ": the two runs took different steps";
    const double per_step = 2 * tau * std::sqrt(2.0 * n / n_top);
    const double tol = per_step * (d.size() - 1);
    const double Fp = std::abs(d[peak_record(d)].force), Dend = d.back().dissipated;
    double dF = 0, du = 0, dD = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
      EXPECT_EQ(d[i].dissipation_control, it[i].dissipation_control) << name << " step " << i;
      dF = std::max(dF, std::abs(d[i].force - it[i].force) / Fp);
      du = std::max(du, std::abs(d[i].load - it[i].load) / std::abs(d[peak_record(d)].load));
      dD = std::max(dD, std::abs(d[i].dissipated - it[i].dissipated) / Dend);
    }
    std::ostringstream s;
    s << d.size() - 1 << " steps, " << n << " dofs (" << n_top << " pulled), Newton tolerance "
      << tau << ": largest differences direct - " << name << ": force " << dF << " of the peak ("
      << Fp << " N/mm), displacement " << du << " of the peak's, dissipation " << dD
      << " of the final (" << Dend << " mJ/mm); bound " << tol << " (" << per_step
      << " per step); linear solver " << sum[name]["timing"]["linear_solver"]
      << ", Newton iterations " << sum["direct"]["timing"]["newton_iterations"] << " / "
      << sum[name]["timing"]["newton_iterations"];
    report("solver_agreement", s.str());
    EXPECT_LT(dF, tol) << s.str();
    EXPECT_LT(du, tol) << s.str();
    EXPECT_LT(dD, 2 * tol) << s.str();
    // The iterative runs used both Krylov methods and no fallback to UMFPACK.
    const auto& ls = sum[name]["timing"]["linear_solver"];
    EXPECT_GT(ls["cg_solves"].get<unsigned>(), 0u);
    EXPECT_LT(ls["cg_solves"].get<unsigned>(), ls["solves"].get<unsigned>());
    EXPECT_EQ(ls["fallbacks"].get<unsigned>(), 0u);
  }
  // D423: one hierarchy per Newton iteration without reuse; with it, one per load step (plus
  // any rebuild) and the rest reused: every iteration either built or reused one.
  const auto& never = sum["iterative_never"]["timing"]["linear_solver"];
  const auto& step = sum["iterative"]["timing"]["linear_solver"];
  const unsigned its_never = sum["iterative_never"]["timing"]["newton_iterations"].get<unsigned>();
  const unsigned its_step = sum["iterative"]["timing"]["newton_iterations"].get<unsigned>();
  EXPECT_EQ(never["amg_reuses"].get<unsigned>(), 0u);
  EXPECT_EQ(never["amg_setups"].get<unsigned>(), its_never);
  EXPECT_GT(step["amg_reuses"].get<unsigned>(), 0u);
  EXPECT_EQ(step["amg_setups"].get<unsigned>() + step["amg_reuses"].get<unsigned>(),
            its_step + step["amg_rebuilds"].get<unsigned>());
  EXPECT_LT(step["amg_setups"].get<unsigned>(), its_step);
}

} // namespace pncdemo::test

namespace pncdemo::test {

namespace {
// The 1-D diffusion matrix of n elements with conductivity k[e] (Dirichlet at both ends
// eliminated): SPD, tridiagonal.
dealii::SparseMatrix<double>& diffusion(const std::vector<double>& k, dealii::SparsityPattern& sp,
                                        dealii::SparseMatrix<double>& K) {
  const unsigned n = static_cast<unsigned>(k.size()) - 1; // interior nodes
  dealii::DynamicSparsityPattern dsp(n, n);
  for (unsigned i = 0; i < n; ++i)
    for (unsigned j = (i ? i - 1 : 0); j <= std::min(n - 1, i + 1); ++j)
      dsp.add(i, j);
  if (sp.n_rows() != n) {
    sp.copy_from(dsp);
    K.reinit(sp);
  }
  K = 0;
  for (unsigned i = 0; i < n; ++i) {
    K.set(i, i, k[i] + k[i + 1]);
    if (i > 0) K.set(i, i - 1, -k[i]);
    if (i + 1 < n) K.set(i, i + 1, -k[i + 1]);
  }
  return K;
}
} // namespace

// D423: a hierarchy reused for a matrix it no longer preconditions well is built again on
// that matrix, and the system solved, before any fallback to UMFPACK. The first matrix has a
// uniform conductivity, the second one that varies smoothly over four decades: with the first
// matrix's AMG the second's preconditioned spectrum fills [10^-2, 10^2] (CG would need of the
// order of sqrt(10^4) ln(2/1e-8) ~ 10^3 iterations), far beyond the 40 allowed, while the
// second's own AMG needs a few (printed).
TEST(DealiiFracture, ReusedAmgThatFailsIsRebuilt) {
  const unsigned ne = 4000;
  std::vector<double> k0(ne, 1.0), k1(ne);
  for (unsigned e = 0; e < ne; ++e)
    k1[e] = std::pow(10.0, 2.0 * std::sin(2.0 * M_PI * (e + 0.5) / ne));
  for (const std::string reuse : {"step", "never"}) {
    Params p;
    p.solver = "iterative";
    p.solver_max_iterations = 40;
    p.amg_reuse = reuse;
    LinearSolver ls(p);
    Timing t;
    dealii::SparsityPattern sp;
    dealii::SparseMatrix<double> K;
    dealii::Vector<double> b(ne - 1), x(ne - 1), r(ne - 1);
    b = 1.0;
    ls.initialize(diffusion(k0, sp, K), true, t);
    ls.solve(b, x, t);
    ls.initialize(diffusion(k1, sp, K), true, t, /*same_step=*/true);
    ls.solve(b, x, t);
    K.residual(r, x, b);
    std::ostringstream s;
    s << "AMG reuse = " << reuse << ": " << t.krylov_iterations << " CG iterations in all, "
      << t.amg_setups << " setups, " << t.amg_rebuilds << " rebuilds";
    report("amg_rebuild", s.str());
    EXPECT_LE(r.l2_norm(), 1e-8 * b.l2_norm()) << reuse;
    EXPECT_EQ(t.fallbacks, 0u) << reuse << ": the rebuilt hierarchy solves it";
    if (reuse == "step") {
      EXPECT_EQ(t.amg_reuses, 1u);
      EXPECT_EQ(t.amg_rebuilds, 1u) << "the reused hierarchy should not reach 1e-8 in 40 its";
      EXPECT_EQ(t.amg_setups, 2u);
    } else {
      EXPECT_EQ(t.amg_reuses, 0u);
      EXPECT_EQ(t.amg_rebuilds, 0u);
      EXPECT_EQ(t.amg_setups, 2u);
    }
  }
}

} // namespace pncdemo::test
