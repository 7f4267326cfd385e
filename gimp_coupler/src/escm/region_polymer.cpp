// The coarse-grained polypropylene MD region (md.type "polymer"; escm_polymer.hpp,
// docs/escm.md "Polymer MD region", D100-D107, D114).
#include "md_region.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/gimp_coupler/escm_polymer.hpp"

#include <cmath>
#include <fmt/format.h>

#include <iostream>
#include <limits>
#include <stdexcept>

namespace pnc::gimp::escm {

namespace {

class PolymerRegion final : public MdRegion {
public:
  void check_input(const CoupleInput& p, const std::string& src) const override {
    // D114: Cases II/III with the polymer: the crack line is a weak interface of the block;
    // the continuum's Gc must be given (no lattice sum gives the polymer's work of separation).
    if (p.crack && !(p.crack_Gc > 0))
      fail(src, "crack.Gc", "", "must be given with md.type \"polymer\" (J/m^2, D114)");
    if (!p.crack && p.load != "tension_x")
      fail(src, "load", "\"" + p.load + "\"",
           "without a crack the polymer MD region runs Case I (\"tension_x\")");
    if (p.lj_given) fail(src, "lj", "", "not used with md.type \"polymer\"");
  }

  void build(const CoupleInput& p, const std::string& out_dir, const std::string& src,
             bool progress) override;
  const LjFcc& calibration() const override { return lj_; }
  double cutoff_A() const override { return rc_A_; }
  double separation_work() const override { return 0.0; } // crack.Gc is required (D114)

  // The block carries its interface in its data file and md_setup (D114).
  std::vector<std::string> md_setup(const CoupleInput&) const override { return poly_.md_setup; }

  // The block's atoms lie in [0, nb h) of the LAMMPS frame (D101).
  Eigen::Vector2d md_offset(const CoupleInput& p, double h) const override {
    return Eigen::Vector2d(p.block_x0() * h, p.block_y0() * h);
  }

  // D114: the line at the middle row's lower edge, the block from 0; the monitored pairs are
  // the non-bonded ones across it at or inside the LJ minimum 2^(1/6) sigma at the start (an
  // amorphous block has pairs at every distance: only these are bonds), broken past the LJ
  // inflection (26/7)^(1/6) sigma, as for the crystal.
  std::unique_ptr<BondMonitor> bond_monitor(const Coupler& cp,
                                            const CoupleInput& p) const override {
    return std::make_unique<BondMonitor>(cp, poly_.interface_y_A, p.svc * lj_.a0_A, lj_.a0_A,
                                         std::pow(2.0, 1.0 / 6.0) * sigma_A_,
                                         lj_inflection(sigma_A_), 0.5 * lj_.a0_A);
  }

  // D107: the left reaction at the end of the settle phase, before any load; a block that is
  // not in equilibrium when the coupling starts shows up here (not kept over a resume).
  void after_step(const Solver<2>& s, double t_settle, double dt, int comp) override {
    if (std::isnan(reaction_settle_) && s.time >= t_settle - 0.5 * dt)
      reaction_settle_ = s.bcs[0].reaction[comp];
  }

  void summarize(nlohmann::json& sj) const override {
    sj["polymer"] = json_;
    if (!std::isnan(reaction_settle_))
      sj["polymer"]["reaction_left_end_of_settle_N_per_m"] = reaction_settle_;
  }

private:
  PolymerBlock poly_;
  LjFcc lj_;
  double rc_A_ = 0.0, sigma_A_ = 0.0; ///< the polymer's LJ cut-off and sigma (D114)
  nlohmann::json json_;
  double reaction_settle_ = std::numeric_limits<double>::quiet_NaN();
};

void PolymerRegion::build(const CoupleInput& p, const std::string& out_dir, const std::string& src,
                          bool progress) {
  PolymerBlockSpec ps;
  ps.nbx = p.nbx;
  ps.nby = p.nby;
  ps.svc_rings = p.svc;
  ps.ivc_rings = p.ivc;
  ps.neumann = p.mode == "neumann";
  ps.cell_A = p.cell_A;
  ps.slab_A = p.slab_A;
  ps.density = p.density;
  ps.beads_per_chain = p.beads_per_chain;
  ps.seed = static_cast<std::uint64_t>(p.md_seed);
  ps.temperature = p.poly_T;
  ps.anneal_ps = p.anneal_ps;
  ps.min_beads_per_cell = p.min_beads;
  ps.strain_probe = p.strain_probe;
  ps.measure_elastic = !p.elastic_given;
  if (p.crack) { // D114: the crack line through the block's middle cell row
    ps.interface_row = p.nby / 2;
    ps.interface_fraction = p.crack_f;
  }
  if (p.ff_sigma > 0) ps.ff.sigma = p.ff_sigma;
  if (p.ff_epsilon > 0) ps.ff.epsilon = p.ff_epsilon;
  if (p.ff_cutoff_sigma > 0) ps.ff.cutoff_sigma = p.ff_cutoff_sigma;
  rc_A_ = ps.ff.cutoff();
  sigma_A_ = ps.ff.sigma;
  pnc::make_output_directory(out_dir);
  if (progress)
    std::cerr << fmt::format("pnc gimp couple: building the polymer block ({} x {} cells)\n", p.nbx,
                             p.nby);
  poly_ = build_polymer_block(ps, out_dir, src);
  lj_.a0_A = poly_.h_A;
  lj_.density = poly_.density_kg_m3;
  const double lam = p.elastic_given ? p.elastic_lambda : poly_.lambda;
  const double mu = p.elastic_given ? p.elastic_mu : poly_.mu;
  if (!(mu > 0 && lam + mu > 0))
    pnc::fail_simulation("ESCM polymer region", -1, std::numeric_limits<double>::quiet_NaN(), "",
                         "the measured elastic constants are not positive definite (lambda " +
                             std::to_string(lam) + " Pa, mu " + std::to_string(mu) +
                             " Pa): give md.elastic");
  lj_.C11 = lam + 2 * mu;
  lj_.C12 = lam;
  lj_.C44 = mu;
  json_ = {{"data_file", poly_.data_file},
           {"cell_size_m", poly_.h_A * units::m_per_A}, // SI keys (D238, D282)
           {"slab_m", poly_.Lz_A * units::m_per_A},
           {"density_kg_per_m3", poly_.density_kg_m3},
           {"build_density_kg_per_m3", poly_.build_density * 1000.0},
           {"atoms", poly_.atoms},
           {"chains", poly_.chains},
           {"beads_per_chain", poly_.beads_per_chain},
           {"elastic_source", p.elastic_given ? "given" : "measured"},
           {"lambda_Pa", lam},
           {"mu_Pa", mu},
           {"E_Pa", lj_.E()},
           {"nu", lj_.nu()},
           {"measured_C_Pa",
            {{"C11", poly_.C11},
             {"C22", poly_.C22},
             {"C33", poly_.C33},
             {"C12", poly_.C12},
             {"C21", poly_.C21},
             {"C31", poly_.C31},
             {"C32", poly_.C32}}},
           {"measured_lambda_Pa", poly_.lambda},
           {"measured_mu_Pa", poly_.mu},
           {"strain_probe", p.strain_probe},
           {"relaxed_pressure_Pa",
            {{"p", poly_.pressure_atm * pnc::units::pa_per_atm},
             {"pxx", poly_.pxx_atm * pnc::units::pa_per_atm},
             {"pyy", poly_.pyy_atm * pnc::units::pa_per_atm},
             {"pzz", poly_.pzz_atm * pnc::units::pa_per_atm}}},
           {"cut_periodic",
            {poly_.cut_periodic_bonds, poly_.cut_periodic_angles, poly_.cut_periodic_dihedrals}},
           {"cut_svc_free", {poly_.cut_svc_bonds, poly_.cut_svc_angles, poly_.cut_svc_dihedrals}},
           {"cut_interface",
            {poly_.cut_interface_bonds, poly_.cut_interface_angles, poly_.cut_interface_dihedrals}},
           {"interface_y_m", poly_.interface_y_A * units::m_per_A},
           {"atoms_changed_zone", poly_.moved_zone},
           {"surface_minimisation",
            {{"passes", poly_.surface_passes},
             {"atoms_changed_zone_last_pass", poly_.moved_zone_last},
             {"fmax_N", poly_.surface_fmax * units::N_per_kcalmolA},
             {"fnorm_N", poly_.surface_fnorm * units::N_per_kcalmolA}}},
           {"volume_cell_beads",
            {{"min", poly_.min_cell_beads},
             {"mean", poly_.mean_cell_beads},
             {"max", poly_.max_cell_beads}}},
           {"wall_s",
            {{"relax", poly_.relax_s}, {"surface", poly_.surface_s}, {"total", poly_.total_s}}}};
}

} // namespace

[[maybe_unused]] const bool polymer_registered =
    register_md_region("polymer", [] { return std::make_unique<PolymerRegion>(); });

} // namespace pnc::gimp::escm
