// Inputs fuzz_cases_h5 found (fuzz/regressions/cases_h5/), read through the same reader: each
// must be refused with a clean pnc::InputError. The card reader's bugs are checked with cards
// built here (CardFitTablesAndCountsAreChecked); the corrupt cards fuzz_card found crash
// inside HDF5 itself and are kept apart in fuzz/hdf5-defects/ (docs/hardening-fuzz.md).
#include "common/fuzz_regressions.hpp"

#include "pnc/core/hdf5_io.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/damage/reference.hpp"

#include <limits>

TEST(FuzzRegressions, CasesH5InputsAreRefusedCleanly) {
  pnc::test::expect_regressions_refused(
      "cases_h5", [](const std::string& f) { (void)pnc::damage::read_stress_strain_h5(f); });
}

namespace {
// A card of the dissertation's pure-polymer constants whose /fit holds the given tables and
// counts, written with the low-level HDF5 helper (write_card always writes well-formed tables).
std::string card_with_fit(const std::string& name, const pnc::h5::RowMatrix& r2,
                          const pnc::h5::RowMatrix& regression, double iterations) {
  using namespace pnc::damage;
  const std::string path = ::testing::TempDir() + "/" + name;
  pnc::h5::File f(path, pnc::h5::File::Mode::truncate);
  const NdmParameters p = dissertation_parameters(Model::pp);
  f.write_string("/model/law", "NDM (Nair 2010)");
  f.set_attr("/model", "variant", "pp");
  f.set_attr("/model", "card_version", 2.0);
  const auto& names = constant_names(Model::pp);
  for (std::size_t i = 0; i < names.size(); ++i)
    f.write_scalar("/constants/" + names[i], p.k[i]);
  f.write_string("/verdict/summary", "usable");
  f.set_attr("/verdict", "level", "usable");
  f.write_matrix("/fit/r2", r2);
  f.write_matrix("/fit/regression", regression);
  f.set_attr("/fit", "iterations", iterations);
  return path;
}

std::string card_error(const std::string& path) {
  try {
    (void)pnc::damage::read_card(path);
  } catch (const pnc::InputError& e) {
    return e.what();
  }
  return "<accepted>";
}
} // namespace

TEST(FuzzRegressions, CardFitTablesAndCountsAreChecked) {
  const pnc::h5::RowMatrix good_r2 = pnc::h5::RowMatrix::Constant(2, 10, 1.0);
  const pnc::h5::RowMatrix good_reg = pnc::h5::RowMatrix::Constant(2, 5, 1.0);
  EXPECT_EQ(card_error(card_with_fit("ok.h5", good_r2, good_reg, 12)), "<accepted>");
  // fewer columns than the reader indexes: read out of bounds before
  const std::string narrow_r2 =
      card_error(card_with_fit("r2.h5", pnc::h5::RowMatrix::Constant(2, 3, 1.0), good_reg, 12));
  EXPECT_NE(narrow_r2.find("'/fit/r2'"), std::string::npos) << narrow_r2;
  EXPECT_NE(narrow_r2.find("at least 5 columns"), std::string::npos) << narrow_r2;
  const std::string narrow_reg =
      card_error(card_with_fit("reg.h5", good_r2, pnc::h5::RowMatrix::Constant(1, 2, 1.0), 12));
  EXPECT_NE(narrow_reg.find("'/fit/regression'"), std::string::npos) << narrow_reg;
  // NaN or a count beyond int: converting it was undefined behaviour
  pnc::h5::RowMatrix nan_r2 = good_r2;
  nan_r2(1, 0) = std::numeric_limits<double>::quiet_NaN();
  const std::string nan_id = card_error(card_with_fit("nan.h5", nan_r2, good_reg, 12));
  EXPECT_NE(nan_id.find("/fit/r2 (row 1)"), std::string::npos) << nan_id;
  const std::string huge = card_error(card_with_fit("huge.h5", good_r2, good_reg, 1e300));
  EXPECT_NE(huge.find("/fit@iterations"), std::string::npos) << huge;
  EXPECT_NE(huge.find("range of int"), std::string::npos) << huge;
}
