// tests/dealii_fracture/dealii_test.h: what the tests of the deal.II fracture tutorial share.
// The card (HDF5) and its constants JSON come from the ctest fixture dealii_fracture.card;
// the linear solver (direct | iterative) from the command line (test_main.cc).
#ifndef PNC_TESTS_DEALII_FRACTURE_DEALII_TEST_H
#define PNC_TESTS_DEALII_FRACTURE_DEALII_TEST_H

#include "fracture_problem.h"

#include <iostream>
#include <string>
#include <vector>

namespace pncdemo::test {

struct Context {
  std::string plugin = PNC_MATERIAL_PLUGIN_PATH, card, json, solver = "direct";
};
/// Set once by main() from --card, --constants-json, --solver.
Context& context();

/// The path of a shipped file of examples/dealii_fracture/.
inline std::string example_file(const std::string& name) {
  return std::string(PNC_DEALII_EXAMPLE_DIR) + "/" + name;
}

/// The overrides every test applies: no output files, no log, the solver under test.
inline std::vector<std::string> quiet_overrides() {
  return {"Output/VTU every=0", "Output/Plot=false", "Output/Quiet=true",
          "Solver/Type=" + context().solver};
}

/// The defaults of the program (no file), quiet, local law, tight Newton tolerance.
inline Params test_params() {
  auto o = quiet_overrides();
  o.push_back("Regularisation/Type=none");
  o.push_back("Newton/Tolerance=1e-11");
  return load_parameters("", o);
}

/// A shipped parameter file read by ParameterHandler, made quiet and set to the solver under
/// test; the caller changes what its test changes.
inline Params shipped(const std::string& prm) {
  return load_parameters(example_file(prm), quiet_overrides());
}

/// The single-edge notch of single_edge_notch.prm (geometry, regularisation length) on
/// `refinements` uniform refinements, displacement control, no fracture closure, with the
/// regularisation `reg` ("none" or "nonlocal").
inline Params notched_params(unsigned refinements, const std::string& reg) {
  Params p = shipped("single_edge_notch.prm");
  p.global_refinements = refinements;
  p.regularisation = reg;
  p.fracture = "none";
  p.control = "displacement";
  p.stop_fraction = 0;
  p.max_iterations = 15;
  p.tolerance = 1e-9;
  return p;
}

/// Prints the measured numbers of a test (one line, as the ctest log shows them).
inline void report(const std::string& name, const std::string& text) {
  std::cout << name << ": " << text << std::endl;
}

} // namespace pncdemo::test

#endif // PNC_TESTS_DEALII_FRACTURE_DEALII_TEST_H
