#pragma once
// The MD region of a coupled run (`pnc gimp couple`, docs/escm.md): what the driver needs from
// the atoms' side, whatever they are. Each kind lives in its own file and registers itself
// there with one line,
//   const bool registered = register_md_region("lj", [] { return std::make_unique<LjRegion>(); });
// keyed by the input's `md.type`; the driver asks the registry (make_md_region) and never
// names a kind. The polymer kind is compiled only when rve/ is built, so a build without it
// simply does not know "polymer" (the input error lists the kinds it knows).
//
// Units: LAMMPS real in the LAMMPS frame (Angstrom, kcal/mol); the calibration in SI (Pa,
// kg/m^3; its a0_A is the continuum cell size in Angstrom).
#include "couple_input.hpp"

#include "pnc/gimp_coupler/escm.hpp"
#include "pnc/gimp_coupler/escm_crack.hpp"
#include "pnc/gimp_coupler/escm_lj.hpp"

#include <nlohmann/json.hpp>

#include <Eigen/Core>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace pnc::gimp::escm {

class MdRegion {
public:
  virtual ~MdRegion() = default;

  /// The rules of this kind on the input, after the common checks (pnc::InputError naming
  /// `src`, the key, the value and the rule).
  virtual void check_input(const CoupleInput& in, const std::string& src) const = 0;
  /// Builds the region if it must be built (the polymer block: LAMMPS stages in child
  /// processes, files in `out_dir`) and calibrates the continuum to it; calibration() and
  /// cutoff_A() are valid afterwards.
  virtual void build(const CoupleInput& in, const std::string& out_dir, const std::string& src,
                     bool progress) = 0;
  /// The continuum calibration (D76; polymer: D101, D102) in the LjFcc struct: a0_A = the cell
  /// size h, lambda = C12, mu = (C11 - C12) / 2, density.
  virtual const LjFcc& calibration() const = 0;
  /// Pair cut-off, A (the schwarz-mode check of D72).
  virtual double cutoff_A() const = 0;
  /// Work of separation of the perfect region across the crack line, J/m^2 (D83); 0 when no
  /// lattice sum gives it (then crack.Gc must be given).
  virtual double separation_work() const = 0;
  /// LAMMPS commands that create the region (Config::md_setup), with the weak interface of the
  /// crack cases (D83, D114); the driver appends `pair_modify shift yes` (D93).
  virtual std::vector<std::string> md_setup(const CoupleInput& in) const = 0;
  /// Continuum position (m) of the LAMMPS origin for cell size h (m).
  virtual Eigen::Vector2d md_offset(const CoupleInput& in, double h) const = 0;
  /// The atom pairs watched across the crack line (D82; polymer D114). Only with a crack.
  virtual std::unique_ptr<BondMonitor> bond_monitor(const Coupler& cp,
                                                    const CoupleInput& in) const = 0;
  /// Called after every coupled step with the continuum; `t_settle` (s) ends the settle phase,
  /// `dt` (s) is the coupled step and `comp` the load component.
  virtual void after_step(const Solver<2>& s, double t_settle, double dt, int comp) {
    (void)s, (void)t_settle, (void)dt, (void)comp;
  }
  /// Its block of summary.json ("lj_fcc", "polymer").
  virtual void summarize(nlohmann::json& sj) const = 0;
};

using MdRegionFactory = std::function<std::unique_ptr<MdRegion>()>;

/// Registers a kind under `kind` (the input's md.type); returns true (for a static
/// initialiser). A kind registered twice is a programming error (std::logic_error).
bool register_md_region(const std::string& kind, MdRegionFactory make);
/// Whether `kind` is registered.
bool md_region_known(const std::string& kind);
/// The registered kinds, sorted ("lj", "polymer").
std::vector<std::string> md_region_kinds();
/// The registered kinds for an error message: "\"lj\" or \"polymer\"".
std::string md_region_kinds_text();
/// A new region of `kind`; an unknown kind is an input error naming `src`, md.type and the
/// kinds this build knows.
std::unique_ptr<MdRegion> make_md_region(const std::string& kind, const std::string& src);

} // namespace pnc::gimp::escm
