#pragma once
// The observers of a coupled run (coupled_run.hpp), each the owner of one output in the run
// directory (docs/escm.md "Outputs", columns in docs/formats.md):
//  - energy.csv: the coupler's energy log (Coupler::write_energy_csv);
//  - profile.csv: displacement and gradient along the block's middle cell row at each frame;
//  - atoms_<k>.vtu, particles_<k>.vtu: the VTU frames with the displacement gradients;
//  - crack.csv and the "crack" block of summary.json (Cases II/III, D80-D84).
// summary.json itself is written by write_couple_summary() from the run and the observers.
#include "coupled_run.hpp"

#include "pnc/gimp_coupler/escm_crack.hpp"

#include <memory>

namespace pnc::gimp::escm {

std::unique_ptr<Observer> make_energy_log();
std::unique_ptr<Observer> make_profile(const CoupledRun& run);
std::unique_ptr<Observer> make_frames();
/// `bonds`: the region's monitor of the atom pairs across the crack line (D82); `progress`:
/// one line per frame on stderr.
std::unique_ptr<Observer> make_crack_record(const CoupledRun& run,
                                            std::unique_ptr<BondMonitor> bonds, bool progress);

/// summary.json of a finished run (keys in docs/escm.md, "Outputs"): the run, the region's
/// block (MdRegion::summarize), the observers' parts, the handshake continuity (D106) and the
/// checkpoint record of `r`. Sets r.summary_json.
void write_couple_summary(CoupledRun& run, const MdRegion& region, const CoupleOptions& o,
                          CoupleSummary& r);
/// profile.png, energy.png (and crack.png) by plot_escm.py; a failure is a warning in r.
void plot_couple(const std::string& out_dir, bool crack, CoupleSummary& r);

} // namespace pnc::gimp::escm
