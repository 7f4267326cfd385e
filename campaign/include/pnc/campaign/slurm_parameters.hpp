#pragma once
// pnc/campaign/slurm_parameters.hpp: the "slurm" section of an input file declared once on the
// parameter layer (pnc/core/parameters.hpp) for every planned command: a `pnc characterize`
// recipe and a `pnc thermo ti --input` file (decisions D245, D301; docs/cluster.md).
#include "pnc/campaign/slurm.hpp"

#include <string>

namespace pnc {
class Parameters;
}

namespace pnc::campaign {

/// Declares the optional section "slurm" bound to `s` (`s.given`: the input has it):
/// partition, account, time (a Slurm time limit), template (a job-script file path), mpi
/// (srun's MPI plugin, a name; D332); with `ranks` also ranks and equilibrate_ranks (pnc
/// characterize; `pnc thermo ti` has its own key `ranks` outside the section, D324). Values are
/// checked by SlurmSpec::validate's rules. `text` says what the section is.
void declare_slurm_section(Parameters& p, SlurmSpec& s, const std::string& text, bool ranks);

} // namespace pnc::campaign
