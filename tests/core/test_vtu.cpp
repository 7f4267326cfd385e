// pnc/core/vtu.hpp (D236): point-cloud VTU frames and PVD collections. The round trip through
// VTK's own readers is read_vtu.py (ctest Vtu.vtk_reads_*); here: the file's structure, the
// base64 encoding, the symmetric order and the input errors.
#include "pnc/core/error.hpp"
#include "pnc/core/vtu.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace pnc::vtu;

namespace {
using pnc::test::slurp;
fs::path tmpdir(const std::string& name) {
  return pnc::test::fresh_dir("test_vtu_" + name);
}
Frame two_points() {
  Frame f;
  f.points = {{1.0, 2.0, 3.0}, {-0.5, 0.25, 0.0}};
  f.arrays = {{"stress_Pa", "Pa", 6, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}, {}},
              {"zone_index", "index", 1, {}, {3, -1}}};
  f.field = {{"time_s", "s", 0.5}};
  return f;
}
/// The InputError's message when `f` throws one, else "".
template <class F> std::string error_of(F f) {
  try {
    f();
  } catch (const pnc::InputError& e) {
    return e.what();
  }
  return "";
}
} // namespace

TEST(Vtu, SymmetricOrderIsXxYyZzXyYzXz) {
  const double m[9] = {11, 12, 13, 12, 22, 23, 13, 23, 33};
  EXPECT_EQ(symmetric6(m), (std::array<double, 6>{11, 22, 33, 12, 23, 13}));
}

TEST(Vtu, AsciiFrameNamesComponentsAndUnits) {
  const fs::path d = tmpdir("ascii");
  write_vtu((d / "a.vtu").string(), two_points());
  const std::string x = slurp(d / "a.vtu");
  EXPECT_NE(x.find("NumberOfPoints=\"2\" NumberOfCells=\"2\""), std::string::npos);
  EXPECT_NE(
      x.find("Name=\"stress_Pa\" NumberOfTuples=\"2\" NumberOfComponents=\"6\" format=\"ascii\""),
      std::string::npos);
  EXPECT_NE(x.find("<DataArray type=\"Int32\" Name=\"zone_index\""), std::string::npos);
  EXPECT_NE(x.find("<DataArray type=\"Float64\" Name=\"time_s\" NumberOfTuples=\"1\" "
                   "format=\"ascii\">\n0.5\n"),
            std::string::npos);
  // "stress_Pa=Pa": s t r e s s _ P a = P a as bytes
  EXPECT_NE(x.find("115 116 114 101 115 115 95 80 97 61 80 97 0"), std::string::npos);
  EXPECT_NE(x.find("1 2 3 4 5 6\n7 8 9 10 11 12\n"), std::string::npos);
}

TEST(Vtu, Base64HoldsTheExactDoubles) {
  const fs::path d = tmpdir("b64");
  Frame f = two_points();
  f.points[1][0] = 0.1; // not exact in decimal
  write_vtu((d / "b.vtu").string(), f, {Encoding::base64, 17});
  const std::string x = slurp(d / "b.vtu");
  const auto a = x.find("Name=\"Points\"");
  const auto b = x.find(">\n", a) + 2;
  const std::string body = x.substr(b, x.find('\n', b) - b);
  // 4-byte header + 48 bytes = 52 bytes -> 72 base64 characters (with padding)
  ASSERT_EQ(body.size(), 72u);
  std::string bytes;
  unsigned buf = 0;
  int bits = 0;
  const std::string tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  for (char c : body) {
    if (c == '=') break;
    buf = (buf << 6) | static_cast<unsigned>(tbl.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      bytes += static_cast<char>((buf >> bits) & 0xFF);
    }
  }
  ASSERT_EQ(bytes.size(), 52u);
  std::uint32_t nb;
  std::memcpy(&nb, bytes.data(), 4);
  EXPECT_EQ(nb, 48u);
  double v[6];
  std::memcpy(v, bytes.data() + 4, 48);
  EXPECT_EQ(v[3], 0.1);
  EXPECT_EQ(v[2], 3.0);
}

TEST(Vtu, BadArraysAreInputErrorsNamingFileArrayAndRule) {
  const fs::path d = tmpdir("bad");
  const std::string p = (d / "x.vtu").string();
  Frame f = two_points();
  f.arrays[0].components = 4;
  auto e = error_of([&] { write_vtu(p, f); });
  EXPECT_NE(e.find(p), std::string::npos) << e;
  EXPECT_NE(e.find("stress_Pa"), std::string::npos) << e;
  EXPECT_NE(e.find("1, 3, 6"), std::string::npos) << e;
  f = two_points();
  f.arrays[0].values.pop_back();
  e = error_of([&] { write_vtu(p, f); });
  EXPECT_NE(e.find("'11'"), std::string::npos) << e;
  EXPECT_NE(e.find("2 x 6"), std::string::npos) << e;
  f = two_points();
  f.arrays[1].labels.push_back(0);
  EXPECT_NE(error_of([&] { write_vtu(p, f); }).find("one label per point"), std::string::npos);
  f = two_points();
  f.arrays[0].name = "a\"b";
  EXPECT_NE(error_of([&] { write_vtu(p, f); }).find("quotes"), std::string::npos);
  f = two_points();
  f.arrays[0].unit = "a=b"; // would break the "units" list
  EXPECT_NE(error_of([&] { write_vtu(p, f); }).find("="), std::string::npos);
  EXPECT_NE(error_of([&] {
              write_vtu(p, two_points(), {Encoding::ascii, 0});
            }).find("1 to 17"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(p)); // nothing written
}

TEST(Vtu, PvdTimestepsMustIncreaseStrictly) {
  const fs::path d = tmpdir("pvd");
  const std::string p = (d / "s.pvd").string();
  write_pvd(p, {{"a.vtu", 0.0}, {"b.vtu", 1e-7}, {"c.vtu", 2e-7}});
  const std::string x = slurp(p);
  EXPECT_NE(x.find("<DataSet timestep=\"1e-07\" part=\"0\" file=\"b.vtu\"/>"), std::string::npos)
      << x;
  const auto e = error_of([&] { write_pvd(p, {{"a.vtu", 1.0}, {"b.vtu", 2.0}, {"c.vtu", 2.0}}); });
  EXPECT_NE(e.find("timestep of entry 2"), std::string::npos) << e;
  EXPECT_NE(e.find("increase strictly"), std::string::npos) << e;
  EXPECT_EQ(slurp(p), x); // the old file stays
  EXPECT_NE(error_of([&] {
              write_pvd(p, {{"a.vtu", std::nan("")}});
            }).find("finite"),
            std::string::npos);
}
