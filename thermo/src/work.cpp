// Free energy of deformation from the stress work (pnc/thermo/work.hpp; decisions D140-D143).
#include "pnc/thermo/work.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/params.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <vector>

namespace pnc::thermo {

namespace fs = std::filesystem;
using damage::PathMatrix;

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool contains(const std::string& s, const char* what) {
  return s.find(what) != std::string::npos;
}

/// deform.temperature (K) of a run's recipe.json. D349: thermo reads the one key it needs of
/// the expanded recipe that `pnc characterize` writes (every key present), not rve's Recipe.
double recipe_temperature(const std::string& rp) {
  const nlohmann::json j = parse_json(read_text_file(rp, "the run's recipe"), rp);
  const nlohmann::json* t = nullptr;
  if (j.is_object() && j.contains("deform") && j.at("deform").is_object() &&
      j.at("deform").contains("temperature"))
    t = &j.at("deform").at("temperature");
  if (!t)
    fail(rp, "deform.temperature", "",
         "is missing: the expanded recipe that pnc characterize writes always gives it (K)");
  if (!t->is_number()) fail(rp, "deform.temperature", t->dump(), "must be a number (K)");
  return t->get<double>();
}
} // namespace

WorkRun read_work_run(const std::string& dir) {
  WorkRun w;
  w.dir = dir;
  const std::string rp = (fs::path(dir) / "recipe.json").string();
  const std::string fp = (fs::path(dir) / "equilibrate" / "final.h5").string();
  const std::string cp = (fs::path(dir) / "cases.h5").string();
  if (!fs::is_regular_file(rp))
    fail(dir, "--from", dir, "is not a `pnc characterize` output (no recipe.json)");
  w.temperature = recipe_temperature(rp);
  if (!(std::isfinite(w.temperature) && w.temperature >= 0))
    fail(rp, "deform.temperature", fmt::format("{}", w.temperature), "must be >= 0 K");
  // a run with replicas ("run": {"replicas": N}, D130) keeps one equilibrated state per replica
  // in replica_<r>/equilibrate/: V0 is then the mean over the replicas
  std::vector<std::string> finals;
  if (fs::is_regular_file(fp)) finals.push_back(fp);
  for (int rep = 1; finals.empty() || rep > 1; ++rep) {
    const std::string f =
        (fs::path(dir) / fmt::format("replica_{}", rep) / "equilibrate" / "final.h5").string();
    if (!fs::is_regular_file(f)) break;
    finals.push_back(f);
    if (rep >= 64) break;
  }
  if (finals.empty())
    fail(fp, "--from", dir,
         "has no equilibrated state (equilibrate/final.h5, or replica_<r>/equilibrate/final.h5): "
         "V0 is its box volume");
  double v_sum = 0;
  for (const std::string& fpath : finals) {
    // decision D141: V0 = mean volume of the final hold (NVT: one volume), the start box of
    // every deformation case
    const h5::File f(fpath, h5::File::Mode::read);
    const h5::RowMatrix t = f.read_matrix("/trace");
    if (t.rows() < 1 || t.cols() < 6)
      fail(fpath, "/trace", fmt::format("{} x {}", t.rows(), t.cols()),
           "must have >= 1 row and 6 columns (T, PE, P, P virial, density, volume A^3)");
    const double v = t.col(5).mean();
    if (!(std::isfinite(v) && v > 0))
      fail(fpath, "/trace[:,5]", fmt::format("{}", v), "the box volume must be finite and > 0 A^3");
    v_sum += v;
  }
  w.volume = v_sum / static_cast<double>(finals.size()) * units::m3_per_angstrom3;
  if (!fs::is_regular_file(cp)) fail(cp, "--from", dir, "has no cases.h5 (run finished?)");
  w.data = damage::read_stress_strain_h5(cp);
  if (w.data.cases.empty()) fail(cp, "/case_<n>", "", "holds no deformation case");
  const std::string& def = w.data.stress_definition;
  w.reference_subtracted = !contains(def, "absolute");
  w.moving_average = contains(def, "moving average") && !contains(def, "no moving average");
  return w;
}

WorkIntegral work_integral(const PathMatrix& strain, const PathMatrix& stress, const PathMatrix& se,
                           const std::string& source, const std::string& field) {
  const Eigen::Index n = strain.rows();
  if (n < 1 || stress.rows() != n)
    fail(source, field, fmt::format("{} strain rows, {} stress rows", n, stress.rows()),
         "strain and stress need the same number (>= 1) of rows");
  const bool has_se = se.rows() == n;
  if (se.rows() != 0 && !has_se)
    fail(source, field + "/stress_stderr", fmt::format("{} rows", se.rows()),
         "must have as many rows as the strain");
  if (!strain.allFinite() || !stress.allFinite() || (has_se && !se.allFinite()))
    fail(source, field, "non-finite", "strain, stress and stress_stderr must be finite");
  // decision D140: start at eps = 0 (prepend the exact origin when the path does not)
  const bool at_origin = strain.row(0).cwiseAbs().maxCoeff() == 0.0;
  const Eigen::Index m = at_origin ? n : n + 1, off = at_origin ? 0 : 1;
  PathMatrix e = PathMatrix::Zero(m, 6), s = PathMatrix::Zero(m, 6), u = PathMatrix::Zero(m, 6);
  e.bottomRows(n) = strain;
  s.bottomRows(n) = stress;
  if (has_se) u.bottomRows(n) = se;
  WorkIntegral w;
  w.has_se = has_se;
  w.value.assign(static_cast<std::size_t>(n), 0.0);
  w.se_indep.assign(static_cast<std::size_t>(n), has_se ? 0.0 : kNaN);
  w.se_bound.assign(static_cast<std::size_t>(n), has_se ? 0.0 : kNaN);
  double acc = 0;
  for (Eigen::Index k = 0; k < m; ++k) {
    if (k > 0) acc += 0.5 * (s.row(k) + s.row(k - 1)).dot(e.row(k) - e.row(k - 1));
    if (k < off) continue;
    const auto out = static_cast<std::size_t>(k - off);
    w.value[out] = acc;
    if (!has_se || k == 0) continue;
    // Delta a(k) = sum_i w_i . sigma_i with w_0 = (e_1 - e_0)/2, w_i = (e_{i+1} - e_{i-1})/2,
    // w_k = (e_k - e_{k-1})/2: a linear combination of the points (decision D143)
    double var = 0, bound = 0;
    for (Eigen::Index i = 0; i <= k; ++i) {
      const Eigen::Index lo = std::max<Eigen::Index>(0, i - 1), hi = std::min(k, i + 1);
      const Eigen::RowVectorXd wi = 0.5 * (e.row(hi) - e.row(lo));
      var += (wi.array().square() * u.row(i).array().square()).sum();
      bound += (wi.array().abs() * u.row(i).array()).sum();
    }
    w.se_indep[out] = std::sqrt(var);
    w.se_bound[out] = bound;
  }
  return w;
}

namespace {

bool softens(const PathMatrix& s, const PathMatrix& se) {
  Eigen::Index comp = 0;
  s.cwiseAbs().colwise().maxCoeff().maxCoeff(&comp);
  const Eigen::VectorXd c = s.col(comp);
  Eigen::Index ip = 0;
  c.cwiseAbs().maxCoeff(&ip);
  const double peak = c(ip), sign = peak < 0 ? -1.0 : 1.0;
  const double sep = se.rows() == s.rows() ? se(ip, comp) : 0.0;
  for (Eigen::Index k = ip + 1; k < c.size(); ++k) {
    const double sek = se.rows() == s.rows() ? se(k, comp) : 0.0;
    const double tol = std::max(3 * std::hypot(sep, sek), 0.05 * std::fabs(peak));
    if (sign * (peak - c(k)) > tol) return true;
  }
  return false;
}

void check_same(const WorkRun& a, const WorkRun& b, const damage::CaseCurve& ca,
                const damage::CaseCurve* cb) {
  const std::string src = b.data.source;
  const std::string field = fmt::format("/case_{}", ca.id);
  if (cb == nullptr)
    fail(
        src, field, "absent",
        fmt::format("the two runs must hold the same cases; {} has case {}", a.data.source, ca.id));
  if (cb->strain.rows() != ca.strain.rows())
    fail(src, field + "/strain", fmt::format("{} rows", cb->strain.rows()),
         fmt::format("must have the same strain points as {} ({} rows)", a.data.source,
                     ca.strain.rows()));
  const double scale = std::max(ca.strain.cwiseAbs().maxCoeff(), 1e-300);
  const double d = (cb->strain - ca.strain).cwiseAbs().maxCoeff();
  if (d > 1e-9 * scale)
    fail(src, field + "/strain", fmt::format("max difference {:.3g}", d),
         fmt::format("must equal the strain of {} (to 1e-9 of its largest strain)", a.data.source));
  if ((ca.stress_stderr.rows() == 0) != (cb->stress_stderr.rows() == 0))
    fail(src, field + "/stress_stderr", cb->stress_stderr.rows() == 0 ? "absent" : "present",
         "both runs need standard errors, or neither");
}

void split(WorkCase& wc, const damage::CaseCurve& c1, const damage::CaseCurve& c2, double t1,
           double t2, const std::string& src) {
  // decision D142: central difference in T at the mean temperature
  const double tm = 0.5 * (t1 + t2), r = tm / (t2 - t1);
  wc.stress = 0.5 * (c1.stress + c2.stress);
  wc.sigma_s = r * (c2.stress - c1.stress);
  wc.sigma_u = wc.stress - wc.sigma_s; // = (1/2 + r) s1 + (1/2 - r) s2
  PathMatrix se_mean(0, 6);
  if (c1.stress_stderr.rows() != 0) {
    const PathMatrix v1 = c1.stress_stderr.array().square().matrix();
    const PathMatrix v2 = c2.stress_stderr.array().square().matrix();
    se_mean = 0.5 * (v1 + v2).array().sqrt().matrix();
    wc.sigma_s_se = (r * r * (v1 + v2)).array().sqrt().matrix();
    wc.sigma_u_se =
        ((0.5 + r) * (0.5 + r) * v1 + (0.5 - r) * (0.5 - r) * v2).array().sqrt().matrix();
  } else {
    wc.sigma_s_se.resize(0, 6);
    wc.sigma_u_se.resize(0, 6);
  }
  const std::string f = fmt::format("/case_{}", c1.id);
  wc.da1 = work_integral(c1.strain, c1.stress, c1.stress_stderr, src, f);
  wc.da2 = work_integral(c2.strain, c2.stress, c2.stress_stderr, src, f);
  wc.da = work_integral(c1.strain, wc.stress, se_mean, src, f);
  wc.da_s = work_integral(c1.strain, wc.sigma_s, wc.sigma_s_se, src, f + " (entropic)");
  wc.da_u = work_integral(c1.strain, wc.sigma_u, wc.sigma_u_se, src, f + " (energetic)");
}

} // namespace

WorkResult stress_work(const WorkRun& a, const WorkRun* b) {
  WorkResult r;
  r.runs = b ? 2 : 1;
  r.t1 = a.temperature;
  r.temperature = a.temperature;
  r.volume = a.volume;
  r.volume1 = a.volume;
  for (const WorkRun* w : {&a, b}) {
    if (w == nullptr) continue;
    if (!w->reference_subtracted)
      fail(w->data.source, "stress_definition", w->data.stress_definition,
           "thermo work needs the stress relative to the zero-strain hold (recipe "
           "analysis.reference = \"subtract\")");
  }
  if (b) {
    r.t2 = b->temperature;
    r.volume2 = b->volume;
    if (!(std::fabs(b->temperature - a.temperature) > 1e-9 * std::max(1.0, a.temperature)))
      fail(b->dir + "/recipe.json", "deform.temperature", fmt::format("{}", b->temperature),
           fmt::format("the two runs need different temperatures (the first is at {} K)",
                       a.temperature));
    if (b->data.cases.size() != a.data.cases.size())
      fail(b->data.source, "/case_<n>", fmt::format("{} cases", b->data.cases.size()),
           fmt::format("the two runs must hold the same cases ({} holds {})", a.data.source,
                       a.data.cases.size()));
    r.temperature = 0.5 * (a.temperature + b->temperature);
    r.volume = 0.5 * (a.volume + b->volume); // decision D142
  }
  for (const auto& c : a.data.cases) {
    WorkCase wc;
    wc.id = c.id;
    wc.strain = c.strain;
    const std::string f = fmt::format("/case_{}", c.id);
    if (b) {
      const damage::CaseCurve* c2 = b->data.find(c.id);
      check_same(a, *b, c, c2);
      split(wc, c, *c2, a.temperature, b->temperature, a.data.source);
      wc.softening = softens(c.stress, c.stress_stderr) || softens(c2->stress, c2->stress_stderr);
    } else {
      wc.stress = c.stress;
      wc.da = work_integral(c.strain, c.stress, c.stress_stderr, a.data.source, f);
      wc.softening = softens(c.stress, c.stress_stderr);
    }
    r.cases.push_back(std::move(wc));
  }
  r.notes.push_back("Delta a = integral of (sigma - sigma_0) : d eps from eps = 0; the work of the "
                    "reference stress, sigma_0 : eps, is not included (cases.h5 holds the "
                    "reference-subtracted stress)");
  r.notes.push_back("a free energy only for an isothermal, quasi-static, reversible deformation; "
                    "beyond yield or with damage the integral is work done, part of it dissipated");
  r.notes.push_back("stderr_indep assumes independent points (replica or block errors); "
                    "stderr_bound holds for any correlation between the points");
  if (a.reference_subtracted || (b && b->reference_subtracted))
    r.notes.push_back("the subtracted sigma_0 is common to all points of a case: its error is "
                      "correlated, so stderr_indep understates it; use stderr_bound");
  if (a.moving_average || (b && b->moving_average))
    r.notes.push_back("the stress was smoothed by a moving average: neighbouring points are "
                      "correlated, stderr_indep understates the error; use stderr_bound");
  if (a.data.cases.front().stress_stderr.rows() == 0)
    r.notes.push_back("cases.h5 has no stress_stderr: the errors are unknown (NaN) and noise is "
                      "not judged");
  if (b)
    r.notes.push_back(fmt::format(
        "two temperatures: sigma and its split refer to T_mean = {} K; sigma_S = T_mean "
        "(sigma(T2) - sigma(T1))/(T2 - T1) (central difference, error O((T2 - T1)^2))",
        r.temperature));
  return r;
}

} // namespace pnc::thermo
