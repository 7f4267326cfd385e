// Replicas and the honest combination of their case curves (replicas.hpp, D130-D134).
#include "pnc/rve/replicas.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/damage/cases.hpp"
#include "pnc/damage/data.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace pnc::rve {

namespace fs = std::filesystem;

namespace {
std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
constexpr std::uint64_t kSeedRange = 800000000; // LAMMPS seeds < 900000000, + row offsets
/// From this many replicas on, every point's own between-replica variance is its error (D130)
constexpr int kPointVarianceReplicas = 8;
} // namespace

std::uint64_t replica_build_seed(std::uint64_t seed, int replica) {
  if (replica <= 1) return seed;
  return 1 + splitmix64(splitmix64(seed) ^ static_cast<std::uint64_t>(replica)) % kSeedRange;
}

std::uint64_t replica_case_seed(std::uint64_t seed, int replica, int case_id) {
  if (replica <= 1) return seed * 100 + static_cast<std::uint64_t>(case_id);
  return 1 + splitmix64(splitmix64(replica_build_seed(seed, replica)) +
                        static_cast<std::uint64_t>(case_id)) %
                 kSeedRange;
}

std::string replica_dir(const std::string& dir, int replicas, int replica) {
  if (replicas <= 1) return dir;
  return (fs::path(dir) / fmt::format("replica_{}", replica)).string();
}

namespace {

const PathM& chosen(const Recipe& r, const CaseResult& c, bool se) {
  if (r.stress == "virial") return se ? c.stress_virial_se : c.stress_virial;
  return se ? c.stress_total_se : c.stress_total;
}
const PathM& chosen_inflated(const Recipe& r, const CaseResult& c) {
  return r.stress == "virial" ? c.stress_virial_inflated : c.stress_total_inflated;
}

/// Rows of the linear-range slope: strain <= half the largest |strain| of the driven column.
std::vector<Eigen::Index> slope_rows(const PathM& strain, int voigt) {
  const double tmax = strain.col(voigt).cwiseAbs().maxCoeff();
  std::vector<Eigen::Index> rows;
  for (Eigen::Index k = 0; k < strain.rows(); ++k)
    if (strain(k, voigt) != 0 && std::fabs(strain(k, voigt)) <= 0.5 * tmax + 1e-15)
      rows.push_back(k);
  if (rows.size() < 2) {
    rows.clear();
    for (Eigen::Index k = 0; k < strain.rows(); ++k)
      if (strain(k, voigt) != 0) rows.push_back(k);
  }
  return rows;
}

md::SlopeFit slope_of(const PathM& strain, const PathM& stress, const PathM* se, double se_common,
                      int voigt) {
  const auto rows = slope_rows(strain, voigt);
  const auto n = static_cast<Eigen::Index>(rows.size());
  // static rows (0 K, D120) have no errors (NaN): the slope then takes the residual scatter
  bool with_se = se != nullptr;
  for (Eigen::Index i = 0; with_se && i < n; ++i)
    with_se = std::isfinite((*se)(rows[i], voigt));
  Eigen::VectorXd t(n), y(n), s(with_se ? n : 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    t[i] = strain(rows[i], voigt);
    y[i] = stress(rows[i], voigt);
    if (with_se) s[i] = std::max((*se)(rows[i], voigt), 1e-300);
  }
  return md::slope_through_origin(t, y, s, std::isfinite(se_common) ? se_common : 0.0);
}

/// stress_definition of cases.h5: the stress, reference, smoothing and error model in words.
std::string describe(const Recipe& r, const CombinedCases& out, std::size_t ncases) {
  const bool subtract = r.reference == "subtract";
  const int nrep = out.replicas;
  // the words "virial only" / "zero-strain hold" are what readers (and tests) look for
  std::string def = r.stress == "virial" ? "virial only, no kinetic term (docs/theory.md §3.5, "
                                           "Zhou 2003; the dissertation's choice: "
                                           "normal constants biased by -rho k_B T, D134)"
                                         : "virial + kinetic term (total stress, D134)";
  def += subtract ? fmt::format("; relative to the zero-strain hold (sigma - sigma_0, sigma_0 "
                                "the mean of the {} x hold zero-strain holds of all {} case(s) "
                                "of a replica; its error is common to every point, D131)",
                                r.deform.reference_holds, ncases)
                  : std::string("; absolute, zero-strain row included");
  def += r.moving_average > 1
             ? fmt::format("; no moving average in the fit data (the {}-point moving average is "
                           "stored for display only, D133)",
                           r.moving_average)
             : std::string("; no moving average");
  def += nrep >= 2
             ? fmt::format("; errors: between-replica standard error sd/sqrt(N) over N = {} "
                           "independent replicas (own structure and equilibration each, D130)",
                           nrep)
             : fmt::format("; errors: block standard errors of one structure (thermal noise "
                           "only), checked against the autocorrelation time: {} of {} holds "
                           "inflated (D132)",
                           out.holds_inflated, out.holds_checked);
  return "MD by pnc rve (LAMMPS): " + def;
}

} // namespace

const CombinedCase* CombinedCases::find(int id) const {
  for (const auto& cc : cases)
    if (cc.id == id) return &cc;
  return nullptr;
}

void replica_mean_curve(const CombinedCase& cc, const std::vector<int>& pick, PathM& mean,
                        PathM& stderr_out) {
  const auto nrep = static_cast<int>(pick.size());
  const Eigen::Index n = cc.strain.rows();
  mean.resize(n, 6);
  stderr_out.resize(n, 6);
  PathM var(n, 6);
  std::vector<double> v(pick.size());
  for (Eigen::Index k = 0; k < n; ++k)
    for (int j = 0; j < 6; ++j) {
      for (std::size_t i = 0; i < pick.size(); ++i)
        v[i] = cc.replica_stress[static_cast<std::size_t>(pick[i])](k, j);
      const md::ReplicaEstimate e = md::replica_mean_se(v);
      mean(k, j) = e.mean;
      var(k, j) = e.sd * e.sd;
    }
  // a point's variance from N < kPointVarianceReplicas replicas has few degrees of freedom
  // (N = 2: one) and can be near zero by chance, an infinite fit weight: it is not used
  // below the variance pooled over the rows of the curve (per component), D130
  const Eigen::RowVectorXd pooled = var.colwise().mean();
  for (Eigen::Index k = 0; k < n; ++k)
    for (int j = 0; j < 6; ++j) {
      const double vk = nrep < kPointVarianceReplicas ? std::max(var(k, j), pooled[j]) : var(k, j);
      stderr_out(k, j) = std::sqrt(vk / nrep);
    }
}

CombinedCases combine_cases(const Recipe& r, const std::vector<std::vector<CaseResult>>& results) {
  CombinedCases out;
  out.replicas = static_cast<int>(results.size());
  if (results.empty() || results[0].empty())
    fail("<cases>", "replicas", "0", "no case results to combine");
  const bool subtract = r.reference == "subtract";
  const auto ncases = results[0].size();
  // decision D131: the reference of a replica is the mean of the zero-strain holds of all its
  // cases (the same equilibrated state, independent thermal trajectories)
  for (const auto& rep : results) {
    if (rep.size() != ncases) fail("<cases>", "replicas", "", "replicas differ in their cases");
    Eigen::RowVectorXd ref = Eigen::RowVectorXd::Zero(6), var = Eigen::RowVectorXd::Zero(6);
    for (const auto& c : rep) {
      if (c.rows_done < 2)
        fail("<cases>", fmt::format("case_{}", c.case_id), "", "has no strain step");
      ref += chosen(r, c, false).row(0);
      var += chosen(r, c, true).row(0).array().square().matrix();
    }
    const double m = static_cast<double>(ncases);
    out.reference.push_back(ref / m);
    out.reference_se.push_back(var.array().sqrt().matrix() / m);
  }
  const int nrep = out.replicas;
  for (std::size_t ci = 0; ci < ncases; ++ci) {
    CombinedCase cc;
    cc.id = results[0][ci].case_id;
    cc.voigt = damage::single_driven(damage::deformation_case(cc.id), "the replica slopes"); // D360
    const Eigen::Index first = subtract ? 1 : 0;
    const Eigen::Index n = results[0][ci].rows_done - first;
    for (int rep = 0; rep < nrep; ++rep) {
      const CaseResult& c = results[rep][ci];
      if (c.case_id != cc.id || c.rows_done - first != n)
        fail("<cases>", fmt::format("replica_{}/case_{}", rep + 1, cc.id), "",
             "replicas differ in their cases or strain steps");
      PathM s = chosen(r, c, false).middleRows(first, n);
      PathM se = chosen(r, c, true).middleRows(first, n);
      if (subtract) {
        const Eigen::RowVectorXd ref = out.reference[rep], rse = out.reference_se[rep];
        for (Eigen::Index k = 0; k < n; ++k) {
          s.row(k) -= ref;
          se.row(k) = (se.row(k).array().square() + rse.array().square()).sqrt().matrix();
        }
      }
      if (rep == 0)
        cc.strain = c.strain.middleRows(first, n);
      else if (!(c.strain.middleRows(first, n) - cc.strain).isZero(1e-12))
        fail("<cases>", fmt::format("replica_{}/case_{}", rep + 1, cc.id), "",
             "replicas differ in their strains");
      cc.replica_stress.push_back(s);
      cc.replica_stderr.push_back(se);
      const PathM& infl = chosen_inflated(r, c);
      for (Eigen::Index k = 0; k < infl.rows(); ++k)
        if (std::isfinite(infl(k, cc.voigt))) {
          ++out.holds_checked;
          if (infl(k, cc.voigt) > 0.5) ++out.holds_inflated;
        }
    }
    if (nrep == 1) {
      cc.stress = cc.replica_stress[0];
      cc.stress_stderr = cc.replica_stderr[0];
      cc.reference_stderr = subtract ? out.reference_se[0] : Eigen::RowVectorXd::Zero(6);
      if (subtract) {
        // decision D131: independent part per point, the reference error common to all
        PathM indep = chosen(r, results[0][ci], true).middleRows(first, n);
        const md::SlopeFit f =
            slope_of(cc.strain, cc.stress, &indep, out.reference_se[0][cc.voigt], cc.voigt);
        cc.slope = f.slope;
        cc.slope_se = f.se;
      }
    } else {
      // decision D130: between-replica mean and standard error sd / sqrt(N)
      std::vector<int> all(static_cast<std::size_t>(nrep));
      for (int rep = 0; rep < nrep; ++rep)
        all[static_cast<std::size_t>(rep)] = rep;
      replica_mean_curve(cc, all, cc.stress, cc.stress_stderr);
      cc.reference_stderr = Eigen::RowVectorXd::Zero(6);
      if (subtract)
        for (int j = 0; j < 6; ++j) {
          std::vector<double> v;
          for (int rep = 0; rep < nrep; ++rep)
            v.push_back(out.reference[rep][j]);
          cc.reference_stderr[j] = md::replica_mean_se(v).se;
        }
      if (subtract) {
        for (int rep = 0; rep < nrep; ++rep)
          cc.replica_slopes.push_back(
              slope_of(cc.strain, cc.replica_stress[rep], nullptr, 0.0, cc.voigt).slope);
        const md::ReplicaEstimate e = md::replica_mean_se(cc.replica_slopes);
        cc.slope = e.mean;
        cc.slope_se = e.se;
        cc.slope_coverage_factor = md::coverage_factor(nrep - 1);
      }
    }
    if (!subtract) cc.slope = cc.slope_se = std::nan("");
    // decision D133: smoothing for display only; the fit rows and their errors are untouched
    if (r.moving_average > 1)
      cc.display_moving_average = moving_average(cc.stress, r.moving_average);
    out.cases.push_back(std::move(cc));
  }
  std::sort(out.cases.begin(), out.cases.end(),
            [](const auto& a, const auto& b) { return a.id < b.id; });
  out.error_method = nrep >= 2 ? "replicas" : "blocks";
  out.stress_definition = describe(r, out, ncases);
  if (r.deform.temperature == 0) {
    out.stress_definition += std::string("; static deformation at 0 K (run 0 after the affine "
                                         "remap") +
                             (r.deform.minimize ? " and an energy minimisation at fixed box" : "") +
                             "), no standard errors (decision D120)";
    out.error_method = "none (static rows, D120)";
  }
  return out;
}

void write_combined_cases_h5(const std::string& path, const Recipe& r, const CombinedCases& c,
                             const std::vector<std::vector<CaseResult>>& results) {
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    // every matrix here has the six Voigt columns (D236: files name their components)
    const auto columns = [&f](const std::string& ds) {
      f.set_attr(ds, "columns",
                 ds.find("strain") != std::string::npos ? damage::kStrainColumns
                                                        : damage::kStressColumns);
    };
    f.set_attr("/", "stress_definition", c.stress_definition);
    f.set_attr("/", "format",
               "pnc cases v2: /case_<n>/{strain,stress,stress_stderr,reference_stderr}, "
               "/replicas/replica_<r>/... (docs/formats.md)");
    f.set_attr("/", "error_method", c.error_method);
    f.set_attr("/", "replicas", c.replicas);
    f.set_attr("/", "stress_choice", r.stress);
    f.set_attr("/", "reference", r.reference);
    f.set_attr("/", "reference_holds", r.deform.reference_holds);
    f.set_attr("/", "holds_checked", c.holds_checked);
    f.set_attr("/", "holds_inflated", c.holds_inflated);
    for (const auto& cc : c.cases) {
      const std::string g = "/case_" + std::to_string(cc.id);
      f.write_matrix(g + "/strain", cc.strain);
      columns(g + "/strain");
      f.set_attr(g + "/strain", "units", "1 (engineering shear)");
      f.write_matrix(g + "/stress", cc.stress);
      columns(g + "/stress");
      f.set_attr(g + "/stress", "units", "Pa");
      // static rows (0 K, decision D120) have no standard errors: none are written, the fit
      // takes its no-data-errors path (a NaN or zero error is never a weight)
      if (r.deform.temperature != 0) {
        f.write_matrix(g + "/stress_stderr", cc.stress_stderr);
        columns(g + "/stress_stderr");
        f.set_attr(g + "/stress_stderr", "units", "Pa");
        f.set_attr(g + "/stress_stderr", "method", c.error_method);
        f.write_matrix(g + "/reference_stderr", h5::RowMatrix(cc.reference_stderr));
        columns(g + "/reference_stderr");
        f.set_attr(g + "/reference_stderr", "units", "Pa");
        f.set_attr(g + "/reference_stderr", "meaning",
                   "part of stress_stderr common to every point of the curve (the subtracted "
                   "reference): a correlation, not independent noise (D131)");
      }
      if (cc.display_moving_average.rows() > 0) {
        f.write_matrix(g + "/stress_moving_average_display", cc.display_moving_average);
        columns(g + "/stress_moving_average_display");
        f.set_attr(g + "/stress_moving_average_display", "units", "Pa");
        f.set_attr(g + "/stress_moving_average_display", "meaning",
                   "display only: never fitted, no error of its own (D133)");
      }
      f.write_scalar(g + "/linear_slope", cc.slope);
      f.set_attr(g + "/linear_slope", "units", "Pa (driven component, strain <= strain_max/2)");
      f.write_scalar(g + "/linear_slope_stderr", cc.slope_se);
      f.set_attr(g + "/linear_slope_stderr", "units", "Pa");
      f.set_attr(g + "/linear_slope_stderr", "method", c.error_method);
      f.write_scalar(g + "/linear_slope_coverage_factor", cc.slope_coverage_factor);
      f.set_attr(g + "/linear_slope_coverage_factor", "meaning",
                 "slope +- factor * stderr is the nominal 68.27 % interval (Student t)");
    }
    for (std::size_t rep = 0; rep < results.size(); ++rep) {
      const std::string rg = fmt::format("/replicas/replica_{}", rep + 1);
      f.write_matrix(rg + "/reference_stress", h5::RowMatrix(c.reference[rep]));
      columns(rg + "/reference_stress");
      f.set_attr(rg + "/reference_stress", "units", "Pa");
      f.write_matrix(rg + "/reference_stderr", h5::RowMatrix(c.reference_se[rep]));
      columns(rg + "/reference_stderr");
      f.set_attr(rg + "/reference_stderr", "units", "Pa");
      for (std::size_t ci = 0; ci < results[rep].size(); ++ci) {
        const CaseResult& cr = results[rep][ci];
        const std::string g = rg + "/case_" + std::to_string(cr.case_id);
        const std::pair<const char*, const PathM*> raw[] = {
            {"/raw_strain", &cr.strain},
            {"/raw_stress_total", &cr.stress_total},
            {"/raw_stress_total_stderr", &cr.stress_total_se},
            {"/raw_stress_virial", &cr.stress_virial},
            {"/raw_stress_virial_stderr", &cr.stress_virial_se},
            {"/raw_stress_total_tau", &cr.stress_total_tau_fs},
            {"/raw_stress_virial_tau", &cr.stress_virial_tau_fs}};
        for (const auto& [name, m] : raw) {
          f.write_matrix(g + name, *m);
          columns(g + name);
          f.set_attr(g + name, "units",
                     std::string(name).find("tau") != std::string::npos
                         ? "fs"
                         : (std::string(name) == "/raw_strain" ? "1" : "Pa"));
        }
        for (const auto& cc : c.cases)
          if (cc.id == cr.case_id) {
            f.write_matrix(g + "/stress", cc.replica_stress[rep]);
            columns(g + "/stress");
            f.set_attr(g + "/stress", "units", "Pa (fit rows of this replica, stress_choice)");
            f.write_matrix(g + "/stress_stderr", cc.replica_stderr[rep]);
            columns(g + "/stress_stderr");
            f.set_attr(g + "/stress_stderr", "units", "Pa (blocks, D132)");
          }
      }
    }
  }
  out.commit();
}

std::string statistics_markdown(const CombinedCases& c) {
  std::string s = "## Statistics\n\n";
  if (c.error_method == "replicas")
    s += fmt::format("Error bars: between-replica standard errors over {} independent replicas "
                     "(own structure and equilibration each; decision D130).\n\n",
                     c.replicas);
  else
    s += fmt::format("Error bars: block standard errors of ONE structure (thermal noise only: "
                     "the structure-to-structure scatter of a glass is not measured; use "
                     "`\"run\": {{\"replicas\": N}}`, D130). Autocorrelation check: {} of {} "
                     "holds had blocks shorter than 5 statistical inefficiencies, their errors "
                     "were inflated (D132).\n\n",
                     c.holds_inflated, c.holds_checked);
  s += "| case | linear-range slope | standard error | 68 % interval |\n|---|---|---|---|\n";
  for (const auto& cc : c.cases)
    s += std::isfinite(cc.slope)
             ? fmt::format("| {} | {:.4f} GPa | {:.4f} GPa | +- {:.4f} GPa |\n", cc.id,
                           cc.slope * 1e-9, cc.slope_se * 1e-9,
                           cc.slope_coverage_factor * cc.slope_se * 1e-9)
             : fmt::format("| {} | not computed (needs analysis.reference = \"subtract\") | | |\n",
                           cc.id);
  s += "\nSlope of the driven component through the origin over strain <= strain_max/2, with "
       "the reference stress's error counted once for the whole curve (D131); a check on the "
       "fitted constants, whose own standard errors treat the points as independent.\n\n";
  return s;
}

nlohmann::json statistics_json(const CombinedCases& c) {
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  nlohmann::json j = {{"error_method", c.error_method},
                      {"replicas", c.replicas},
                      {"holds_checked", c.holds_checked},
                      {"holds_inflated", c.holds_inflated}};
  j["cases"] = nlohmann::json::array();
  for (const auto& cc : c.cases) {
    nlohmann::json rs = nlohmann::json::array();
    for (double v : cc.replica_slopes)
      rs.push_back(num(v));
    j["cases"].push_back({{"case", cc.id},
                          {"linear_slope_Pa", num(cc.slope)},
                          {"linear_slope_stderr_Pa", num(cc.slope_se)},
                          {"coverage_factor_68", num(cc.slope_coverage_factor)},
                          {"replica_slopes_Pa", rs}});
  }
  return j;
}

} // namespace pnc::rve
