// `pnc card export`: the host input blocks, and the exported PROPS fed to umat_ reproduce
// the plugin's stress along a damaging path (also with a turned platelet, 32 PROPS).
#include "material_cli.hpp"

#include "pnc/damage/card.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/fe_material/material.hpp"
#include "pnc/fe_material/umat.h"

#include <nlohmann/json.hpp>

#include <cmath>

using pnc::test::CliResult;
using pnc::test::MaterialCli;
namespace fs = std::filesystem;

namespace {

// Abaqus order 11,22,33,12,13,23 -> plugin (Voigt) index
constexpr int kAbaqus[6] = {0, 1, 2, 5, 4, 3};

std::vector<double> parse_props(const std::string& text) {
  std::vector<double> v;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty()) v.push_back(std::stod(line));
  return v;
}

} // namespace

TEST_F(MaterialCli, CardExportPrintsTheHostBlocks) {
  const std::string card = tables_card();
  const CliResult a = run("card export '" + card + "' --format abaqus");
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_NE(a.out.find("*MATERIAL, NAME=PNC\n*USER MATERIAL, CONSTANTS=23, UNSYMM\n1., "),
            std::string::npos)
      << a.out;
  EXPECT_NE(a.out.find("*DEPVAR\n6\n1, kappa1, "), std::string::npos) << a.out;
  EXPECT_NE(a.out.find("6, D3, damage variable D3"), std::string::npos) << a.out;
  const CliResult c = run("card export '" + card + "' --format calculix --name CLAY_PP");
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_NE(c.out.find("*MATERIAL, NAME=ABAQUSCLAY_PP\n*USER MATERIAL, CONSTANTS=23\n"),
            std::string::npos)
      << c.out;
  EXPECT_NE(c.out.find("*DEPVAR\n6\n"), std::string::npos) << c.out;
  // data lines carry at most 8 numbers
  std::istringstream in(a.out);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '*') {
      EXPECT_LE(std::count(line.begin(), line.end(), ','), 8) << line;
    }
  }
  // JSON: PROPS in order with names, units and the card's values (through the C ABI)
  const CliResult j = run("card export '" + card + "' --format json");
  ASSERT_EQ(j.code, 0) << j.err;
  const auto doc = nlohmann::json::parse(j.out);
  const auto mat = pnc::fe_material::Material::from_card(card);
  const auto names = mat.constant_names();
  const auto values = mat.constants();
  ASSERT_EQ(doc["nprops"].get<std::size_t>(), names.size() + 1);
  EXPECT_EQ(doc["props"][0]["name"], "model_code");
  EXPECT_EQ(doc["props"][0]["value"].get<double>(), 1.0);
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(doc["props"][i + 1]["name"], names[i]);
    EXPECT_EQ(doc["props"][i + 1]["index"].get<std::size_t>(), i + 2);
    EXPECT_EQ(doc["props"][i + 1]["value"].get<double>(), values[i]);
    EXPECT_EQ(doc["props"][i + 1]["units"], names[i] == "alpha" ? "1" : "Pa");
  }
  EXPECT_EQ(doc["nstatv"].get<int>(), 6);
  // bad names and formats
  const CliResult bad = run("card export '" + card + "' --format calculix --name 'A B'");
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("field '--name': value 'A B'"), std::string::npos) << bad.err;
  EXPECT_NE(run("card export '" + card + "' --format nastran").code, 0);
}

TEST_F(MaterialCli, ExportedPropsThroughUmatReproduceThePlugin) {
  // a card with a turned platelet, written here
  pnc::damage::NdmParameters par = pnc::damage::dissertation_parameters(pnc::damage::Model::pnc);
  par.R = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()))
              .toRotationMatrix()
              .transpose();
  const std::string card = p("turned.h5");
  pnc::damage::write_card(card, pnc::damage::card_from_parameters(par, "test"), "test");
  for (const std::string& file : {card, tables_card("pp")}) {
    const CliResult r = run("card export '" + file + "' --format props");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::vector<double> props = parse_props(r.out);
    const auto mat = pnc::fe_material::Plugin(PNC_PLUGIN).from_card(file);
    const int ns = mat.n_state();
    ASSERT_EQ(props.size(),
              static_cast<std::size_t>(mat.n_constants() + 1 + (file == card ? 9 : 0)));
    // a damaging path with shear, load and unload
    std::vector<double> s0 = mat.initial_state(), s1;
    std::vector<double> statev(static_cast<std::size_t>(ns), 0.0); // Abaqus: zeros
    pnc::fe_material::Voigt6 e0{}, de{}, sig{};
    std::array<double, 6> stran{}, dstran{}, stress{};
    std::array<double, 36> ddsdde{}, K{};
    double sse = 0, spd = 0, scd = 0, rpl = 0, pnewdt = 1, dtime = 1, temp = 0, celent = 1;
    std::array<double, 36> scratch{};
    int ndi = 3, nshr = 3, ntens = 6, nstatv = ns, nprops = static_cast<int>(props.size());
    int noel = 1, npt = 1, one = 1;
    char cmname[80];
    std::fill(std::begin(cmname), std::end(cmname), ' ');
    for (int step = 1; step <= 40; ++step) {
      const double t = step <= 30 ? step / 30.0 : (40 - step) / 10.0 * 0.5 + 0.5;
      const pnc::fe_material::Voigt6 e = {0.25 * t, -0.02 * t, 0.01 * t, 0.03 * t, 0.0, 0.05 * t};
      for (int i = 0; i < 6; ++i)
        de[static_cast<std::size_t>(i)] =
            e[static_cast<std::size_t>(i)] - e0[static_cast<std::size_t>(i)];
      mat.integrate(s0, s1, e0, de, sig, &K);
      for (int a = 0; a < 6; ++a)
        dstran[static_cast<std::size_t>(a)] = de[static_cast<std::size_t>(kAbaqus[a])];
      pnc_umat_(stress.data(), statev.data(), ddsdde.data(), &sse, &spd, &scd, &rpl, scratch.data(),
                scratch.data(), scratch.data(), stran.data(), dstran.data(), scratch.data(), &dtime,
                &temp, &temp, scratch.data(), scratch.data(), cmname, &ndi, &nshr, &ntens, &nstatv,
                props.data(), &nprops, scratch.data(), scratch.data(), &pnewdt, &celent,
                scratch.data(), scratch.data(), &noel, &npt, &one, &one, &one, &one, sizeof cmname);
      ASSERT_EQ(pnewdt, 1.0) << file << " step " << step;
      for (int a = 0; a < 6; ++a) {
        const double ref = sig[static_cast<std::size_t>(kAbaqus[a])];
        EXPECT_NEAR(stress[static_cast<std::size_t>(a)], ref, 1e-12 * std::abs(ref) + 1e-6)
            << file << " step " << step << " component " << a;
      }
      for (int i = 0; i < ns; ++i)
        EXPECT_NEAR(statev[static_cast<std::size_t>(i)], s1[static_cast<std::size_t>(i)], 1e-14);
      for (int a = 0; a < 6; ++a)
        stran[static_cast<std::size_t>(a)] += dstran[static_cast<std::size_t>(a)];
      s0 = s1;
      e0 = e;
    }
    EXPECT_GT(s0[static_cast<std::size_t>(ns / 2)], 0.0) << file; // damaged (D1 or D)
  }
}
