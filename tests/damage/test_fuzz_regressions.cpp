// Inputs the fuzz targets fuzz_csv, fuzz_cases_h5 and fuzz_card found (fuzz/regressions/),
// read through the same readers: each must be refused with a clean pnc::InputError.
#include "common/fuzz_regressions.hpp"

#include "pnc/damage/card.hpp"
#include "pnc/damage/data.hpp"

TEST(FuzzRegressions, CasesH5InputsAreRefusedCleanly) {
  pnc::test::expect_regressions_refused(
      "cases_h5", [](const std::string& f) { (void)pnc::damage::read_stress_strain_h5(f); });
}

TEST(FuzzRegressions, CardInputsAreRefusedCleanly) {
  pnc::test::expect_regressions_refused(
      "card", [](const std::string& f) { (void)pnc::damage::read_card(f); });
}
