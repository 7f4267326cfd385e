#pragma once
// pnc/rve/replica_fits.hpp: the NDM fitted to every replica on its own, and the
// between-replica standard error of every fitted constant (decision D130).
//
// Units: constants in Pa (alpha dimensionless), as damage::fit_ndm returns them.
//
// The joint fit of the replica-mean curves treats its points as independent; the deviations
// of one replica are correlated along its curves, so that fit's standard errors can be too
// small. Fitting each replica separately and taking sd/sqrt(N) of each constant (Student-t
// factor for the nominal 68 % interval) counts those correlations.
#include "pnc/damage/fit.hpp"
#include "pnc/rve/replicas.hpp"

#include <string>
#include <vector>

namespace pnc::rve {

struct ReplicaFits {
  std::vector<std::string> names;          ///< constant names (damage::constant_names)
  std::vector<std::vector<double>> values; ///< [replica][constant]; NaN when that fit failed
  std::vector<int> fitted_in;              ///< per constant: in how many replica fits it was fitted
  std::vector<double> mean, se;            ///< per constant over the replicas whose fit worked
  std::vector<std::string> failures;       ///< "replica r: message" for fits that threw
  double coverage_factor = 1;              ///< Student t, N - 1 degrees of freedom
  int replicas = 0;
};

/// Fits every replica's fit rows (CombinedCase::replica_stress / replica_stderr) with
/// `options`; needs >= 2 replicas (else an empty result). A replica whose fit throws an
/// InputError is left out and named in `failures`.
ReplicaFits fit_replicas(const CombinedCases& c, const damage::FitOptions& options);

/// The "larger of" rule of the card's error bars (D130, D431): every std_error[i] below a finite
/// floor[i] (or not a number itself) is raised to floor[i]; none is lowered; a NaN floor (a
/// constant not fitted) leaves std_error[i] alone. Marks raised[i] when `raised` is given (sized
/// to std_error). Returns how many were raised.
int raise_errors(std::vector<double>& std_error, const std::vector<double>& floor,
                 std::vector<bool>* raised = nullptr);

/// Markdown table: constant, joint-fit value and its own standard error, between-replica mean
/// and standard error, 68 % interval.
std::string replica_fits_markdown(const ReplicaFits& f, const damage::FitReport& joint);

/// The replicas' own fits as CSV (the run's `replica_fits.csv`, docs/formats.md): a header
/// `replica,<constant>_<unit>...` (constants in Pa as `C11_Pa`, alpha as `alpha_1`), then one
/// row per replica (1-based) with every constant to 17 significant digits, empty where that
/// replica's fit failed. Empty string with fewer than 2 replicas.
std::string replica_fits_csv(const ReplicaFits& f);

} // namespace pnc::rve
