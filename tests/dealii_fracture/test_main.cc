// tests/dealii_fracture/test_main.cc: GoogleTest main of the deal.II tutorial's tests.
//   test_dealii_fracture [gtest options] --card CARD.h5 --constants-json CARD.json
//                        [--solver direct|iterative] [--plugin PLUGIN.so]
// MPI is initialised for Trilinos (the iterative solver's AMG), one process.
#include "dealii_test.h"

#include <deal.II/base/mpi.h>

#include <gtest/gtest.h>

#include <stdexcept>

namespace pncdemo::test {
Context& context() {
  static Context c;
  return c;
}
} // namespace pncdemo::test

int main(int argc, char** argv) {
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, dealii::numbers::invalid_unsigned_int);
  ::testing::InitGoogleTest(&argc, argv);
  auto& c = pncdemo::test::context();
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      std::cerr << "test_dealii_fracture: argument '" << a << "' needs a value\n";
      return 2;
    }
    const std::string v = argv[++i];
    if (a == "--card")
      c.card = v;
    else if (a == "--constants-json")
      c.json = v;
    else if (a == "--solver" && (v == "direct" || v == "iterative"))
      c.solver = v;
    else if (a == "--plugin")
      c.plugin = v;
    else {
      std::cerr << "test_dealii_fracture: unknown argument '" << a << " " << v << "'\n";
      return 2;
    }
  }
  if (c.card.empty() || c.json.empty()) {
    std::cerr << "test_dealii_fracture: --card and --constants-json are required\n";
    return 2;
  }
  std::cout << "linear solver: " << c.solver << std::endl;
  return RUN_ALL_TESTS();
}
