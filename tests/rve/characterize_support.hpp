// Shared by the pnc characterize CLI tests: the tiny recipe (seconds per replica), running pnc
// and reading a file.
#pragma once

#include "common/run_command.hpp"
#include "common/temp_dir.hpp" // slurp

#include <string>

namespace pnc::test {

/// pnc (PNC_EXE) with `args` through the shell; its stdout and exit code.
inline CommandResult run_pnc(const std::string& args) {
  return run_command(std::string(PNC_EXE) + " " + args);
}

/// A pure-polymer recipe small enough for a test: 8 chains, two cases (2: extension, 6: shear)
/// of 3 steps to 3 % strain, short stages; the machinery is under test, not the physics.
inline const char* const tiny_recipe = R"({
  "name": "tiny", "seed": 3,
  "build": { "chains": 8 },
  "equilibrate": { "pushoff_steps": 500, "hot_steps": 1000, "cool_steps": 500,
                   "langevin_chunk_steps": 200, "langevin_max_chunks": 2,
                   "npt_steps": 1000, "final_steps": 200 },
  "deform": { "cases": [2, 6], "strain_max": 0.03, "steps": 3, "timestep_fs": 1.0,
              "hold_steps": 200, "sample_every": 10, "blocks": 4 },
  "phase_check": { "enabled": true, "steps": 1000, "sample_every": 5,
                   "cavitation_steps": 200 },
  "analysis": { "moving_average": 1 },
  "run": { "jobs": 2 }
})";

} // namespace pnc::test
