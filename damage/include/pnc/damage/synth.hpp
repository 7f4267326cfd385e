#pragma once
// pnc/damage/synth.hpp: synthetic stress-strain curves from the NDM itself (for the main
// demo, for fit-validation tests and for benchmarks). Stress = kernel response along each
// case's monotonic strain path + independent Gaussian noise of a given standard deviation.
// Units: noise_sd in Pa, like the stresses.
#include "pnc/damage/data.hpp"
#include "pnc/damage/ndm.hpp"

#include <cstdint>
#include <vector>

namespace pnc::damage {

struct SynthOptions {
  std::vector<int> cases;      ///< case ids 1..9 (D424); empty = the model's cases
  int points = 200;            ///< points per case, >= 3
  double max_extension = 0.20; ///< largest imposed normal strain, > 0
  double max_shear = 0.40;     ///< largest imposed engineering shear strain, > 0
  double noise_sd = 2e6;       ///< Pa, >= 0
  std::uint64_t seed = 1;
  void validate() const; ///< throws pnc::InputError naming the option
};

/// Curves for every requested case; the recorded stress_stderr equals noise_sd (when > 0).
StressStrainData synthesize(const NdmParameters& p, const SynthOptions& o);

} // namespace pnc::damage
