// The unit constants of pnc/core/units.hpp against independent arithmetic, and the rule that
// no other source spells them as literals.
#include "pnc/core/units.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace fs = std::filesystem;
using namespace pnc;

TEST(Units, DerivedConversionsMatchTabulatedValues) {
  // Tabulated conversions, each to the digits quoted (tolerance: half the last digit).
  // 1 eV = 96.48533212 kJ/mol (CODATA 2018, e N_A) = 23.060548 kcal/mol.
  EXPECT_NEAR(1.602176634e-19 / units::joule_per_kcal_mol, 23.060548, 5e-7);
  EXPECT_NEAR(units::joule_per_kcal_mol * units::kcal_mol_per_joule, 1.0, 1e-15);
  // 1 kcal/mol/A^3 = 6.947695 GPa, 1 kcal/mol/A = 69.47695 pN (LAMMPS real-units tables).
  EXPECT_NEAR(units::pa_per_kcal_mol_A3 / 1e9, 6.947695, 5e-7);
  EXPECT_NEAR(units::newton_per_kcal_mol_A * 1e12, 69.47695, 5e-6);
  EXPECT_NEAR(units::j_m2_per_kcal_mol_A2, 0.6947695, 5e-8); // J/m^2 (6.947695e-21 J / 1e-20 m^2)
  // 1 g/mol per molecule = 1 Da = 1.66053906660e-27 kg (CODATA 2018; the molar mass constant
  // is 1 g/mol to 3.5e-10 since 2019).
  EXPECT_NEAR(units::kg_per_g_mol / 1.66053906660e-27, 1.0, 1e-9);
  // 1 A/fs = 1e-10 m / 1e-15 s = 1e5 m/s (to the rounding of the quotient).
  EXPECT_NEAR(units::m_per_s_per_angstrom_per_fs / 1e5, 1.0, 1e-15);
}

TEST(Units, BoltzmannInKcalPerMolKIsLammpsValueWithinItsCodata) {
  // LAMMPS real units use k_B = 0.0019872067 kcal/mol/K (CODATA 2006 R = 8.314472(15) J/mol/K,
  // relative standard uncertainty 1.8e-6); the exact SI value R = k_B N_A must agree within
  // two of those uncertainties.
  const double exact = units::boltzmann * units::avogadro / units::joule_per_kcal;
  EXPECT_NEAR(units::kB_kcal_mol_K / exact - 1.0, 0.0, 2 * 1.8e-6);
}

TEST(Units, NoOtherSourceSpellsAConstantAsALiteral) {
  // Literals of N_A, k_B, the calorie and the atmosphere outside units.hpp (comments aside),
  // and a conversion factor of its own (`constexpr double m_per_A = 1e-10`, `x_per_y = 1e5`):
  // a name "<unit>_per_<unit>" or "<unit>_to_<unit>" given a number literal.
  const std::regex literal(R"((6\.022|1\.3806|4184|4\.184|101325|0\.0019872))");
  const std::regex own_factor(R"(\b[A-Za-z]\w*_(per|to)_\w+\s*=\s*[-+]?[0-9.])");
  const fs::path root = PNC_SOURCE_DIR;
  std::string offenders;
  for (const char* part : {"core", "damage", "md", "rve", "thermo", "fe_material", "gimp_coupler",
                           "app", "examples", "bench"}) {
    if (!fs::exists(root / part)) continue;
    for (const auto& e : fs::recursive_directory_iterator(root / part)) {
      const auto ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".cpp" && ext != ".hpp" && ext != ".cc" && ext != ".h"))
        continue;
      if (e.path().filename() == "units.hpp") continue;
      std::ifstream in(e.path());
      std::string line;
      for (int n = 1; std::getline(in, line); ++n) {
        const auto code = line.substr(0, line.find("//"));
        const bool declares = code.find("const") != std::string::npos;
        if (std::regex_search(code, literal) || (declares && std::regex_search(code, own_factor)))
          offenders += e.path().lexically_relative(root).string() + ":" + std::to_string(n) + ": " +
                       line + "\n";
      }
    }
  }
  EXPECT_TRUE(offenders.empty()) << "use pnc/core/units.hpp instead of:\n" << offenders;
}
