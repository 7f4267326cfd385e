// Per-replica NDM fits and the between-replica error of every constant (replica_fits.hpp).
#include "pnc/rve/replica_fits.hpp"

#include "pnc/core/error.hpp"

#include <fmt/format.h>

#include <cmath>

namespace pnc::rve {

ReplicaFits fit_replicas(const CombinedCases& c, const damage::FitOptions& options) {
  ReplicaFits out;
  out.replicas = c.replicas;
  if (c.replicas < 2 || c.cases.empty()) return out;
  out.names = damage::constant_names(options.model);
  const std::size_t nk = out.names.size();
  out.fitted_in.assign(nk, 0);
  for (int rep = 0; rep < c.replicas; ++rep) {
    damage::StressStrainData d;
    d.source = fmt::format("replica {}", rep + 1);
    d.stress_definition = c.stress_definition;
    for (const auto& cc : c.cases) {
      damage::CaseCurve cv;
      cv.id = cc.id;
      cv.strain = cc.strain;
      cv.stress = cc.replica_stress[static_cast<std::size_t>(rep)];
      cv.stress_stderr = cc.replica_stderr[static_cast<std::size_t>(rep)];
      d.cases.push_back(cv);
    }
    std::vector<double> v(nk, std::nan(""));
    try {
      const damage::FitReport f = damage::fit_ndm(d, options);
      for (std::size_t i = 0; i < nk; ++i) {
        v[i] = f.params.k[i];
        if (i < f.fitted.size() && f.fitted[i]) ++out.fitted_in[i];
      }
    } catch (const InputError& e) {
      out.failures.push_back(fmt::format("replica {}: {}", rep + 1, e.what()));
    }
    out.values.push_back(v);
  }
  for (std::size_t i = 0; i < nk; ++i) {
    std::vector<double> x;
    for (const auto& v : out.values)
      if (std::isfinite(v[i])) x.push_back(v[i]);
    const md::ReplicaEstimate e = md::replica_mean_se(x);
    out.mean.push_back(e.mean);
    out.se.push_back(e.se);
  }
  int worked = 0;
  for (const auto& v : out.values)
    worked += std::isfinite(v[0]) ? 1 : 0;
  out.coverage_factor = worked >= 2 ? md::coverage_factor(worked - 1) : std::nan("");
  return out;
}

std::string replica_fits_markdown(const ReplicaFits& f, const damage::FitReport& joint) {
  if (f.replicas < 2 || f.names.empty()) return "";
  std::string s = fmt::format(
      "### Between-replica errors of the fitted constants\n\nThe NDM fitted to each of the {} "
      "replicas on its own; sd/sqrt(N) of each constant counts the correlations along a "
      "replica's curves that the joint fit's own standard errors ignore (D130). Compare the two "
      "error columns; trust the larger.\n\n| constant | joint fit | its standard error | "
      "replica mean | between-replica s.e. | 68 % interval | fitted in |\n"
      "|---|---|---|---|---|---|---|\n",
      f.replicas);
  for (std::size_t i = 0; i < f.names.size(); ++i) {
    const bool alpha = f.names[i] == "alpha";
    const double u = alpha ? 1.0 : 1e-9;
    const char* unit = alpha ? "" : " GPa";
    const double jse = i < joint.std_error.size() ? joint.std_error[i] : std::nan("");
    const auto g = [&](double v, const char* fmt3) {
      return std::isfinite(v) ? fmt::format(fmt::runtime(fmt3), v * u) + unit : std::string("-");
    };
    if (f.fitted_in[i] == 0) {
      s += fmt::format("| {} | {} | - | held in every replica | - | - | 0/{} |\n", f.names[i],
                       g(joint.params.k[i], "{:.4g}"), f.replicas);
      continue;
    }
    s += fmt::format("| {} | {} | {} | {} | {} | +- {} | {}/{} |\n", f.names[i],
                     g(joint.params.k[i], "{:.4g}"), g(jse, "{:.3g}"), g(f.mean[i], "{:.4g}"),
                     g(f.se[i], "{:.3g}"), g(f.coverage_factor * f.se[i], "{:.3g}"), f.fitted_in[i],
                     f.replicas);
  }
  for (const auto& m : f.failures)
    s += "\n- fit failed: " + m;
  return s + "\n";
}

int raise_errors(std::vector<double>& std_error, const std::vector<double>& floor,
                 std::vector<bool>* raised) {
  int n = 0;
  for (std::size_t i = 0; i < std_error.size() && i < floor.size(); ++i) {
    if (!std::isfinite(floor[i]) || floor[i] <= std_error[i]) continue;
    std_error[i] = floor[i];
    if (raised != nullptr && i < raised->size()) (*raised)[i] = true;
    ++n;
  }
  return n;
}

std::string replica_fits_csv(const ReplicaFits& f) {
  if (f.replicas < 2 || f.names.empty()) return "";
  std::string s = "replica";
  for (const auto& n : f.names)
    s += "," + n + "_" + damage::constant_unit(n);
  s += "\n";
  for (std::size_t r = 0; r < f.values.size(); ++r) {
    s += std::to_string(r + 1);
    for (const double v : f.values[r])
      s += std::isfinite(v) ? fmt::format(",{:.17g}", v) : std::string(",");
    s += "\n";
  }
  return s;
}

} // namespace pnc::rve
