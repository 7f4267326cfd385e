// Data files and material cards: round trips, and bad input named precisely (file, field,
// value, rule) without leaving partial outputs behind.
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/synth.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <unistd.h>

using namespace pnc::damage;
namespace fs = std::filesystem;

namespace {

class TempDir : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pnc_test_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
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

const char* kHeader = "case,e11,e22,e33,g23,g13,g12,s11,s22,s33,s23,s13,s12\n";

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
      // CSV keeps 10 significant digits of MPa; HDF5 is exact.
      const double tol = f == "d.csv" ? 1e-9 : 0.0;
      EXPECT_LE((r.cases[i].stress - d.cases[i].stress).cwiseAbs().maxCoeff(),
                tol * d.cases[i].stress.cwiseAbs().maxCoeff());
      EXPECT_LE((r.cases[i].strain - d.cases[i].strain).cwiseAbs().maxCoeff(), 1e-10);
      EXPECT_EQ(r.cases[i].stress_stderr.rows(), d.cases[i].stress.rows());
    }
  }
  EXPECT_EQ(listing(), (std::vector<std::string>{"d.csv", "d.h5"})); // no temporaries
}

TEST_F(DataFiles, CsvStressIsReadAsMPa) {
  write("one.csv", std::string(kHeader) + "2,0,0.01,0,0,0,0,7.08,11.53,5.63,0,0,0\n");
  const StressStrainData d = read_stress_strain(path("one.csv"));
  EXPECT_DOUBLE_EQ(d.cases[0].stress(0, 1), 11.53e6);
}

TEST_F(DataFiles, MissingColumnIsNamed) {
  write("bad.csv", "case,e11,e22,e33,g23,g13,g12,s11,s33,s23,s13,s12\n1,0,0,0,0,0,0,0,0,0,0,0\n");
  const std::string m = error_of([&] { read_stress_strain(path("bad.csv")); });
  EXPECT_NE(m.find("bad.csv"), std::string::npos) << m;
  EXPECT_NE(m.find("'s22'"), std::string::npos) << m;
  EXPECT_NE(m.find("missing"), std::string::npos) << m;
}

TEST_F(DataFiles, NonNumericCellIsNamedWithLineAndValue) {
  write("bad.csv",
        std::string(kHeader) + "1,0.01,0,0,0,0,0,1,2,3,0,0,0\n1,0.02,0,0,0,0,0,abc,2,3,0,0,0\n");
  const std::string m = error_of([&] { read_stress_strain(path("bad.csv")); });
  EXPECT_NE(m.find("bad.csv"), std::string::npos) << m;
  EXPECT_NE(m.find("s11 (line 3)"), std::string::npos) << m;
  EXPECT_NE(m.find("'abc'"), std::string::npos) << m;
  EXPECT_NE(m.find("finite number"), std::string::npos) << m;
}

TEST_F(DataFiles, UnknownCaseNumberIsNamed) {
  write("bad.csv", std::string(kHeader) + "7,0.01,0,0,0,0,0,1,2,3,0,0,0\n");
  const std::string m = error_of([&] { read_stress_strain(path("bad.csv")); });
  EXPECT_NE(m.find("bad.csv"), std::string::npos) << m;
  EXPECT_NE(m.find("case (line 2)"), std::string::npos) << m;
  EXPECT_NE(m.find("'7'"), std::string::npos) << m;
  EXPECT_NE(m.find("1..6"), std::string::npos) << m;
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
  write("dup.csv", "case,e11,e22,e33,g23,g13,g12,s11,s22,s33,s23,s13,s12,s11\n" +
                       row.substr(0, row.size() - 1) + ",9\n");
  const std::string m = error_of([&] { read_stress_strain(path("dup.csv")); });
  EXPECT_NE(m.find("dup.csv: field 's11'"), std::string::npos) << m;
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
