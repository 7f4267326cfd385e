// The VTU output of the GIMP run driver: base64 and the particle data, ASCII and binary.
#include "test_input_util.hpp"

#include "pnc/gimp_coupler/input.hpp"
#include "pnc/gimp_coupler/output.hpp"
#include "pnc/gimp_coupler/run.hpp"

#include "pnc/core/error.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/reference.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace pnc::gimp;
using namespace pnc::gimp::test;

namespace {
std::vector<unsigned char> unbase64(const std::string& s) {
  auto val = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<unsigned char> out;
  unsigned buf = 0;
  int bits = 0;
  for (char c : s) {
    const int v = val(c);
    if (v < 0) continue;
    buf = (buf << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((buf >> bits) & 0xFF));
    }
  }
  return out;
}
/// The text between <DataArray ... Name="name" ...> and </DataArray>.
std::string data_array(const std::string& xml, const std::string& name) {
  const auto a = xml.find("Name=\"" + name + "\"");
  const auto b = xml.find('>', a) + 1;
  const auto e = xml.find("</DataArray>", b);
  return xml.substr(b, e - b);
}
} // namespace

TEST(GimpOutput, Base64MatchesRfc4648) {
  const std::string t = "Many hands make light work.";
  EXPECT_EQ(base64(reinterpret_cast<const unsigned char*>(t.data()), t.size()),
            "TWFueSBoYW5kcyBtYWtlIGxpZ2h0IHdvcmsu");
  EXPECT_EQ(base64(reinterpret_cast<const unsigned char*>("ab"), 2), "YWI=");
  EXPECT_EQ(base64(reinterpret_cast<const unsigned char*>("a"), 1), "YQ==");
}

TEST(GimpOutput, VtuAsciiAndBinaryHoldTheParticleData) {
  Solver<2> s;
  load_input_text<2>(base_input().dump(), "in.json", "", s);
  s.initialize();
  s.step(1e-7);
  const fs::path d = tmpdir("vtu");
  for (bool binary : {false, true}) {
    const std::string path = (d / (binary ? "b.vtu" : "a.vtu")).string();
    write_vtu<2>(path, s, binary, {"poly"});
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string xml = ss.str();
    EXPECT_NE(xml.find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
    EXPECT_NE(xml.find("NumberOfPoints=\"" + std::to_string(s.particles.size()) + "\""),
              std::string::npos);
    for (const char* name : {"displacement_m", "velocity_m_per_s", "stress_Pa", "strain_1",
                             "density_kg_per_m3", "volume_m3", "mass_kg",
                             "strain_energy_density_J_per_m3", "material_index", "types", "time_s"})
      EXPECT_NE(xml.find(std::string("Name=\"") + name + "\""), std::string::npos) << name;
    // the symmetric tensors as one 6-component array each (D236)
    for (const char* name : {"stress_Pa", "strain_1"})
      EXPECT_NE(xml.find(std::string("Name=\"") + name + "\" NumberOfTuples=\"" +
                         std::to_string(s.particles.size()) + "\" NumberOfComponents=\"6\""),
                std::string::npos)
          << name;
    std::vector<double> pts;
    const std::string body = data_array(xml, "Points");
    if (binary) {
      const auto bytes = unbase64(body);
      std::uint32_t nb;
      std::memcpy(&nb, bytes.data(), 4);
      ASSERT_EQ(nb, 3 * s.particles.size() * sizeof(double));
      ASSERT_EQ(bytes.size(), 4 + nb);
      pts.resize(nb / sizeof(double));
      std::memcpy(pts.data(), bytes.data() + 4, nb);
    } else {
      std::istringstream in(body);
      double v;
      while (in >> v)
        pts.push_back(v);
    }
    ASSERT_EQ(pts.size(), 3 * s.particles.size());
    for (std::size_t p = 0; p < s.particles.size(); ++p) {
      EXPECT_NEAR(pts[3 * p], s.particles.x[p][0], binary ? 0.0 : 1e-10);
      EXPECT_NEAR(pts[3 * p + 1], s.particles.x[p][1], binary ? 0.0 : 1e-10);
      EXPECT_EQ(pts[3 * p + 2], 0.0);
    }
  }
}
