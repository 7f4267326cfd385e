// Fuzz target: the stress-strain CSV reader (pnc::damage::read_stress_strain_csv, which goes
// through pnc::read_csv). Input: the bytes of a .csv file.
#include "fuzz_util.hpp"

#include "pnc/damage/data.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static pnc::fuzz::ScratchFile file(".csv");
  const std::string& path = file.write(data, size);
  pnc::fuzz::expect_clean([&] { (void)pnc::damage::read_stress_strain_csv(path); });
  return 0;
}
