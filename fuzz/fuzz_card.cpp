// Fuzz target: the material card reader (pnc::damage::read_card, which validates the
// constants). Input: the bytes of an HDF5 card (the seed corpus holds small valid cards).
#include "fuzz_util.hpp"

#include "pnc/damage/card.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static pnc::fuzz::ScratchFile file(".h5");
  const std::string& path = file.write(data, size);
  pnc::fuzz::expect_clean([&] { (void)pnc::damage::read_card(path); });
  return 0;
}
