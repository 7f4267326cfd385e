// tests/dealii_fracture/test_elastic.cc: the elastic part of the deal.II tutorial
// (examples/dealii_fracture): patch test, uniform strain, one element against the plugin
// alone, mesh convergence of the elastic stiffness. Each prints its measured numbers.
#include "dealii_test.h"

#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/lac/full_matrix.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace pncdemo::test {
namespace {
// Patch test: a distorted mesh, the affine displacement u = G x on the whole boundary and a
// strain far below the damage threshold. The FE solution must be exactly G x at every node and
// the stress exactly [C0] eps at every quadrature point (rotated platelet, so all of [C0]'s
// in-plane entries are exercised), with and without the nonlocal regularisation.
template <int dim> bool test_patch() {
  bool ok = true;
  for (const std::string reg : {"none", "nonlocal"}) {
    Params p = test_params();
    p.dim = dim;
    p.geometry = "bar";
    p.width = p.height = p.thickness = 1;
    p.cell_size = 0.25;
    p.global_refinements = 0;
    p.distortion = 0.25;
    p.regularisation = reg;
    p.length = 0.2;
    p.path = "0, 1";
    p.step = 1;
    auto m = make_material(context().plugin, context().card, "", 30.0);
    FractureProblem<dim> fp(p, *m.material);
    fp.make_grid();
    Tensor<2, dim> G;
    G[0][0] = 1e-3;
    G[1][1] = -5e-4;
    G[0][1] = 4e-4;
    G[1][0] = 2e-4;
    if (dim == 3) {
      G[2][2] = 3e-4;
      G[0][2] = 1e-4;
      G[2][1] = -2e-4;
    }
    fp.dirichlet.clear();
    for (types::boundary_id id = 0; id <= 5; ++id)
      fp.dirichlet.push_back({id, ComponentMask(dim, true),
                              [G](const Point<dim>& x, unsigned c) { return (G * x)[c]; }});
    unsigned its = 0;
    const bool conv = fp.solve_step(1.0, its);
    // Nodal error.
    std::vector<Point<dim>> support(fp.dof_handler.n_dofs());
    MappingQ1<dim> mapping;
    DoFTools::map_dofs_to_support_points(mapping, fp.dof_handler, support);
    double eu = 0;
    std::vector<types::global_dof_index> dofs(fp.fe.n_dofs_per_cell());
    for (const auto& cell : fp.dof_handler.active_cell_iterators()) {
      cell->get_dof_indices(dofs);
      for (unsigned i = 0; i < dofs.size(); ++i) {
        const unsigned c = fp.fe.system_to_component_index(i).first;
        eu = std::max(eu, std::abs(fp.solution[dofs[i]] - (G * support[dofs[i]])[c]));
      }
    }
    // Stress error against [C0] eps.
    Voigt6 e{};
    e[0] = G[0][0];
    e[1] = G[1][1];
    e[5] = G[0][1] + G[1][0];
    if (dim == 3) {
      e[2] = G[2][2];
      e[3] = G[1][2] + G[2][1];
      e[4] = G[0][2] + G[2][0];
    }
    std::vector<double> s0 = m.material->initial_state(), s1(s0.size());
    Voigt6 z{}, sref{};
    m.material->integrate(s0.data(), s1.data(), z.data(), e.data(), sref.data());
    double es = 0, sn = 0;
    for (int v = 0; v < 6; ++v)
      sn = std::max(sn, std::abs(sref[v]) * kPaToMPa);
    for (const auto& h : fp.history)
      for (int v = 0; v < 6; ++v)
        es = std::max(es, std::abs(h.sigma[v] - sref[v] * kPaToMPa));
    const bool pass = conv && eu < 1e-12 && es < 1e-9 * sn;
    std::ostringstream s;
    s << dim << "-D, regularisation " << reg << ", " << fp.triangulation.n_active_cells()
      << " distorted cells, platelet 30 deg: max |u - Gx| = " << eu
      << " mm, max |sigma - C0 eps| / |sigma| = " << es / sn << ", Newton its " << its;
    report("patch", s.str());
    EXPECT_TRUE(pass) << s.str();
    ok = ok && pass;
  }
  return ok;
}

// Uniform-strain test: a bar in uniaxial tension (free lateral contraction, plane strain)
// below the damage threshold. The reaction must be E* eps H with the plane-strain uniaxial
// modulus of the card's [C0]: E* = 1 / (S_11) with S the inverse of the in-plane block
// (11, 22, 12) of [C0] rotated to the platelet angle (0 and 90 degrees). Both ways of making
// the material (card read in the plugin; constants JSON) are checked.
bool test_uniform() {
  bool ok = true;
  for (const double angle : {0.0, 90.0})
    for (const int route : {0, 1}) {
      Params p = test_params();
      p.geometry = "bar";
      p.width = 4;
      p.height = 2;
      p.cell_size = 0.5;
      p.global_refinements = 0;
      p.path = "0, 0.004"; // eps11 = 1e-3
      p.step = 0.002;
      auto m = make_material(context().plugin, route == 0 ? context().card : "",
                             route == 1 ? context().json : "", angle);
      FractureProblem<2> fp(p, *m.material);
      fp.make_grid();
      fp.run();
      // E* from the plugin's [C0] (tangent at zero strain): in-plane block.
      std::vector<double> s0 = m.material->initial_state(), s1(s0.size());
      Voigt6 z{}, sg{};
      Tangent36 K{};
      m.material->integrate(s0.data(), s1.data(), z.data(), z.data(), sg.data(), K.data());
      const int idx[3] = {0, 1, 5};
      FullMatrix<double> Q(3, 3), S(3, 3);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          Q(i, j) = K[6 * idx[i] + idx[j]] * kPaToMPa;
      S.invert(Q);
      const double Estar = 1.0 / S(0, 0), eps = 1e-3;
      // Independent of the plugin's tangent: C11 - C12^2/C22 (0 deg) or C22 - C12^2/C11 (90).
      const double c11 = m.material->constant("C11") * kPaToMPa,
                   c22 = m.material->constant("C22") * kPaToMPa,
                   c12 = m.material->constant("C12") * kPaToMPa;
      const double Ecard = angle == 0.0 ? c11 - c12 * c12 / c22 : c22 - c12 * c12 / c11;
      const double expected = Estar * eps * p.height, got = fp.records.back().force;
      double spread = 0;
      for (const auto& h : fp.history)
        spread = std::max({spread, std::abs(h.sigma[0] - Estar * eps), std::abs(h.sigma[1])});
      const double rel = std::abs(got - expected) / expected;
      const bool pass = fp.finished && rel < 1e-9 && spread < 1e-8 * Estar * eps &&
                        std::abs(Estar - Ecard) < 1e-9 * Ecard;
      std::ostringstream s;
      s << "platelet " << angle << " deg, material from " << (route == 0 ? "card" : "JSON")
        << ": E* = " << Estar << " MPa (card constants: " << Ecard << "), reaction " << got
        << " N/mm vs " << expected << " (rel " << rel << "), max |sigma - uniform| = " << spread
        << " MPa";
      report("uniform", s.str());
      EXPECT_TRUE(pass) << s.str();
      ok = ok && pass;
    }
  return ok;
}

// One-element test: the same uniaxial load history (loading past damage onset, unloading,
// reloading beyond) through deal.II (one plane-strain element, lateral contraction found by
// the global Newton) and through the plugin directly (a point driver that finds eps22 with
// sigma22 = 0 by its own Newton). The stress paths must agree to round-off.
bool test_one_element() {
  bool ok = true;
  for (const double angle : {0.0, 90.0}) {
    Params p = test_params();
    p.geometry = "bar";
    p.width = p.height = 1;
    p.cell_size = 1;
    p.global_refinements = 0;
    p.path = "0, 0.15, 0.05, 0.25";
    p.step = 0.005;
    p.max_iterations = 30;
    auto m = make_material(context().plugin, context().card, "", angle);
    FractureProblem<2> fp(p, *m.material);
    fp.make_grid();
    fp.run();
    // The point driver: the plugin alone, eps11 from the same steps, eps22 such that
    // sigma22 = 0 (eps33 = 0 and gamma12 = 0, as in the element).
    const auto& mat = *m.material;
    std::vector<double> s0 = mat.initial_state(), s1(s0.size());
    Voigt6 eo{}, sig{};
    Tangent36 K{};
    double path_err = 0, max_s = 0, dmax = 0;
    for (std::size_t r = 1; r < fp.records.size(); ++r) {
      Voigt6 e = eo;
      e[0] = fp.records[r].load / p.width;
      for (int it = 0; it < 50; ++it) {
        Voigt6 de;
        for (int v = 0; v < 6; ++v)
          de[v] = e[v] - eo[v];
        mat.integrate(s0.data(), s1.data(), eo.data(), de.data(), sig.data(), K.data());
        if (std::abs(sig[1]) < 1e-14 * std::abs(sig[0]) + 1e-7) break;
        e[1] -= sig[1] / K[6 * 1 + 1];
      }
      s0 = s1;
      eo = e;
      // deal.II: sigma11 = reaction / height (uniform stress in the element).
      path_err = std::max(path_err, std::abs(fp.records[r].force / p.height - sig[0] * kPaToMPa));
      max_s = std::max(max_s, std::abs(sig[0]) * kPaToMPa);
      dmax = std::max(dmax, *std::max_element(s1.begin() + 3, s1.end()));
    }
    // The element's own points at the end of the path.
    double max_err = 0;
    for (const auto& h : fp.history)
      max_err = std::max(max_err, std::abs(h.sigma[0] - sig[0] * kPaToMPa));
    const bool pass =
        fp.finished && path_err < 1e-7 * max_s && max_err < 1e-7 * max_s && dmax > 0.05;
    std::ostringstream s;
    s << "platelet " << angle << " deg, path eps11 0 -> 0.15 -> 0.05 -> 0.25 ("
      << fp.records.size() - 1
      << " steps): max |sigma11(deal.II) - sigma11(plugin)| = " << std::max(path_err, max_err)
      << " MPa of max " << max_s << " MPa, final D_max = " << dmax;
    report("one_element", s.str());
    EXPECT_TRUE(pass) << s.str();
    ok = ok && pass;
  }
  return ok;
}

// Mesh convergence of the elastic response: the stiffness F/u of the single-edge-notch
// specimen below damage onset on four uniformly refined meshes. The differences between
// successive meshes must decrease (asymptotic convergence; the re-entrant notch corners limit
// the rate) and the last one be below 0.5 %.
bool test_elastic_convergence() {
  std::vector<double> k;
  std::vector<std::size_t> n;
  for (unsigned r = 0; r < 4; ++r) {
    Params p = notched_params(r, "none");
    p.path = "0, 0.001";
    p.step = 0.001;
    auto m = make_material(context().plugin, context().card, "", 0.0);
    FractureProblem<2> fp(p, *m.material);
    fp.make_grid();
    fp.run();
    k.push_back(fp.records.back().force / 0.001);
    n.push_back(fp.dof_handler.n_dofs());
  }
  std::ostringstream s;
  s << "single-edge notch, stiffness F/u (N/mm/mm):";
  for (std::size_t i = 0; i < k.size(); ++i)
    s << " " << n[i] << " dofs: " << std::setprecision(8) << k[i] << ";";
  const double d1 = std::abs(k[1] - k[0]), d2 = std::abs(k[2] - k[1]), d3 = std::abs(k[3] - k[2]);
  const double rate = std::log2(d2 / d3);
  s << " successive differences " << d1 << ", " << d2 << ", " << d3 << " (observed order " << rate
    << "), last relative " << d3 / k[3];
  report("elastic_convergence", s.str());
  return d2 < d1 && d3 < d2 && d3 / k[3] < 5e-3;
}

} // namespace

TEST(DealiiFracture, Patch2D) {
  EXPECT_TRUE(test_patch<2>());
}
TEST(DealiiFracture, Patch3D) {
  EXPECT_TRUE(test_patch<3>());
}
TEST(DealiiFracture, Uniform) {
  EXPECT_TRUE(test_uniform());
}
TEST(DealiiFracture, OneElement) {
  EXPECT_TRUE(test_one_element());
}
TEST(DealiiFracture, ElasticConvergence) {
  EXPECT_TRUE(test_elastic_convergence());
}
} // namespace pncdemo::test
