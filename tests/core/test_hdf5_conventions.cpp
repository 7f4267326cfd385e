// The conventions every pnc HDF5 file follows (pnc/core/hdf5_io.hpp, docs/formats.md
// "Conventions"): counts are stored as integers, quantities as doubles, and every file carries
// the provenance block. Types are checked with the HDF5 C API, independently of pnc's reader.
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/version.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace {

/// HDF5's own class and size of a dataset's stored type ("integer 8", "float 8", ...).
std::string stored_type(const std::string& file, const std::string& dataset) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, dataset.c_str(), H5P_DEFAULT);
  const hid_t t = H5Dget_type(d);
  const H5T_class_t c = H5Tget_class(t);
  const std::string out = std::string(c == H5T_INTEGER ? "integer"
                                      : c == H5T_FLOAT ? "float"
                                                       : "other") +
                          " " + std::to_string(H5Tget_size(t)) +
                          (c == H5T_INTEGER && H5Tget_sign(t) == H5T_SGN_2 ? " signed" : "");
  H5Tclose(t);
  H5Dclose(d);
  H5Fclose(f);
  return out;
}

std::string attr_type(const std::string& file, const std::string& object, const char* name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t a = H5Aopen_by_name(f, object.c_str(), name, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t t = H5Aget_type(a);
  const H5T_class_t c = H5Tget_class(t);
  const std::string out = c == H5T_INTEGER ? "integer" : c == H5T_FLOAT ? "float" : "other";
  H5Tclose(t);
  H5Aclose(a);
  H5Fclose(f);
  return out;
}

} // namespace

TEST(Hdf5Conventions, IntegralValuesAreStoredAsSixtyFourBitIntegers) {
  const auto d = pnc::test::fresh_dir("h5conv_int");
  const std::string path = (d / "x.h5").string();
  const std::int64_t big = (std::int64_t{1} << 53) + 1; // not exact as a double
  {
    pnc::h5::File f(path, pnc::h5::File::Mode::truncate);
    f.write_scalar("/steps", 20);                // int
    f.write_scalar("/atoms", std::size_t{4000}); // size_t
    f.write_scalar("/big", big);                 // int64
    f.write_scalar("/strain_max", 0.1);          // a quantity
    f.write_integers("/type", {1, 2, 2, 3});     // ids
    f.set_attr("/steps", "replicas", 3);         // integral attribute
    f.set_attr("/steps", "temperature", 300.0);  // quantity attribute
  }
  EXPECT_EQ(stored_type(path, "/steps"), "integer 8 signed");
  EXPECT_EQ(stored_type(path, "/atoms"), "integer 8 signed");
  EXPECT_EQ(stored_type(path, "/big"), "integer 8 signed");
  EXPECT_EQ(stored_type(path, "/type"), "integer 8 signed");
  EXPECT_EQ(stored_type(path, "/strain_max"), "float 8");
  EXPECT_EQ(attr_type(path, "/steps", "replicas"), "integer");
  EXPECT_EQ(attr_type(path, "/steps", "temperature"), "float");

  pnc::h5::File r(path, pnc::h5::File::Mode::read);
  EXPECT_EQ(r.read_integer("/big"), big); // exact: no trip through double
  EXPECT_TRUE(r.is_integer("/steps"));
  EXPECT_FALSE(r.is_integer("/strain_max"));
  // readers of numbers take either type, so files of earlier versions (counts as doubles) and
  // new ones read the same
  EXPECT_EQ(r.read_scalar("/steps"), 20.0);
  EXPECT_EQ(r.read_vector("/type"), (std::vector<double>{1, 2, 2, 3}));
  EXPECT_EQ(r.attr_double("/steps", "replicas").value(), 3.0);
  try {
    (void)r.read_integer("/strain_max");
    FAIL() << "a floating-point dataset read as an integer";
  } catch (const pnc::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/strain_max"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected an integer dataset"), std::string::npos)
        << e.what();
  }
}

TEST(Hdf5Conventions, ProvenanceNamesSoftwareTimeAndCommand) {
  const auto d = pnc::test::fresh_dir("h5conv_prov");
  const std::string a = (d / "a.h5").string(), b = (d / "b.h5").string(), c = (d / "c.h5").string();
  const std::string saved = pnc::invocation();
  pnc::set_invocation("");
  {
    pnc::h5::File f(a, pnc::h5::File::Mode::truncate);
    pnc::h5::write_provenance(f); // no command known: said so
  }
  pnc::set_invocation("pnc characterize 'my recipe.json' --out run");
  {
    pnc::h5::File f(b, pnc::h5::File::Mode::truncate);
    pnc::h5::write_provenance(f); // the running program's command line
  }
  {
    pnc::h5::File f(c, pnc::h5::File::Mode::truncate);
    pnc::h5::write_provenance(f, "pnc fit data.csv --out card.h5"); // given explicitly
  }
  pnc::set_invocation(saved);
  const auto cmd = [](const std::string& p) {
    return pnc::h5::File(p, pnc::h5::File::Mode::read).attr_string("/provenance", "command");
  };
  EXPECT_EQ(cmd(a).value(), "(not run from the pnc command)");
  EXPECT_EQ(cmd(b).value(), "pnc characterize 'my recipe.json' --out run");
  EXPECT_EQ(cmd(c).value(), "pnc fit data.csv --out card.h5");
  pnc::h5::File r(b, pnc::h5::File::Mode::read);
  EXPECT_EQ(r.read_string("/provenance/software"), pnc::version_string());
  EXPECT_EQ(r.attr_string("/", "software").value(), pnc::version_string());
  const std::string created = r.attr_string("/provenance", "created").value();
  // ISO 8601 UTC to the second: YYYY-MM-DDTHH:MM:SSZ
  ASSERT_EQ(created.size(), 20u) << created;
  EXPECT_EQ(created[4], '-');
  EXPECT_EQ(created[10], 'T');
  EXPECT_EQ(created.back(), 'Z');
}
