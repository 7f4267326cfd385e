#pragma once
// The run reports of `pnc thermo ti`, `pnc thermo persistence` and `pnc thermo work`
// (`<out>/report.html` and its plain-text twin `<out>/report.md`; docs/formats.md "Run reports"):
// what was run, the verdict in words (decision D270: a difference or stiffness whose error bar
// reaches its value is noise), the key numbers with their standard errors and units, the figures
// plot_thermo.py drew, the warnings and what to do next. Written with pnc::html::Page. Units: free
// energies in kcal/mol (LAMMPS real), moduli in GPa, EI in kcal/mol A and N m^2, lengths in A,
// rates in A/fs; `thermo work`: densities in J/m^3 (SI) and Delta A in kcal/mol.
#include "pnc/thermo/persistence.hpp"
#include "pnc/thermo/ti.hpp"
#include "pnc/thermo/work.hpp"

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

/// Decision D143: a work integral is noise when its errors are known and |value| at the largest
/// strain is within twice its any-correlation bound.
bool work_is_noise(const thermo::WorkIntegral& w);
/// A case resolves nothing asked of it: its total is noise, or with two runs (the split asked
/// for) both its entropic and energetic parts are.
bool work_case_is_noise(const thermo::WorkCase& c, int runs);

/// `pnc thermo work`: per case the free-energy density da = integral of sigma : de at the
/// largest strain (J/m^3) with its standard error (independent points) and its bound (any
/// correlation), Delta A = V0 da (kcal/mol), with two runs the entropic and energetic parts;
/// the verdict of decision D143 (a value within twice its bound is noise). Returns the HTML path.
std::string write_work_report(const ThermoRun& run, const thermo::WorkResult& r);

} // namespace pnc::app
