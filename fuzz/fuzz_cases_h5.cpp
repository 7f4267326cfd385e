// Fuzz target: the cases.h5 reader (pnc::damage::read_stress_strain_h5). Input: the bytes of
// an HDF5 file (the seed corpus holds small valid files written by pnc).
#include "fuzz_util.hpp"

#include "pnc/damage/data.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static pnc::fuzz::ScratchFile file(".h5");
  const std::string& path = file.write(data, size);
  pnc::fuzz::expect_clean([&] { (void)pnc::damage::read_stress_strain_h5(path); });
  return 0;
}
