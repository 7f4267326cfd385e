// Thermodynamic integration engine and the polymer free energy of deformation (units real).
#include "pnc/thermo/ti.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"
#include "pnc/rve/lammps_path.hpp"
#include "pnc/rve/runner.hpp"
#include "pnc/rve/stage_stop.hpp"

#include <lammps/library.h>

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>

namespace pnc::thermo {

namespace fs = std::filesystem;

void LjPath::validate(const std::string& source) const {
  auto pos = [&](const char* f, double v) {
    if (!(v > 0) || !std::isfinite(v)) fail(source, f, fmt::format("{}", v), "must be > 0");
  };
  pos("eps0", eps0);
  pos("eps1", eps1);
  pos("sig0", sig0);
  pos("sig1", sig1);
  pos("cutoff", cutoff);
  if (cutoff < std::max(sig0, sig1))
    fail(source, "cutoff", fmt::format("{}", cutoff), "must be >= max(sig0, sig1)");
}

double lj_energy(double r, double eps, double sig) {
  const double s6 = std::pow(sig / r, 6);
  return 4 * eps * (s6 * s6 - s6);
}

double lj_dudl(double r, double l, const LjPath& p) {
  const double s = p.sig(l), e = p.eps(l);
  const double s6 = std::pow(s / r, 6);
  const double r6 = std::pow(r, 6);
  // d/dl 4 eps (s^12/r^12 - s^6/r^6) = 4 eps' (..) + 4 eps s' (12 s^11/r^12 - 6 s^5/r^6)
  return 4 * (p.eps1 - p.eps0) * (s6 * s6 - s6) +
         4 * e * (p.sig1 - p.sig0) * (12 * s6 * s6 / s - 6 * std::pow(s, 5) / r6);
}

PairSums lj_sums(const double* r, long n, double l, const LjPath& p) {
  PairSums out;
  const double s = p.sig(l), e = p.eps(l), de = p.eps1 - p.eps0, ds = p.sig1 - p.sig0;
  for (long i = 0; i < n; ++i) {
    if (!(r[i] < p.cutoff)) continue;
    const double q = s / r[i];
    const double q2 = q * q;
    const double q6 = q2 * q2 * q2;
    const double q12 = q6 * q6;
    out.u += 4 * e * (q12 - q6);
    out.dudl += 4 * de * (q12 - q6) + 4 * e * ds * (12 * q12 - 6 * q6) / s;
    ++out.pairs;
  }
  return out;
}

double lj_energy_sum(const double* r, long n, double l, const LjPath& p) {
  return lj_sums(r, n, l, p).u;
}

void SamplingSpec::validate(const std::string& source) const {
  if (!(timestep_fs > 0 && timestep_fs <= 10))
    fail(source, "timestep_fs", fmt::format("{}", timestep_fs), "must be in (0, 10]");
  if (equil_steps < 0) fail(source, "equil_steps", std::to_string(equil_steps), "must be >= 0");
  if (sample_every < 1) fail(source, "sample_every", std::to_string(sample_every), "must be >= 1");
  if (blocks < 3) fail(source, "blocks", std::to_string(blocks), "must be >= 3");
  if (prod_steps < static_cast<long>(sample_every) * blocks)
    fail(source, "prod_steps", std::to_string(prod_steps),
         fmt::format("must be >= sample_every * blocks = {}", sample_every * blocks));
  if (!(temperature > 0))
    fail(source, "temperature", fmt::format("{}", temperature), "must be > 0 K");
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string log_of(const std::string& h5) {
  fs::path p(h5);
  p.replace_extension(".log");
  return p.string();
}

void write_point(const std::string& path, const PointJob& j, const PointResult& r,
                 const SamplingSpec& s) {
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    f.set_attr("/", "format", "pnc-thermo-lambda-point");
    f.write_string("/label", j.label);
    f.write_scalar("/lambda", r.lambda);
    f.write_scalar("/lambda_prev", r.lambda_prev);
    f.write_scalar("/lambda_next", r.lambda_next);
    f.write_string("/seed", std::to_string(j.seed));
    f.write_scalar("/timestep", s.timestep_fs);
    f.set_attr("/timestep", "units", "fs");
    f.write_scalar("/equil_steps", s.equil_steps);
    f.write_scalar("/prod_steps", s.prod_steps);
    f.write_scalar("/sample_every", s.sample_every);
    f.write_scalar("/blocks", s.blocks);
    f.write_scalar("/temperature", s.temperature);
    f.set_attr("/temperature", "units", "K");
    f.write_scalar("/dhdl_mean", r.dhdl.value);
    f.set_attr("/dhdl_mean", "units", "kcal/mol");
    f.write_scalar("/dhdl_stderr", r.dhdl.se);
    f.set_attr("/dhdl_stderr", "units", "kcal/mol (block average)");
    const std::pair<const char*, const std::vector<double>*> series[] = {
        {"/samples/dhdl", &r.dhdl_s},
        {"/samples/u", &r.u_s},
        {"/samples/du_prev", &r.dprev_s},
        {"/samples/du_next", &r.dnext_s}};
    for (const auto& [name, v] : series) {
      f.write_vector(name, *v);
      f.set_attr(name, "units", "kcal/mol");
    }
    f.set_attr("/samples/u", "definition", "lambda-dependent energy U(lambda)");
    f.set_attr("/samples/du_prev", "definition", "U(lambda_prev) - U(lambda) (FEP)");
    f.set_attr("/samples/du_next", "definition", "U(lambda_next) - U(lambda) (FEP)");
    for (const auto& [k, v] : r.checks)
      f.write_scalar("/checks/" + k, v);
    f.write_scalar("/seconds", r.seconds);
  }
  out.commit();
}

void point_child(rve::Lammps& l, const SamplingSpec& s, const LambdaSystem& sys,
                 const PointJob& j) {
  const auto t0 = std::chrono::steady_clock::now();
  sys.setup(l, j.lambda, j.seed);
  l.cmd(fmt::format("timestep {:.10g}", s.timestep_fs));
  if (s.equil_steps > 0) l.cmd(fmt::format("run {}", s.equil_steps));
  PointResult r;
  r.lambda = j.lambda;
  r.lambda_prev = j.lambda_prev;
  r.lambda_next = j.lambda_next;
  if (sys.checks) r.checks = sys.checks(l, j.lambda);
  const long n = s.prod_steps / s.sample_every;
  if (sys.production) {
    for (const auto& smp :
         sys.production(l, j.lambda, j.lambda_prev, j.lambda_next, s.prod_steps, s.sample_every)) {
      r.dhdl_s.push_back(smp.dhdl);
      r.u_s.push_back(smp.u);
      r.dprev_s.push_back(smp.du_prev);
      r.dnext_s.push_back(smp.du_next);
    }
    if (static_cast<long>(r.dhdl_s.size()) != n)
      fail(j.h5, "samples", std::to_string(r.dhdl_s.size()), fmt::format("expected {}", n));
  }
  const auto tp = std::chrono::steady_clock::now();
  long next_report = n / 5;
  for (long k = 0; k < (sys.production ? 0 : n); ++k) {
    // the first chunk sets the run up (a check may have changed coefficients)
    l.cmd(fmt::format(k == 0 ? "run {}" : "run {} pre no post no", s.sample_every));
    const LambdaSample smp = sys.sample(l, j.lambda, j.lambda_prev, j.lambda_next);
    r.dhdl_s.push_back(smp.dhdl);
    r.u_s.push_back(smp.u);
    r.dprev_s.push_back(smp.du_prev);
    r.dnext_s.push_back(smp.du_next);
    if (k + 1 == next_report && k + 1 < n) {
      const double el = seconds_since(tp);
      std::cerr << fmt::format("    {}: sample {}/{}, running mean dH/dl {:.4f} kcal/mol, "
                               "ETA {:.0f} s\n",
                               j.label, k + 1, n, block_mean(r.dhdl_s, 1).value,
                               el / static_cast<double>(k + 1) * static_cast<double>(n - k - 1))
                << std::flush;
      next_report += n / 5;
    }
  }
  r.dhdl = block_mean(r.dhdl_s, s.blocks);
  r.seconds = seconds_since(t0);
  write_point(j.h5, j, r, s);
}

} // namespace

PointResult read_point(const std::string& path) {
  if (!fs::exists(path)) fail(path, "", "", "no such lambda-point file");
  h5::File f(path, h5::File::Mode::read);
  if (f.attr_string("/", "format").value_or("") != "pnc-thermo-lambda-point")
    fail(path, "format", f.attr_string("/", "format").value_or(""),
         "must be pnc-thermo-lambda-point");
  PointResult r;
  r.lambda = f.read_scalar("/lambda");
  r.lambda_prev = f.read_scalar("/lambda_prev");
  r.lambda_next = f.read_scalar("/lambda_next");
  r.dhdl.value = f.read_scalar("/dhdl_mean");
  r.dhdl.se = f.read_scalar("/dhdl_stderr");
  r.dhdl_s = f.read_vector("/samples/dhdl");
  r.u_s = f.read_vector("/samples/u");
  r.dprev_s = f.read_vector("/samples/du_prev");
  r.dnext_s = f.read_vector("/samples/du_next");
  if (f.exists("/checks"))
    for (const auto& k : f.children("/checks"))
      r.checks[k] = f.read_scalar("/checks/" + k);
  r.seconds = f.read_scalar("/seconds");
  return r;
}

void run_points(const SamplingSpec& s,
                const std::vector<std::pair<PointJob, LambdaSystem>>& point_jobs, bool resume,
                int jobs, const Progress& progress) {
  s.validate("<sampling>");
  std::vector<const std::pair<PointJob, LambdaSystem>*> pending;
  for (const auto& t : point_jobs)
    if (!(resume && fs::exists(t.first.h5))) pending.push_back(&t);
  const int total = static_cast<int>(point_jobs.size());
  int done = total - static_cast<int>(pending.size());
  if (progress && done > 0) progress("resumed: finished points reused", done, total, 0, 0);
  const auto t0 = std::chrono::steady_clock::now();
  jobs = std::max(1, jobs);
  for (std::size_t b = 0; b < pending.size(); b += static_cast<std::size_t>(jobs)) {
    std::vector<std::pair<rve::StageSpec, rve::StageBody>> stages;
    for (std::size_t i = b; i < std::min(pending.size(), b + static_cast<std::size_t>(jobs)); ++i) {
      const PointJob j = pending[i]->first;
      const LambdaSystem sys = pending[i]->second;
      make_output_directory(fs::path(j.h5).parent_path().string());
      rve::StageSpec spec{j.label, log_of(j.h5), {}};
      stages.push_back(
          {spec, rve::stoppable([s, sys, j](rve::Lammps& l) { point_child(l, s, sys, j); })});
    }
    const auto outcomes = rve::run_stages(stages, jobs);
    pnc::throw_if_stopped("the running lambda points stopped; finished points are kept");
    for (std::size_t i = 0; i < outcomes.size(); ++i) {
      if (!outcomes[i].ok)
        rve::throw_stage_failure(outcomes[i], "lambda point " + outcomes[i].name);
      ++done;
      const double el = seconds_since(t0);
      const int left = total - done;
      // the points of a batch end together: time per batch x batches left
      const double batches_done = static_cast<double>(b / static_cast<std::size_t>(jobs) + 1);
      const double batches_left = std::ceil(static_cast<double>(left) / jobs);
      if (progress) {
        const PointResult r = read_point(pending[b + i]->first.h5);
        progress(fmt::format("{}: <dH/dl> = {:.4f} +- {:.4f} kcal/mol ({:.1f} s)",
                             pending[b + i]->first.label, r.dhdl.value, r.dhdl.se,
                             outcomes[i].seconds),
                 done, total, el, el / batches_done * batches_left);
      }
    }
  }
}

std::vector<PointJob> node_jobs(const Quadrature& q, const std::string& dir,
                                const std::string& label, std::uint64_t seed) {
  std::vector<PointJob> out;
  const std::size_t n = q.nodes.size();
  for (std::size_t i = 0; i < n; ++i) {
    PointJob j;
    j.lambda = q.nodes[i];
    j.lambda_prev = i > 0 ? q.nodes[i - 1] : std::nan("");
    j.lambda_next = i + 1 < n ? q.nodes[i + 1] : std::nan("");
    j.h5 = (fs::path(dir) / fmt::format("lambda_{}.h5", i)).string();
    j.label = fmt::format("{} lambda {:.4f} ({}/{})", label, j.lambda, i + 1, n);
    j.seed = seed + i;
    out.push_back(j);
  }
  return out;
}

LambdaIntegral collect(const Quadrature& q, const std::vector<PointJob>& jobs, double kT,
                       int blocks) {
  LambdaIntegral li;
  li.rule = q;
  std::vector<double> m, se;
  for (const auto& j : jobs) {
    li.points.push_back(read_point(j.h5));
    if (std::fabs(li.points.back().lambda - j.lambda) > 1e-12)
      fail(
          j.h5, "/lambda", fmt::format("{}", li.points.back().lambda),
          fmt::format("expected {} (the file belongs to another rule; use a new --out)", j.lambda));
    m.push_back(li.points.back().dhdl.value);
    se.push_back(li.points.back().dhdl.se);
  }
  li.dA = integrate(q, m, se);
  for (std::size_t i = 0; i + 1 < li.points.size(); ++i) {
    const auto& a = li.points[i];
    const auto& b = li.points[i + 1];
    li.fep_forward.push_back(fep(a.dnext_s, kT, blocks));
    Estimate bw = fep(b.dprev_s, kT, blocks);
    bw.value = -bw.value;
    li.fep_backward.push_back(bw);
    const double h = b.lambda - a.lambda;
    li.ti_trapezoid.push_back(
        {0.5 * h * (a.dhdl.value + b.dhdl.value), 0.5 * h * std::hypot(a.dhdl.se, b.dhdl.se)});
  }
  return li;
}

// ------------------------------------------------------------------------------------------

std::vector<std::string> deform_commands(const DeformState& st, const double lo[3],
                                         const double hi[3], double xy, double yz, double xz) {
  Eigen::Matrix3d H; // columns: box vectors a, b, c (LAMMPS: a = (lx,0,0), b = (xy,ly,0), ...)
  H << hi[0] - lo[0], xy, xz, 0, hi[1] - lo[1], yz, 0, 0, hi[2] - lo[2];
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  if (st.kind == "vol")
    F *= 1 + st.strain; // volumetric F = (1+a) I (docs/theory.md §4.2, D63)
  else if (st.kind == "dev")
    // deviatoric F = I + b (1 - delta_ij) (docs/theory.md §4.2)
    F += st.strain * (Eigen::Matrix3d::Ones() - Eigen::Matrix3d::Identity());
  else if (st.kind != "ref")
    fail("<ti>", "state", st.kind, "must be ref, vol or dev");
  std::vector<std::string> out;
  if (st.kind == "ref") return out;
  // F H = Q R with R upper triangular and positive diagonal: the rotated box Q^T F H = R is
  // LAMMPS's form; remap keeps fractional coordinates, i.e. x -> R H^-1 x = Q^T F x (D63).
  Eigen::HouseholderQR<Eigen::Matrix3d> qr(F * H);
  Eigen::Matrix3d R = qr.matrixQR().triangularView<Eigen::Upper>();
  for (int i = 0; i < 3; ++i)
    if (R(i, i) < 0) R.row(i) *= -1;
  const double c[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  if (st.kind == "dev") out.push_back("change_box all triclinic");
  std::string cb = "change_box all";
  for (int a = 0; a < 3; ++a)
    cb += fmt::format(" {} final {:.15g} {:.15g}", "xyz"[a], c[a] - 0.5 * R(a, a),
                      c[a] + 0.5 * R(a, a));
  if (st.kind == "dev")
    cb += fmt::format(" xy final {:.15g} xz final {:.15g} yz final {:.15g}", R(0, 1), R(0, 2),
                      R(1, 2));
  out.push_back(cb + " remap units box");
  return out;
}

void TiSpec::validate(const std::string& source) const {
  path.validate(source);
  sampling.validate(source);
  make_rule(rule, points, source);
  auto check = [&](const char* f, const std::vector<double>& v) {
    for (double x : v)
      if (!std::isfinite(x) || std::fabs(x) > 0.1)
        fail(source, f, fmt::format("{}", x), "strain parameters must be finite, |s| <= 0.1");
  };
  check("vol", vol);
  check("dev", dev);
  if (vol.empty() && dev.empty()) fail(source, "vol/dev", "", "at least one deformation state");
  if (!(damp_fs > 0)) fail(source, "damp_fs", fmt::format("{}", damp_fs), "must be > 0");
  if (!(fd_h > 0 && fd_h < 0.05))
    fail(source, "fd_h", fmt::format("{}", fd_h), "must be in (0, 0.05)");
  if (seed < 1 || seed > 800000000)
    fail(source, "seed", std::to_string(seed), "must be in 1..800000000 (LAMMPS seeds)");
  if (dhdl_method != "virial" && dhdl_method != "pairs")
    fail(source, "dhdl_method", dhdl_method, "must be \"virial\" or \"pairs\"");
}

std::vector<DeformState> ti_states(const TiSpec& spec) {
  std::vector<DeformState> out;
  bool ref = false;
  for (const auto& [kind, list] :
       {std::pair<std::string, const std::vector<double>*>{"vol", &spec.vol}, {"dev", &spec.dev}})
    for (double s : *list) {
      if (s == 0.0) {
        if (!ref) out.push_back({"ref", 0.0, "ref"});
        ref = true;
        continue;
      }
      out.push_back({kind, s, fmt::format("{}_{:.6g}", kind, s)});
    }
  return out;
}

namespace {
std::string lj_coeff(const LjPath& p, double l) {
  return fmt::format("pair_coeff * * {:.15g} {:.15g} {:.15g}", p.eps(l), p.sig(l), p.cutoff);
}
} // namespace

namespace {
/// U12, U6 from the pair energy U and the pair virial W = sum r.f (one LJ type).
LambdaSample from_energy_virial(double U, double W, double l, double lp, double ln,
                                const LjPath& p) {
  const double u12 = (W - 6 * U) / 6, u6 = (W - 12 * U) / 6;
  const double e = p.eps(l), sg = p.sig(l);
  LambdaSample out;
  out.u = U;
  out.dhdl = (p.eps1 - p.eps0) / e * U + (p.sig1 - p.sig0) / sg * W;
  auto at = [&](double lq) {
    if (!std::isfinite(lq)) return std::nan("");
    const double sr = p.sig(lq) / sg, s6 = std::pow(sr, 6);
    return p.eps(lq) / e * (s6 * s6 * u12 - s6 * u6) - U;
  };
  out.du_prev = at(lp);
  out.du_next = at(ln);
  return out;
}
} // namespace

LambdaSystem lj_sampling(const LjPath& p, double h, const std::string& method) {
  if (method != "virial" && method != "pairs")
    fail("<ti>", "dhdl_method", method, "must be \"virial\" or \"pairs\"");
  LambdaSystem sys;
  auto coeff = [p](double l) { return lj_coeff(p, l); };
  auto distances = [](rve::Lammps& l) {
    if (!l.handle())
      fail("<ti>", "ranks", "", "the TI samplers need LAMMPS inside the stage child (1 rank)");
    auto* rows = static_cast<int*>(
        lammps_extract_compute(l.handle(), "pnc_pl", LMP_STYLE_LOCAL, LMP_SIZE_ROWS));
    auto* d = static_cast<double*>(
        lammps_extract_compute(l.handle(), "pnc_pl", LMP_STYLE_LOCAL, LMP_TYPE_VECTOR));
    const long n = rows ? *rows : 0;
    if (n > 0 && !d) fail("<lammps>", "compute pair/local", "", "no distance vector");
    return std::pair<const double*, long>{d, n};
  };
  sys.sample = [=](rve::Lammps& l, double lambda, double lp, double ln) {
    const auto [d, n] = distances(l);
    const PairSums s = lj_sums(d, n, lambda, p);
    LambdaSample out;
    out.dhdl = s.dudl;
    out.u = s.u;
    out.du_prev = std::isfinite(lp) ? lj_energy_sum(d, n, lp, p) - s.u : std::nan("");
    out.du_next = std::isfinite(ln) ? lj_energy_sum(d, n, ln, p) - s.u : std::nan("");
    return out;
  };
  sys.checks = [=](rve::Lammps& l, double lambda) {
    std::map<std::string, double> c;
    l.cmd("run 0");
    const double e0 = l.thermo("evdwl");
    const auto [d, n] = distances(l);
    const PairSums s = lj_sums(d, n, lambda, p);
    // central differences at h and 2h; Richardson (4 D_h - D_2h)/3 is O(h^4); |D_h - D_2h|/3
    // estimates the error of D_h (an upper bound for the extrapolated value), plus round-off
    double e[4];
    const double off[4] = {-2 * h, -h, h, 2 * h};
    for (int k = 0; k < 4; ++k) {
      l.cmd(coeff(lambda + off[k]));
      l.cmd("run 0");
      e[k] = l.thermo("evdwl");
    }
    l.cmd(coeff(lambda));
    l.cmd("run 0");
    const double d1 = (e[2] - e[1]) / (2 * h), d2 = (e[3] - e[0]) / (4 * h);
    double emax = 0;
    for (double v : e)
      emax = std::max(emax, std::fabs(v));
    c["fd_dhdl_lammps"] = (4 * d1 - d2) / 3;
    c["fd_error_estimate"] = std::fabs(d1 - d2) / 3 + 8 * 2.3e-16 * emax / h;
    c["fd_h"] = h;
    c["dhdl_pnc"] = s.dudl;
    c["u_lammps"] = e0;
    c["u_pnc"] = s.u;
    c["pairs"] = static_cast<double>(s.pairs);
    c["volume"] = l.thermo("vol");
    // the virial identity on the same configuration (D64)
    l.cmd("compute pnc_chk_pp all pressure NULL pair");
    l.cmd("run 0");
    const double nktv2p = *static_cast<double*>(lammps_extract_global(l.handle(), "nktv2p"));
    const double W = 3 * l.thermo("vol") * l.compute_value("pnc_chk_pp") / nktv2p;
    l.cmd("uncompute pnc_chk_pp");
    // U(lambda') - U(lambda) at a probe lambda' = lambda - 0.05 both ways (the FEP samples)
    const double lq = lambda - 0.05;
    const LambdaSample id = from_energy_virial(l.thermo("evdwl"), W, lambda, lq, lq, p);
    c["dhdl_virial_identity"] = id.dhdl;
    c["du_probe_virial_identity"] = id.du_prev;
    c["du_probe_pnc"] = lj_energy_sum(d, n, lq, p) - s.u;
    return c;
  };
  if (method == "virial")
    sys.production = [p](rve::Lammps& l, double lambda, double lp, double ln, long steps,
                         int every) {
      l.cmd("compute pnc_epair all pair lj/cut evdwl");
      l.cmd("compute pnc_ppair all pressure NULL pair");
      l.cmd("variable pnc_vol equal vol");
      // the pair energy is extensive, pressure and volume intensive: two fix vectors
      l.cmd(fmt::format("fix pnc_ue all vector {} c_pnc_epair", every));
      l.cmd(fmt::format("fix pnc_uw all vector {} c_pnc_ppair v_pnc_vol", every));
      if (!l.handle())
        fail("<ti>", "ranks", "", "the TI samplers need LAMMPS inside the stage child (1 rank)");
      const double nktv2p = *static_cast<double*>(lammps_extract_global(l.handle(), "nktv2p"));
      // five pieces for progress; fix vector appends across runs
      const int pieces = steps >= 5L * every ? 5 : 1;
      const auto t0 = std::chrono::steady_clock::now();
      long done = 0;
      for (int k = 0; k < pieces; ++k) {
        long chunk = (steps / every / pieces) * every;
        if (k == pieces - 1) chunk = steps - done;
        l.cmd(fmt::format("run {}", chunk)); // pre yes: fix vector sizes its storage per run
        done += chunk;
        if (k + 1 < pieces) {
          const double el =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          std::cerr << fmt::format("    lambda {:.4f}: {}/{} production steps, ETA {:.0f} s\n",
                                   lambda, done, steps,
                                   el / static_cast<double>(done) *
                                       static_cast<double>(steps - done))
                    << std::flush;
        }
      }
      // rows: the first run's start step (end of equilibration) and every `every` steps after
      const long rows = steps / every + 1;
      std::vector<LambdaSample> out;
      for (long i = 1; i < rows; ++i) {
        const double U = l.fix_value("pnc_ue", static_cast<int>(i));
        const double P = l.fix_value("pnc_uw", static_cast<int>(i), 0);
        const double V = l.fix_value("pnc_uw", static_cast<int>(i), 1);
        out.push_back(from_energy_virial(U, 3 * V * P / nktv2p, lambda, lp, ln, p));
      }
      l.cmd("unfix pnc_uw");
      l.cmd("unfix pnc_ue");
      l.cmd("uncompute pnc_ppair");
      l.cmd("uncompute pnc_epair");
      return out;
    };
  return sys;
}

LambdaSystem polymer_system(const TiSpec& spec, const DeformState& st, const std::string& restart,
                            const std::vector<std::string>& ff) {
  rve::lammps_path(restart, "restart"); // refused here, in the parent, if it cannot be quoted
  LambdaSystem sys = lj_sampling(spec.path, spec.fd_h, spec.dhdl_method);
  const LjPath p = spec.path;
  const double T = spec.sampling.temperature, damp = spec.damp_fs;
  const std::string style = spec.atom_style;
  sys.setup = [=](rve::Lammps& l, double lambda, std::uint64_t seed) {
    l.cmd("units real");
    l.cmd("atom_style " + style);
    l.cmd("read_restart " + rve::lammps_path(restart, "restart"));
    l.cmds(ff);
    l.cmd(fmt::format("pair_style lj/cut {:.15g}", p.cutoff)); // D62: fixed cut-off
    l.cmd("pair_modify shift no tail no");
    double lo[3], hi[3], xy, yz, xz;
    l.box(lo, hi, xy, yz, xz);
    l.cmds(deform_commands(st, lo, hi, xy, yz, xz));
    l.cmd(lj_coeff(p, lambda));
    l.cmd("reset_timestep 0");
    l.cmd("fix pnc_nve all nve");
    l.cmd(fmt::format("fix pnc_lan all langevin {0:.10g} {0:.10g} {1:.10g} {2} zero yes", T, damp,
                      seed));
    l.cmd("fix pnc_mom all momentum 100 linear 1 1 1");
    l.cmd("compute pnc_pl all pair/local dist");
    l.cmd("thermo_style custom step temp pe evdwl press vol");
    l.cmd("thermo 1000");
  };
  return sys;
}

namespace {

ResponseFit fit_kind(const std::string& kind, const std::vector<StateResult>& st) {
  ResponseFit rf;
  rf.kind = kind;
  std::vector<double> x, y, sy;
  for (const auto& s : st)
    if (s.state.kind == kind || s.state.kind == "ref") {
      x.push_back(s.state.strain);
      y.push_back(s.ti.dA.value);
      sy.push_back(s.ti.dA.se);
      if (s.state.kind == "ref") rf.v0 = s.volume;
    }
  if (x.size() < 3 || rf.v0 <= 0) {
    rf.modulus = rf.modulus_se = std::nan("");
    return rf;
  }
  rf.fit = polyfit(x, y, sy, 2, false);
  const double f = kind == "vol" ? 2.0 / 9.0 : 1.0 / 6.0; // D65
  rf.modulus = f * rf.fit.c[2] / rf.v0 * units::pa_per_kcal_mol_A3;
  rf.modulus_se = f * rf.fit.se[2] / rf.v0 * units::pa_per_kcal_mol_A3;
  return rf;
}

} // namespace

TiResult collect_ti(const TiSpec& spec, const std::string& dir) {
  TiResult r;
  r.spec = spec;
  const Quadrature q = make_rule(spec.rule, spec.points, "<ti>");
  const double kT = units::kB_kcal_mol_K * spec.sampling.temperature;
  for (const auto& st : ti_states(spec)) {
    StateResult sr;
    sr.state = st;
    sr.ti = collect(q, node_jobs(q, (fs::path(dir) / st.id).string(), st.id, 0), kT,
                    spec.sampling.blocks);
    sr.volume = sr.ti.points.front().checks.count("volume")
                    ? sr.ti.points.front().checks.at("volume")
                    : std::nan("");
    r.states.push_back(sr);
  }
  for (const char* k : {"vol", "dev"})
    r.fits.push_back(fit_kind(k, r.states));
  return r;
}

void check_ti_start(const TiSpec& spec, const std::string& restart) {
  spec.validate("<ti>");
  if (!fs::is_regular_file(restart))
    fail(restart, "restart", restart, "no such LAMMPS restart file");
}

std::vector<TiPoint> ti_points(const TiSpec& spec, const std::string& dir) {
  const Quadrature q = make_rule(spec.rule, spec.points, "<ti>");
  std::vector<TiPoint> out;
  const auto states = ti_states(spec);
  for (std::size_t k = 0; k < states.size(); ++k) {
    const auto& st = states[k];
    const auto jobs =
        node_jobs(q, (fs::path(dir) / st.id).string(), st.id, spec.seed * 1000 + k * 10 + 1);
    for (std::size_t i = 0; i < jobs.size(); ++i)
      out.push_back({st, k, i, jobs[i]});
  }
  return out;
}

void run_ti_point(const TiSpec& spec, const TiPoint& point, const std::string& restart,
                  const std::vector<std::string>& ff, const Progress& progress) {
  check_ti_start(spec, restart);
  const LambdaSystem sys = polymer_system(spec, point.state, fs::absolute(restart).string(), ff);
  run_points(spec.sampling, {{point.job, sys}}, false, 1, progress);
}

TiResult finish_ti(const TiSpec& spec, const std::string& dir, const std::string& source_json,
                   double seconds) {
  TiResult r = collect_ti(spec, dir);
  r.h5 = (fs::path(dir) / "ti.h5").string();
  r.seconds = seconds;
  write_ti_h5(r.h5, r, source_json);
  return r;
}

TiResult run_ti(const TiSpec& spec, const std::string& restart, const std::vector<std::string>& ff,
                const std::string& dir, bool resume, const std::string& source_json,
                const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  check_ti_start(spec, restart);
  std::vector<std::pair<PointJob, LambdaSystem>> point_jobs;
  std::vector<LambdaSystem> systems; // one per state
  for (const auto& p : ti_points(spec, dir)) {
    if (p.state_index >= systems.size())
      systems.push_back(polymer_system(spec, p.state, fs::absolute(restart).string(), ff));
    point_jobs.push_back({p.job, systems[p.state_index]});
  }
  run_points(spec.sampling, point_jobs, resume, spec.jobs, progress);
  return finish_ti(spec, dir, source_json, seconds_since(t0));
}

void write_ti_h5(const std::string& path, const TiResult& r, const std::string& source_json) {
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    f.set_attr("/", "format", "pnc-thermo-ti");
    f.set_attr("/", "units", "LAMMPS real: kcal/mol, A, fs, K; moduli in Pa");
    f.write_string("/recipe", source_json.empty() ? "{}" : source_json);
    const auto& s = r.spec;
    f.write_string("/spec/rule", s.rule);
    f.write_scalar("/spec/points", s.points);
    f.write_vector("/spec/nodes",
                   r.states.empty() ? std::vector<double>{} : r.states.front().ti.rule.nodes);
    f.write_vector("/spec/weights",
                   r.states.empty() ? std::vector<double>{} : r.states.front().ti.rule.weights);
    f.write_scalar("/spec/eps0", s.path.eps0);
    f.write_scalar("/spec/eps1", s.path.eps1);
    f.set_attr("/spec/eps0", "units", "kcal/mol");
    f.set_attr("/spec/eps1", "units", "kcal/mol");
    f.write_scalar("/spec/sig0", s.path.sig0);
    f.write_scalar("/spec/sig1", s.path.sig1);
    f.write_scalar("/spec/cutoff", s.path.cutoff);
    f.set_attr("/spec/cutoff", "units", "A (fixed at every lambda, D62)");
    f.write_scalar("/spec/timestep", s.sampling.timestep_fs);
    f.write_scalar("/spec/equil_steps", s.sampling.equil_steps);
    f.write_scalar("/spec/prod_steps", s.sampling.prod_steps);
    f.write_scalar("/spec/sample_every", s.sampling.sample_every);
    f.write_scalar("/spec/blocks", s.sampling.blocks);
    f.write_scalar("/spec/temperature", s.sampling.temperature);
    f.write_scalar("/spec/damp", s.damp_fs);
    f.write_string("/spec/seed", std::to_string(s.seed));
    for (const auto& st : r.states) {
      const std::string g = "/states/" + st.state.id;
      f.write_string(g + "/kind", st.state.kind);
      f.write_scalar(g + "/strain", st.state.strain);
      f.write_scalar(g + "/volume", st.volume);
      f.set_attr(g + "/volume", "units", "A^3");
      std::vector<double> lam, m, se, fd, an;
      for (const auto& p : st.ti.points) {
        lam.push_back(p.lambda);
        m.push_back(p.dhdl.value);
        se.push_back(p.dhdl.se);
        fd.push_back(p.checks.count("fd_dhdl_lammps") ? p.checks.at("fd_dhdl_lammps")
                                                      : std::nan(""));
        an.push_back(p.checks.count("dhdl_pnc") ? p.checks.at("dhdl_pnc") : std::nan(""));
      }
      f.write_vector(g + "/lambda", lam);
      f.write_vector(g + "/dhdl_mean", m);
      f.set_attr(g + "/dhdl_mean", "units", "kcal/mol");
      f.write_vector(g + "/dhdl_stderr", se);
      f.set_attr(g + "/dhdl_stderr", "units", "kcal/mol");
      f.write_vector(g + "/fd_check/dhdl_lammps_finite_difference", fd);
      f.write_vector(g + "/fd_check/dhdl_pnc", an);
      f.set_attr(g + "/fd_check", "definition",
                 "one configuration per point after equilibration: pnc's pair-distance sum vs "
                 "(evdwl(l+h) - evdwl(l-h)) / 2h from LAMMPS, kcal/mol");
      f.write_scalar(g + "/dA", st.ti.dA.value);
      f.set_attr(g + "/dA", "units", "kcal/mol (A(lambda=1) - A(lambda=0), whole RVE)");
      f.write_scalar(g + "/dA_stderr", st.ti.dA.se);
      std::vector<double> ff, fb, tt, ffs, fbs, tts;
      for (std::size_t i = 0; i < st.ti.fep_forward.size(); ++i) {
        ff.push_back(st.ti.fep_forward[i].value);
        ffs.push_back(st.ti.fep_forward[i].se);
        fb.push_back(st.ti.fep_backward[i].value);
        fbs.push_back(st.ti.fep_backward[i].se);
        tt.push_back(st.ti.ti_trapezoid[i].value);
        tts.push_back(st.ti.ti_trapezoid[i].se);
      }
      f.write_vector(g + "/adjacent/fep_forward", ff);
      f.write_vector(g + "/adjacent/fep_forward_stderr", ffs);
      f.write_vector(g + "/adjacent/fep_backward", fb);
      f.write_vector(g + "/adjacent/fep_backward_stderr", fbs);
      f.write_vector(g + "/adjacent/ti_trapezoid", tt);
      f.write_vector(g + "/adjacent/ti_trapezoid_stderr", tts);
      f.set_attr(g + "/adjacent", "definition",
                 "A(lambda_i+1) - A(lambda_i), kcal/mol, between adjacent nodes");
      for (std::size_t i = 0; i < st.ti.points.size(); ++i) {
        const auto& p = st.ti.points[i];
        const std::string pg = g + fmt::format("/points/{}", i);
        f.write_scalar(pg + "/lambda", p.lambda);
        f.write_vector(pg + "/samples/dhdl", p.dhdl_s);
        f.write_vector(pg + "/samples/u", p.u_s);
        f.write_vector(pg + "/samples/du_prev", p.dprev_s);
        f.write_vector(pg + "/samples/du_next", p.dnext_s);
        f.set_attr(pg + "/samples", "units", "kcal/mol");
        for (const auto& [k, v] : p.checks)
          f.write_scalar(pg + "/checks/" + k, v);
      }
    }
    for (const auto& fit : r.fits) {
      const std::string g = "/results/" + fit.kind;
      std::vector<double> x, y, sy, rel, rels;
      double a0 = std::nan(""), s0 = std::nan("");
      for (const auto& st : r.states)
        if (st.state.kind == "ref") {
          a0 = st.ti.dA.value;
          s0 = st.ti.dA.se;
        }
      for (const auto& st : r.states)
        if (st.state.kind == fit.kind || st.state.kind == "ref") {
          x.push_back(st.state.strain);
          y.push_back(st.ti.dA.value);
          sy.push_back(st.ti.dA.se);
          rel.push_back(st.state.kind == "ref" ? 0.0 : st.ti.dA.value - a0);
          rels.push_back(st.state.kind == "ref" ? 0.0 : std::hypot(st.ti.dA.se, s0));
        }
      f.write_vector(g + "/strain", x);
      f.set_attr(g + "/strain", "definition",
                 fit.kind == "vol" ? "alpha of F = (1+alpha) I" : "beta of F = I + beta(1-delta)");
      f.write_vector(g + "/dA", y);
      f.write_vector(g + "/dA_stderr", sy);
      f.write_vector(g + "/dA_minus_ref", rel);
      f.write_vector(g + "/dA_minus_ref_stderr", rels);
      f.set_attr(g + "/dA", "units", "kcal/mol");
      if (!fit.fit.c.empty()) {
        f.write_vector(g + "/quadratic_fit", fit.fit.c);
        f.write_vector(g + "/quadratic_fit_stderr", fit.fit.se);
        f.set_attr(g + "/quadratic_fit", "definition", "dA = c0 + c1 s + c2 s^2, kcal/mol");
        f.write_scalar(g + "/modulus", fit.modulus);
        f.write_scalar(g + "/modulus_stderr", fit.modulus_se);
        f.set_attr(g + "/modulus", "units", "Pa");
        f.set_attr(g + "/modulus", "definition",
                   fit.kind == "vol" ? "K = 2 c2 / (9 V0) (theory.md §4.4, D65)"
                                     : "mu = c2 / (6 V0) (theory.md §4.4, D65)");
      }
    }
  }
  out.commit();
}

} // namespace pnc::thermo
