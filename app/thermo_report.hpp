#pragma once
// The run reports of `pnc thermo ti` and `pnc thermo persistence` (`<out>/report.html` and its
// plain-text twin `<out>/report.md`; docs/formats.md "Run reports"): what was run, the verdict
// in words (decision D270: a difference or stiffness whose error bar reaches its value is
// noise), the key numbers with their standard errors and units, the figures plot_thermo.py
// drew, the warnings and what to do next. Written with pnc::html::Page.
// Units: free energies in kcal/mol (LAMMPS real), moduli in GPa, EI in kcal/mol A and N m^2,
// lengths in A, rates in A/fs.
#include "pnc/thermo/persistence.hpp"
#include "pnc/thermo/ti.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pnc::app {

/// What every thermo report states about the run itself.
struct ThermoRun {
  std::string command_line, out, h5;
  double seconds = 0;             ///< wall time of the command, s
  bool plots = true;              ///< false: --no-plots
  std::vector<std::string> pngs;  ///< the figures drawn (absolute or relative to the cwd)
  std::string plot_warning;       ///< why figures are missing ("" when drawn or not asked)
  std::vector<std::string> notes; ///< further warnings of the command
};

/// Noise level of a value with standard error `se` (D270): 2 = resolved (|v| > 2 se),
/// 1 = weak (se < |v| <= 2 se), 0 = noise (|v| <= se, or not finite).
int resolution(double value, double se);

/// `pnc thermo ti`: Delta A per state (and relative to the reference state) with standard
/// errors, the moduli of the quadratic response fits, the finite-difference check of dH/dl.
/// `worst_fd`: largest relative difference of that check. Returns the HTML path.
std::string write_ti_report(const ThermoRun& run, const thermo::TiSpec& spec,
                            const thermo::TiResult& r, double worst_fd);

/// `pnc thermo persistence`: EI per rate, the zero-rate EI(0) with its 95 % interval, the
/// persistence length xi_p = EI/kT. Returns the HTML path.
std::string write_persistence_report(const ThermoRun& run, const thermo::PersistenceSpec& spec,
                                     const thermo::PersistenceResult& r);

/// The --json object of `pnc thermo ti` (docs/schemas/thermo-ti.schema.json): SI (D238, D280),
/// free energies of the whole simulated box in J (LAMMPS real kcal/mol x 4184 / N_A), volumes
/// in m^3, moduli in Pa, the wall time `run.seconds` in s. `report`: the HTML path.
nlohmann::json ti_json(const ThermoRun& run, const thermo::TiSpec& spec, const thermo::TiResult& r,
                       const std::string& report, double worst_fd);

/// The --json object of `pnc thermo persistence` (docs/schemas/thermo-persistence.schema.json):
/// SI (D238, D280), EI in N m^2, lengths in m, anchor speeds in m/s.
nlohmann::json persistence_json(const ThermoRun& run, const thermo::PersistenceSpec& spec,
                                const thermo::PersistenceResult& r, const std::string& report);

} // namespace pnc::app
