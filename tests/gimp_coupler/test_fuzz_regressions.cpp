// Inputs fuzz_gimp_input found (fuzz/regressions/gimp_input/), read through load_input as
// `pnc gimp run` does, in 2-D and 3-D: each must be refused with a clean pnc::InputError.
#include "common/fuzz_regressions.hpp"

#include "pnc/gimp_coupler/input.hpp"

TEST(FuzzRegressions, GimpInputsAreRefusedCleanly) {
  pnc::test::expect_regressions_refused("gimp_input", [](const std::string& f) {
    pnc::gimp::Solver<2> s;
    (void)pnc::gimp::load_input<2>(f, s);
  });
  pnc::test::expect_regressions_refused("gimp_input", [](const std::string& f) {
    pnc::gimp::Solver<3> s;
    (void)pnc::gimp::load_input<3>(f, s);
  });
}
