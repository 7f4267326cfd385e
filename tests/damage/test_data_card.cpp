// Data files and material cards: round trips, and bad input named precisely (file, field,
// value, rule) without leaving partial outputs behind.
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/synth.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <unistd.h>

using namespace pnc::damage;
namespace fs = std::filesystem;

namespace {

class TempDir : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = pnc::test::fresh_dir(
        "test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// Files in the directory (to check that nothing partial was left behind).
  std::vector<std::string> listing() const {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(dir_))
      v.push_back(e.path().filename().string());
    std::sort(v.begin(), v.end());
    return v;
  }
  void write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
  }
  fs::path dir_;
};

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const pnc::InputError& e) {
    return e.what();
  }
  return "<no error>";
}

const char* kHeader =
    "case,e11,e22,e33,g23,g13,g12,s11_MPa,s22_MPa,s33_MPa,s23_MPa,s13_MPa,s12_MPa\n";

} // namespace

using DataFiles = TempDir;

TEST_F(DataFiles, CsvAndHdf5RoundTrip) {
  SynthOptions o;
  o.points = 20;
  o.noise_sd = 1e6;
  const StressStrainData d = synthesize(dissertation_parameters(Model::pnc), o);
  write_stress_strain_csv(path("d.csv"), d);
  write_stress_strain_h5(path("d.h5"), d);
  for (const std::string f : {"d.csv", "d.h5"}) {
    const StressStrainData r = read_stress_strain(path(f));
    ASSERT_EQ(r.cases.size(), d.cases.size()) << f;
    for (std::size_t i = 0; i < d.cases.size(); ++i) {
      EXPECT_EQ(r.cases[i].id, d.cases[i].id);
      // both exact: the CSV is in Pa with 17 significant digits (max_digits10, D342), which
      // read back to the same doubles, and HDF5 stores the doubles
      EXPECT_EQ(r.cases[i].stress, d.cases[i].stress) << f;
      EXPECT_EQ(r.cases[i].strain, d.cases[i].strain) << f;
      EXPECT_EQ(r.cases[i].stress_stderr, d.cases[i].stress_stderr) << f;
      EXPECT_TRUE(r.warnings.empty()) << f;
    }
  }
  EXPECT_EQ(listing(), (std::vector<std::string>{"d.csv", "d.h5"})); // no temporaries
}

// ------------------------------------------------------------ the unit in the column name (D342)
namespace {
/// A header whose stress columns are `s11<suffix>` and, if `sd`, `sd11<suffix>`.
std::string header_with(const std::string& suffix, bool sd) {
  std::string h = "case,e11,e22,e33,g23,g13,g12";
  for (const char* n : {"s11", "s22", "s33", "s23", "s13", "s12"})
    h += std::string(",") + n + suffix;
  if (sd)
    for (const char* n : {"sd11", "sd22", "sd33", "sd23", "sd13", "sd12"})
      h += std::string(",") + n + suffix;
  return h + "\n";
}
} // namespace

TEST_F(DataFiles, CsvStressColumnsAreReadInTheUnitTheirNameStates) {
  // 0.25 GPa = 250 MPa = 2.5e8 Pa, and 0.5 of it as the standard error: exact in every unit,
  // so the three spellings and the legacy bare name (MPa) read to the same doubles.
  const std::pair<const char*, double> per_unit[] = {
      {"_Pa", 1e6}, {"_MPa", 1.0}, {"_GPa", 1e-3}, {"", 1.0}};
  for (const auto& [suffix, from_mpa] : per_unit) {
    std::ostringstream row;
    row.precision(17);
    row << "2,0,0.01,0,0,0,0";
    for (int k = 0; k < 6; ++k)
      row << ',' << (k == 1 ? 250 * from_mpa : 0.0);
    for (int k = 0; k < 6; ++k)
      row << ',' << (k == 1 ? 125 * from_mpa : 0.0);
    write("u.csv", header_with(suffix, true) + row.str() + "\n");
    const StressStrainData d = read_stress_strain(path("u.csv"));
    EXPECT_EQ(d.cases.at(0).stress(0, 1), 2.5e8) << suffix;
    EXPECT_EQ(d.cases.at(0).stress_stderr(0, 1), 1.25e8) << suffix;
    // only the bare names warn, once, naming the file and the columns read as MPa
    ASSERT_EQ(d.warnings.size(), std::string(suffix).empty() ? 1u : 0u) << suffix;
    if (!d.warnings.empty()) {
      EXPECT_EQ(d.warnings[0].rfind(path("u.csv") + ": columns s11,s22", 0), 0u) << d.warnings[0];
      EXPECT_NE(d.warnings[0].find("sd12 have no unit suffix and are read as MPa"),
                std::string::npos)
          << d.warnings[0];
    }
  }
}

TEST_F(DataFiles, SynthesizedCurvesReadTheSameFromPaMPaAndLegacyColumns) {
  // Stresses rounded to multiples of 2^-16 MPa (< 2^26 of them: |s| < 1000 MPa): such a
  // number times 1e6 = 2^6 * 15625 needs at most 26 + 14 bits, so the reader's MPa -> Pa
  // product is exact and every spelling gives the same doubles (then the fit of them is
  // the same fit, test Cli.SynthFitGivesTheSameCardFromEverySpellingOfTheStressColumns).
  SynthOptions o;
  o.points = 15;
  o.noise_sd = 1e6;
  StressStrainData d = synthesize(dissertation_parameters(Model::pp), o);
  const double q = std::ldexp(1.0, -16);
  for (auto& c : d.cases) {
    c.stress = ((c.stress / 1e6 / q).array().round() * q * 1e6).matrix();
    c.stress_stderr = ((c.stress_stderr / 1e6 / q).array().round() * q * 1e6).matrix();
  }
  write_stress_strain_csv(path("pa.csv"), d);
  for (const std::string suffix : {"_MPa", ""}) {
    std::ostringstream f;
    f.precision(17);
    f << header_with(suffix, true);
    for (const auto& c : d.cases)
      for (Eigen::Index k = 0; k < c.strain.rows(); ++k) {
        f << c.id;
        for (int i = 0; i < 6; ++i)
          f << ',' << c.strain(k, i);
        for (int i = 0; i < 6; ++i)
          f << ',' << c.stress(k, i) / 1e6;
        for (int i = 0; i < 6; ++i)
          f << ',' << c.stress_stderr(k, i) / 1e6;
        f << '\n';
      }
    write("mpa.csv", f.str());
    const StressStrainData a = read_stress_strain(path("pa.csv"));
    const StressStrainData b = read_stress_strain(path("mpa.csv"));
    ASSERT_EQ(a.cases.size(), b.cases.size());
    for (std::size_t i = 0; i < a.cases.size(); ++i) {
      EXPECT_EQ(a.cases[i].stress, d.cases[i].stress);
      EXPECT_EQ(b.cases[i].stress, a.cases[i].stress) << "'" << suffix << "'";
      EXPECT_EQ(b.cases[i].stress_stderr, a.cases[i].stress_stderr) << "'" << suffix << "'";
      EXPECT_EQ(b.cases[i].strain, a.cases[i].strain);
    }
  }
}

TEST_F(DataFiles, TwoSpellingsOfOneStressColumnOrAnUnknownSuffixAreRefused) {
  const std::string row = "2,0,0.01,0,0,0,0,7.08,11.53,5.63,0,0,0,9\n";
  const std::string base = header_with("_Pa", false);
  const std::string head = base.substr(0, base.size() - 1);
  for (const char* extra : {"s22", "s22_MPa"}) {
    write("two.csv", head + "," + extra + "\n" + row);
    const std::string m = error_of([&] { read_stress_strain(path("two.csv")); });
    EXPECT_NE(m.find("two.csv: field 's22_Pa/" + std::string(extra) + "': value 'both'"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("two columns give s22"), std::string::npos) << m;
    EXPECT_NE(m.find("<name>_Pa, <name>_MPa or <name>_GPa"), std::string::npos) << m;
  }
  write("kpa.csv", head + ",sd13_kPa\n" + row);
  const std::string m = error_of([&] { read_stress_strain(path("kpa.csv")); });
  EXPECT_NE(m.find("kpa.csv: field 'sd13_kPa': value 'kPa': unknown unit suffix"),
            std::string::npos)
      << m;
  EXPECT_NE(m.find("docs/formats.md"), std::string::npos) << m;
}

TEST_F(DataFiles, MissingColumnIsNamed) {
  write("bad.csv", "case,e11,e22,e33,g23,g13,g12,s11_Pa,s33_Pa,s23_Pa,s13_Pa,s12_Pa\n"
                   "1,0,0,0,0,0,0,0,0,0,0,0\n");
  const std::string m = error_of([&] { read_stress_strain(path("bad.csv")); });
  EXPECT_NE(m.find("bad.csv"), std::string::npos) << m;
  EXPECT_NE(m.find("'s22_Pa'"), std::string::npos) << m; // the name a column has now
  EXPECT_NE(m.find("_MPa"), std::string::npos) << m;     // and the rule
  EXPECT_NE(m.find("missing"), std::string::npos) << m;
}

TEST_F(DataFiles, NonNumericCellIsNamedWithLineAndValue) {
  write("bad.csv",
        std::string(kHeader) + "1,0.01,0,0,0,0,0,1,2,3,0,0,0\n1,0.02,0,0,0,0,0,abc,2,3,0,0,0\n");
  const std::string m = error_of([&] { read_stress_strain(path("bad.csv")); });
  EXPECT_NE(m.find("bad.csv"), std::string::npos) << m;
  EXPECT_NE(m.find("s11_MPa (line 3)"), std::string::npos) << m;
  EXPECT_NE(m.find("'abc'"), std::string::npos) << m;
  EXPECT_NE(m.find("finite number"), std::string::npos) << m;
}

TEST_F(DataFiles, UnknownCaseNumberIsNamed) {
  write("bad.csv", std::string(kHeader) + "10,0.01,0,0,0,0,0,1,2,3,0,0,0\n");
  const std::string m = error_of([&] { read_stress_strain(path("bad.csv")); });
  EXPECT_NE(m.find("bad.csv"), std::string::npos) << m;
  EXPECT_NE(m.find("case (line 2)"), std::string::npos) << m;
  EXPECT_NE(m.find("'10'"), std::string::npos) << m;
  EXPECT_NE(m.find("1..9"), std::string::npos) << m;
}

TEST_F(DataFiles, RaggedRowAndUnknownFormat) {
  write("bad.csv", std::string(kHeader) + "1,0.01,0,0\n");
  EXPECT_NE(error_of([&] { read_stress_strain(path("bad.csv")); }).find("line 2"),
            std::string::npos);
  write("x.txt", "hello");
  EXPECT_NE(error_of([&] { read_stress_strain(path("x.txt")); }).find(".csv or .h5"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_stress_strain(path("absent.csv")); }).find("cannot open"),
            std::string::npos);
}

using Cards = TempDir;

TEST_F(Cards, RoundTripIsExactAndCarriesUnits) {
  for (Model m : {Model::pnc, Model::pp}) {
    NdmParameters p = dissertation_parameters(m);
    p.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    write_card(path("c.h5"), card_from_parameters(p, "test"), "test");
    const Card c = read_card(path("c.h5"));
    EXPECT_EQ(c.params.model, m);
    for (std::size_t i = 0; i < p.size(); ++i)
      EXPECT_EQ(c.params.k[i], p.k[i]);
    EXPECT_EQ((c.params.R - p.R).norm(), 0.0);
    pnc::h5::File f(path("c.h5"), pnc::h5::File::Mode::read);
    EXPECT_EQ(f.attr_string("/constants/C11", "units").value(), "Pa");
    EXPECT_EQ(f.attr_string("/constants/alpha", "units").value(), "1");
  }
}

TEST_F(Cards, MissingConstantIsNamed) {
  // A card written by hand without A5.
  {
    pnc::h5::File f(path("broken.h5"), pnc::h5::File::Mode::truncate);
    f.write_string("/model/law", "NDM");
    f.set_attr("/model", "variant", "pnc");
    f.set_attr("/model", "card_version", 1.0);
    const NdmParameters p = dissertation_parameters(Model::pnc);
    for (const auto& n : constant_names(Model::pnc))
      if (n != "A5") f.write_scalar("/constants/" + n, p[n]);
  }
  const std::string m = error_of([&] { read_card(path("broken.h5")); });
  EXPECT_NE(m.find("broken.h5"), std::string::npos) << m;
  EXPECT_NE(m.find("'/constants/A5'"), std::string::npos) << m;
  EXPECT_NE(m.find("missing"), std::string::npos) << m;
}

TEST_F(Cards, NonPositiveDefiniteC0IsRejectedOnReadAndNeverWritten) {
  NdmParameters p = dissertation_parameters(Model::pnc);
  p["C23"] = 1.5e9; // > sqrt(C22 C33) = 0.86 GPa
  const std::string w =
      error_of([&] { write_card(path("npd.h5"), card_from_parameters(p, ""), ""); });
  EXPECT_NE(w.find("positive definite"), std::string::npos) << w;
  EXPECT_TRUE(listing().empty()) << "no partial card may be left behind";
  {
    pnc::h5::File f(path("npd.h5"), pnc::h5::File::Mode::truncate);
    f.write_string("/model/law", "NDM");
    f.set_attr("/model", "variant", "pnc");
    f.set_attr("/model", "card_version", 1.0);
    for (const auto& n : constant_names(Model::pnc))
      f.write_scalar("/constants/" + n, p[n]);
  }
  const std::string m = error_of([&] { read_card(path("npd.h5")); });
  EXPECT_NE(m.find("npd.h5"), std::string::npos) << m;
  EXPECT_NE(m.find("C0"), std::string::npos) << m;
  EXPECT_NE(m.find("positive definite"), std::string::npos) << m;
}

// decision D417: the law's shape error is a fit attribute, dimensionless, absent = not tested
TEST_F(Cards, TheShapeErrorRoundTripsAndANegativeOneIsRefusedOnRead) {
  Card card = card_from_parameters(dissertation_parameters(Model::pp), "test");
  card.fit.present = true;
  write_card(path("untested.h5"), card, "test");
  EXPECT_TRUE(std::isnan(read_card(path("untested.h5")).fit.shape_error));
  card.fit.shape_error = 0.037;
  write_card(path("tested.h5"), card, "test");
  EXPECT_EQ(read_card(path("tested.h5")).fit.shape_error, 0.037);
  card.fit.shape_error = std::numeric_limits<double>::infinity(); // a curve of zero stress
  write_card(path("infinite.h5"), card, "test");
  EXPECT_EQ(read_card(path("infinite.h5")).fit.shape_error, card.fit.shape_error);
  card.fit.shape_error = -0.5;
  write_card(path("negative.h5"), card, "test");
  const std::string m = error_of([&] { read_card(path("negative.h5")); });
  EXPECT_NE(m.find("negative.h5"), std::string::npos) << m;
  EXPECT_NE(m.find("/fit@shape_error"), std::string::npos) << m;
  EXPECT_NE(m.find("-0.5"), std::string::npos) << m;
}

TEST_F(Cards, NotACard) {
  write("text.h5", "not hdf5");
  EXPECT_NE(error_of([&] { read_card(path("text.h5")); }).find("not an HDF5 file"),
            std::string::npos);
}

// ------------------------------------------------------------------ hardening of the readers
// A spreadsheet's UTF-8 byte order mark is not part of the first column's name; a column named
// twice is ambiguous and refused, naming it.
TEST_F(DataFiles, CsvWithByteOrderMarkIsReadAndDuplicatedColumnIsRefused) {
  const std::string row = "2,0,0.01,0,0,0,0,7.08,11.53,5.63,0,0,0\n";
  write("bom.csv", "\xEF\xBB\xBF" + std::string(kHeader) + row);
  const StressStrainData d = read_stress_strain(path("bom.csv"));
  ASSERT_EQ(d.cases.size(), 1u);
  EXPECT_EQ(d.cases[0].id, 2);
  EXPECT_DOUBLE_EQ(d.cases[0].stress(0, 1), 11.53e6);
  write("dup.csv", std::string(kHeader).substr(0, std::string(kHeader).size() - 1) + ",s11_MPa\n" +
                       row.substr(0, row.size() - 1) + ",9\n");
  const std::string m = error_of([&] { read_stress_strain(path("dup.csv")); });
  EXPECT_NE(m.find("dup.csv: field 's11_MPa'"), std::string::npos) << m;
  EXPECT_NE(m.find("duplicated column"), std::string::npos) << m;
}

// cases.h5: the stress scale comes from the `units` attribute, so a dataset without it is
// refused (not read as Pa); a standard error is >= 0. Each message names the dataset.
TEST_F(DataFiles, CasesH5NeedsUnitsAndNonNegativeStandardErrors) {
  SynthOptions o;
  o.points = 5;
  o.noise_sd = 1e6;
  o.cases = {2};
  const StressStrainData d = synthesize(dissertation_parameters(Model::pp), o);
  auto write_h5 = [&](const std::string& name, const char* skip_units, double stderr_value) {
    pnc::h5::File f(path(name), pnc::h5::File::Mode::truncate);
    const auto& c = d.cases[0];
    const std::string g = "/case_2";
    f.write_matrix(g + "/strain", c.strain);
    f.write_matrix(g + "/stress", c.stress);
    pnc::h5::RowMatrix se = c.stress_stderr;
    se(1, 2) = stderr_value;
    f.write_matrix(g + "/stress_stderr", se);
    for (const char* ds : {"strain", "stress", "stress_stderr"})
      if (std::string(ds) != skip_units)
        f.set_attr(g + "/" + ds, "units",
                   std::string(ds) == "strain" ? "1 (engineering shear)" : "Pa");
  };
  write_h5("ok.h5", "", 1e6);
  EXPECT_EQ(read_stress_strain(path("ok.h5")).cases.at(0).stress_stderr(1, 2), 1e6);
  for (const char* ds : {"strain", "stress", "stress_stderr"}) {
    write_h5("nounits.h5", ds, 1e6);
    const std::string m = error_of([&] { read_stress_strain(path("nounits.h5")); });
    EXPECT_NE(m.find("nounits.h5: field '/case_2/" + std::string(ds) + "@units'"),
              std::string::npos)
        << m;
  }
  write_h5("neg.h5", "", -1.0);
  const std::string m = error_of([&] { read_stress_strain(path("neg.h5")); });
  EXPECT_NE(m.find("neg.h5: field '/case_2/stress_stderr': value '-1 (row 2, column 3)'"),
            std::string::npos)
      << m;
  EXPECT_NE(m.find(">= 0"), std::string::npos) << m;
}
