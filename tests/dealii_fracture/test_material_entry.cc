// tests/dealii_fracture/test_material_entry.cc: the plugin entry of the tutorial's Newton
// assembly (examples/dealii_fracture, 'Material/Entry', D311, D312). The batched entry (ABI 1.2)
// gives the point entry's numbers bit for bit (D260-D262), so the whole run must be the same
// to the last bit either way: the force-displacement records, the energies, the summary, the
// solution and every point's history. A failed point is reported the same way by both.
#include "dealii_test.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace pncdemo::test {
namespace {

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Bitwise equality of two arrays of doubles; the first difference goes to `where`.
template <class A>
bool same_bits(const A& a, const A& b, const std::string& what, std::string& where) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same_bits(a[i], b[i])) {
      std::ostringstream s;
      s.precision(17);
      s << what << "[" << i << "]: " << a[i] << " vs " << b[i];
      where = s.str();
      return false;
    }
  return true;
}

struct EntryRun {
  std::vector<StepRecord> records;
  nlohmann::json summary;
  std::vector<double> solution;
  std::vector<PointHistory> history;
  unsigned batched_calls = 0;
};

EntryRun run_with(Params p, const std::string& entry) {
  p.material_entry = entry;
  auto m = make_material(context().plugin, context().card, "", p.platelet_angle);
  EXPECT_TRUE(m.material->has_batch()) << "the plugin has no batched entry: nothing is compared";
  FractureProblem<2> fp(p, *m.material);
  fp.make_grid();
  fp.run();
  EntryRun r;
  r.records = fp.records;
  r.summary = fp.summary();
  r.solution.assign(fp.solution.begin(), fp.solution.end());
  r.history = fp.history;
  r.batched_calls = fp.timing.batched_calls;
  return r;
}

// Both entries on one parameter set: everything but the wall-clock timings bit for bit.
void expect_same_run(const std::string& name, const Params& p, bool composed) {
  SCOPED_TRACE(name);
  const EntryRun a = run_with(p, "point"), b = run_with(p, "batched");
  // The switch took effect, and the run reached the damaging part of the law.
  EXPECT_EQ(a.batched_calls, 0u);
  EXPECT_GT(b.batched_calls, 0u);
  EXPECT_EQ(a.summary["timing"]["material_includes_composition"].get<bool>(), composed);
  EXPECT_GT(a.records.back().max_damage, 0.0) << "no damage: the loading path is too short";
  ASSERT_EQ(a.records.size(), b.records.size());
  std::string where;
  for (std::size_t i = 0; i < a.records.size(); ++i) {
    const StepRecord &x = a.records[i], &y = b.records[i];
    const std::vector<double> vx{x.load,       x.force,      x.work,         x.elastic,
                                 x.max_damage, x.dissipated, x.max_fracture, x.implex_error},
        vy{y.load,       y.force,      y.work,         y.elastic,
           y.max_damage, y.dissipated, y.max_fracture, y.implex_error};
    EXPECT_TRUE(same_bits(vx, vy, "step " + std::to_string(i) + " record", where)) << where;
    EXPECT_EQ(x.iterations, y.iterations) << "step " << i;
    EXPECT_EQ(x.cuts, y.cuts) << "step " << i;
    EXPECT_EQ(x.dofs, y.dofs) << "step " << i;
  }
  nlohmann::json sa = a.summary, sb = b.summary;
  const auto ta = sa["timing"], tb = sb["timing"];
  sa.erase("timing");
  sb.erase("timing");
  EXPECT_EQ(sa, sb); // nlohmann compares the doubles with ==; they come from the records
  EXPECT_EQ(ta["newton_iterations"], tb["newton_iterations"]);
  EXPECT_EQ(ta["assemblies"], tb["assemblies"]);
  ASSERT_EQ(a.solution.size(), b.solution.size());
  EXPECT_TRUE(same_bits(a.solution, b.solution, "solution", where)) << where;
  ASSERT_EQ(a.history.size(), b.history.size());
  for (std::size_t x = 0; x < a.history.size(); ++x) {
    const PointHistory &ha = a.history[x], &hb = b.history[x];
    const std::string at = "point " + std::to_string(x) + " ";
    ASSERT_TRUE(same_bits(ha.state_old, hb.state_old, at + "state_old", where)) << where;
    ASSERT_TRUE(same_bits(ha.state_new, hb.state_new, at + "state_new", where)) << where;
    ASSERT_TRUE(same_bits(ha.sigma, hb.sigma, at + "sigma", where)) << where;
  }
  report("material_entry", name + ": " + std::to_string(a.records.size() - 1) + " steps, " +
                               std::to_string(a.solution.size()) + " dofs, " +
                               std::to_string(b.batched_calls) +
                               " batched calls; point and batched runs identical to the bit");
}

} // namespace

// short.prm as ctest's demo runs it: adaptive, nonlocal, so the stress is composed here from
// the law's pieces (the plugin is asked for no tangent).
TEST(DealiiFracture, MaterialEntryComposed) {
  expect_same_run("short.prm (nonlocal, adaptive)", shipped("short.prm"), true);
}

// The same mesh and path with the plain local law: the plugin's own consistent tangent enters
// the matrix (the batched call with PNC_MATERIAL_TANGENT_CONSISTENT).
TEST(DealiiFracture, MaterialEntryPluginTangent) {
  Params p = shipped("short.prm");
  p.regularisation = "none";
  expect_same_run("short.prm (local law)", p, false);
}

// A point the plugin refuses (a non-finite state) in the middle of the second chunk of 64
// cells: both entries stop the assembly there, print the same line (cell, quadrature point,
// the point entry's message) and leave the same history behind.
TEST(DealiiFracture, MaterialEntryFailedPoint) {
  Params p = shipped("short.prm");
  p.quiet = false;
  p.adaptive = false;
  std::vector<std::string> lines;
  std::vector<std::vector<PointHistory>> hist;
  const std::size_t cell = 70, q = 2;
  for (const std::string entry : {"point", "batched"}) {
    p.material_entry = entry;
    auto m = make_material(context().plugin, context().card, "", p.platelet_angle);
    FractureProblem<2> fp(p, *m.material);
    fp.make_grid();
    const std::size_t nq = fp.quadrature.size();
    ASSERT_GT(fp.history.size(), (cell + 1) * nq);
    fp.history[cell * nq + q].state_old[0] = std::numeric_limits<double>::quiet_NaN();
    std::ostringstream err;
    auto* old = std::cerr.rdbuf(err.rdbuf());
    unsigned its = 0;
    const bool converged = fp.solve_step(0.05, its);
    std::cerr.rdbuf(old);
    EXPECT_FALSE(converged) << entry;
    std::string line;
    for (std::istringstream in(err.str()); std::getline(in, line);)
      if (line.find("plugin:") != std::string::npos) break;
    lines.push_back(line);
    hist.push_back(fp.history);
    EXPECT_EQ(fp.timing.batched_calls > 0, entry == "batched");
  }
  const std::string expect_at =
      "  plugin: cell " + std::to_string(cell) + ", quadrature point " + std::to_string(q) + ": ";
  EXPECT_EQ(lines[0].rfind(expect_at, 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find("state0"), std::string::npos) << lines[0]; // the plugin's message
  EXPECT_EQ(lines[0], lines[1]);
  std::string where;
  for (std::size_t x = 0; x < hist[0].size(); ++x)
    ASSERT_TRUE(same_bits(hist[0][x].state_new, hist[1][x].state_new,
                          "point " + std::to_string(x) + " state_new", where))
        << where;
}

} // namespace pncdemo::test
