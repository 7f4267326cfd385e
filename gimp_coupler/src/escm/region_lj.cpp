// The LJ FCC crystal MD region (md.type "lj", the default; escm_lj.hpp, D76-D78, D83).
#include "md_region.hpp"

#include <sstream>

namespace pnc::gimp::escm {

namespace {

class LjRegion final : public MdRegion {
public:
  void check_input(const CoupleInput&, const std::string&) const override {}

  void build(const CoupleInput& p, const std::string&, const std::string&, bool) override {
    lj_ = lj_fcc(p.eps, p.sig, p.rc, p.mass); // lattice sums (D76)
    eps_ = p.eps;
    sig_ = p.sig;
    rc_ = p.rc;
  }
  const LjFcc& calibration() const override { return lj_; }
  double cutoff_A() const override { return rc_; }
  double separation_work() const override {
    return lj_fcc_separation_work(lj_, eps_, sig_, rc_); // D83
  }

  std::vector<std::string> md_setup(const CoupleInput& p) const override {
    std::vector<std::string> c =
        lj_fcc_block_commands(lj_, p.nbx, p.nby, p.nz, p.mass, p.eps, p.sig, p.rc, p.crack ? 2 : 1);
    if (p.crack) append_weak_interface(c, (p.nby / 2 - 0.25) * lj_.a0_A, p);
    return c;
  }

  // The FCC block starts a0/4 inside its first cell.
  Eigen::Vector2d md_offset(const CoupleInput& p, double h) const override {
    return Eigen::Vector2d(p.block_x0() * h + 0.25 * h, p.block_y0() * h + 0.25 * h);
  }

  // D82: the crack line lies a0/4 below the atom row of the block's middle cell row; the free
  // region starts svc_rings cells into the block; D91: a column has slipped past a0/2.
  std::unique_ptr<BondMonitor> bond_monitor(const Coupler& cp,
                                            const CoupleInput& p) const override {
    return std::make_unique<BondMonitor>(cp, (p.nby / 2 - 0.25) * lj_.a0_A,
                                         (p.svc - 0.25) * lj_.a0_A, lj_.a0_A, 0.85 * lj_.a0_A,
                                         lj_inflection(p.sig), 0.5 * lj_.a0_A);
  }

  void summarize(nlohmann::json& sj) const override {
    // SI keys with unit suffixes (D238, D282)
    sj["lj_fcc"] = {{"a0_m", lj_.a0_A * units::m_per_A},
                    {"C11_Pa", lj_.C11},
                    {"C12_Pa", lj_.C12},
                    {"C44_Pa", lj_.C44},
                    {"E_Pa", lj_.E()},
                    {"nu", lj_.nu()},
                    {"density_kg_per_m3", lj_.density}};
  }

private:
  /// D83: the atoms above the crack line become type 2; pairs across the line (types 1-2) get
  /// LJ epsilon x interface_fraction (y_line_A in the LAMMPS frame).
  static void append_weak_interface(std::vector<std::string>& cmds, double y_line_A,
                                    const CoupleInput& p) {
    std::ostringstream s;
    s.precision(12);
    s << "region escm_upper block INF INF " << y_line_A << " INF INF INF units box";
    cmds.push_back(s.str());
    cmds.push_back("set region escm_upper type 2");
    s.str("");
    s << "pair_coeff 1 2 " << p.crack_f * p.eps << ' ' << p.sig;
    cmds.push_back(s.str());
  }

  LjFcc lj_;
  double eps_ = 0.0, sig_ = 0.0, rc_ = 0.0;
};

} // namespace

[[maybe_unused]] const bool lj_registered =
    register_md_region("lj", [] { return std::make_unique<LjRegion>(); });

} // namespace pnc::gimp::escm
