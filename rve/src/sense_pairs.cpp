// A shear and its negative sense side by side (sense_pairs.hpp, decision D428).
#include "pnc/rve/sense_pairs.hpp"

#include "pnc/damage/cases.hpp"
#include "pnc/damage/fit.hpp"
#include "pnc/md/statistics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pnc::rve {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const char* const kPlane[6] = {"", "", "", "2-3", "1-3", "1-2"};

/// The run's case that shears the plane of `pos` the other way, if any.
const CombinedCase* negative_of(const CombinedCases& c, const damage::DeformationCase& pos) {
  for (const auto& row : damage::deformation_cases())
    if (row.gradient == -pos.gradient && damage::driven_sense(row) < 0) return c.find(row.id);
  return nullptr;
}

/// Rows 0..n-1 of both cases at the same load, n the fitted rows of the positive case; 0 when
/// the two were not run to the same loads.
Eigen::Index common_rows(const CombinedCase& p, const CombinedCase& n, double strain_max,
                         double stretch_max) {
  const Eigen::Index rows = damage::rows_in_fit_range(p.strain, strain_max, stretch_max);
  if (rows < 1 || n.strain.rows() < rows) return 0;
  for (Eigen::Index k = 0; k < rows; ++k) {
    const double a = p.strain(k, p.voigt), b = -n.strain(k, n.voigt);
    if (std::fabs(a - b) > 1e-12 * std::max(std::fabs(a), std::fabs(b))) return 0;
  }
  return rows;
}

SensePair compare(const CombinedCase& p, const CombinedCase& n, Eigen::Index rows, int replicas) {
  SensePair s;
  s.positive_id = p.id;
  s.negative_id = n.id;
  s.voigt = p.voigt;
  s.replicas = replicas;
  const int v = p.voigt;
  const std::size_t nrep = std::min(p.replica_stress.size(), n.replica_stress.size());
  std::vector<double> per_replica(nrep, 0.0), d(nrep);
  for (Eigen::Index k = 0; k < rows; ++k) {
    s.t.push_back(p.strain(k, v));
    s.positive.push_back(p.stress(k, v));
    s.positive_se.push_back(p.stress_stderr(k, v));
    s.negative.push_back(-n.stress(k, v));
    s.negative_se.push_back(n.stress_stderr(k, v));
    for (std::size_t r = 0; r < nrep; ++r) {
      d[r] = p.replica_stress[r](k, v) + n.replica_stress[r](k, v); // + (-(-sigma))
      per_replica[r] += d[r] / static_cast<double>(rows);
    }
    const md::ReplicaEstimate e = md::replica_mean_se(d);
    s.difference.push_back(e.mean);
    s.difference_se.push_back(nrep >= 2 ? e.se : kNaN);
  }
  const md::ReplicaEstimate m = md::replica_mean_se(per_replica);
  s.mean_difference = m.mean;
  s.mean_difference_se = nrep >= 2 ? m.se : kNaN;
  if (nrep < 2)
    s.p = kNaN;
  else if (m.se > 0)
    s.p = 2 * (1 - md::student_t_cdf(std::fabs(m.mean / m.se), static_cast<int>(nrep) - 1));
  else // no scatter between replicas: resolved exactly, unless there is nothing to resolve
    s.p = m.mean == 0 ? 1.0 : 0.0;
  s.scale = std::max(std::fabs(s.positive.back()), std::fabs(s.negative.back()));
  return s;
}

std::string pct(double x, double scale) {
  return std::isfinite(x) && scale > 0 ? fmt::format("{:.1f} %", 100 * x / scale) : "–";
}

std::string mpa(double x, double se) {
  return std::isfinite(se) ? fmt::format("{:+.2f} ± {:.2f}", x * 1e-6, se * 1e-6)
                           : fmt::format("{:+.2f}", x * 1e-6);
}

} // namespace

std::vector<SensePair> sense_pairs(const CombinedCases& c, double strain_max, double stretch_max) {
  std::vector<SensePair> out;
  for (const auto& p : c.cases) {
    const damage::DeformationCase& row = damage::deformation_case(p.id);
    if (row.driven.size() != 1 || row.driven[0] < 3 || damage::driven_sense(row) < 0) continue;
    const CombinedCase* n = negative_of(c, row);
    if (!n) continue;
    const Eigen::Index rows = common_rows(p, *n, strain_max, stretch_max);
    if (rows > 0) out.push_back(compare(p, *n, rows, c.replicas));
  }
  return out;
}

nlohmann::json sense_pairs_json(const std::vector<SensePair>& pairs) {
  const auto value = [](double x) {
    return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
  };
  nlohmann::json a = nlohmann::json::array();
  for (const auto& s : pairs) {
    const std::size_t last = s.t.size() - 1;
    a.push_back({{"cases", {s.positive_id, s.negative_id}},
                 {"shear", kPlane[s.voigt]},
                 {"replicas", s.replicas},
                 {"rows", s.t.size()},
                 {"mean_difference_Pa", value(s.mean_difference)},
                 {"mean_difference_stderr_Pa", value(s.mean_difference_se)},
                 {"p", value(s.p)},
                 {"last_load", s.t[last]},
                 {"last_difference_Pa", value(s.difference[last])},
                 {"last_difference_stderr_Pa", value(s.difference_se[last])},
                 {"stress_scale_Pa", value(s.scale)}});
  }
  return a;
}

std::string sense_pairs_markdown(const std::vector<SensePair>& pairs) {
  if (pairs.empty()) return "";
  std::string md =
      "\n## Both senses of each shear (D428)\n\n"
      "The same replicas sheared both ways, read along each case (the stress of the negative "
      "sense with its sign turned). Differences are paired by replica (positive minus negative "
      "sense): over the fitted rows, each replica's mean difference is one sample; at the last "
      "row, the difference there. The law is odd along a shear (docs/theory.md §2.1) and fits "
      "the two senses' mean; a difference the replicas resolve is a preference of the material "
      "for one sense, which the fit cannot follow.\n\n"
      "| shear | cases | replicas | mean over the rows (MPa) | share of the stress | at the last "
      "row, γ = … (MPa) | share | p (t, N − 1 dof) |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& s : pairs) {
    const std::size_t last = s.t.size() - 1;
    md += fmt::format("| {} | {}, {} | {} | {} | {} | γ = {:.3g}: {} | {} | {} |\n",
                      kPlane[s.voigt], s.positive_id, s.negative_id, s.replicas,
                      mpa(s.mean_difference, s.mean_difference_se), pct(s.mean_difference, s.scale),
                      s.t[last], mpa(s.difference[last], s.difference_se[last]),
                      pct(s.difference[last], s.scale),
                      std::isfinite(s.p) ? fmt::format("{:.2g}", s.p) : std::string("–"));
  }
  if (pairs.front().replicas < 2)
    md += "\nOne replica: no between-replica error, so the difference is shown and not judged "
          "(one structure's two senses differ by chance as two replicas do).\n";
  return md + "\n";
}

std::string sense_pairs_summary(const std::vector<SensePair>& pairs) {
  std::string out;
  for (const auto& s : pairs) {
    const bool judged = std::isfinite(s.p);
    out += fmt::format("pnc characterize: shear {} both ways (cases {}, {}; {} replica{}): "
                       "positive minus negative sense {} MPa over the fitted rows ({} of the "
                       "stress){}\n",
                       kPlane[s.voigt], s.positive_id, s.negative_id, s.replicas,
                       s.replicas == 1 ? "" : "s", mpa(s.mean_difference, s.mean_difference_se),
                       pct(s.mean_difference, s.scale),
                       judged ? fmt::format(", p = {:.2g}", s.p) : std::string(", not judged"));
  }
  return out;
}

} // namespace pnc::rve
