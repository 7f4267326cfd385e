// Thermodynamic integration engine and the polymer free energy of deformation (units real).
#include "pnc/thermo/ti.hpp"

#include "pnc/md/box.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/progress.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"
#include "pnc/md/lammps_path.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/md/stage_stop.hpp"

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

void point_child(md::Lammps& l, const SamplingSpec& s, const LambdaSystem& sys, const PointJob& j) {
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
  pnc::Progress bar(j.label, static_cast<double>(n), "samples"); // D344
  long next_report = n / 5;
  for (long k = 0; k < (sys.production ? 0 : n); ++k) {
    // the first chunk sets the run up (a check may have changed coefficients)
    l.cmd(fmt::format(k == 0 ? "run {}" : "run {} pre no post no", s.sample_every));
    const LambdaSample smp = sys.sample(l, j.lambda, j.lambda_prev, j.lambda_next);
    r.dhdl_s.push_back(smp.dhdl);
    r.u_s.push_back(smp.u);
    r.dprev_s.push_back(smp.du_prev);
    r.dnext_s.push_back(smp.du_next);
    if (k + 1 == next_report || k + 1 == n) {
      bar.set(static_cast<double>(k + 1),
              fmt::format("running mean dH/dl {:.4f} kcal/mol", block_mean(r.dhdl_s, 1).value));
      if (k + 1 == next_report) next_report += n / 5;
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
                int jobs, const Progress& progress, int ranks) {
  s.validate("<sampling>");
  if (ranks < 1 || ranks > 4096) fail("<ti>", "ranks", std::to_string(ranks), "must be 1 to 4096");
  std::vector<const std::pair<PointJob, LambdaSystem>*> pending;
  for (const auto& t : point_jobs)
    if (!(resume && fs::exists(t.first.h5))) pending.push_back(&t);
  jobs = std::max(1, jobs);
  pnc::ProgressOptions po; // the points of a batch end together: rounds of `jobs` (D345)
  po.lanes = jobs;
  po.enabled = static_cast<bool>(progress);
  po.sink = progress;
  pnc::Progress bar("pnc thermo ti", static_cast<double>(point_jobs.size()), "lambda points", po);
  if (pending.size() < point_jobs.size())
    bar.skip(static_cast<double>(point_jobs.size() - pending.size()),
             "resumed: finished points reused");
  for (std::size_t b = 0; b < pending.size(); b += static_cast<std::size_t>(jobs)) {
    std::vector<std::pair<md::StageSpec, md::StageBody>> stages;
    for (std::size_t i = b; i < std::min(pending.size(), b + static_cast<std::size_t>(jobs)); ++i) {
      const PointJob j = pending[i]->first;
      const LambdaSystem sys = pending[i]->second;
      make_output_directory(fs::path(j.h5).parent_path().string());
      md::StageSpec spec{j.label, log_of(j.h5), {}, ranks}; // D324
      stages.push_back(
          {spec, md::stoppable([s, sys, j](md::Lammps& l) { point_child(l, s, sys, j); })});
    }
    const auto outcomes = md::run_stages(stages, jobs);
    pnc::throw_if_stopped("the running lambda points stopped; finished points are kept");
    for (std::size_t i = 0; i < outcomes.size(); ++i) {
      if (!outcomes[i].ok) md::throw_stage_failure(outcomes[i], "lambda point " + outcomes[i].name);
      std::string detail;
      if (progress) {
        const PointResult r = read_point(pending[b + i]->first.h5);
        detail =
            fmt::format("{}: <dH/dl> = {:.4f} +- {:.4f} kcal/mol ({:.1f} s)",
                        pending[b + i]->first.label, r.dhdl.value, r.dhdl.se, outcomes[i].seconds);
      }
      bar.advance(1, detail);
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

std::vector<std::string> deform_commands(const DeformState& st, const md::LmpBox& box) {
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  if (st.kind == "vol")
    F *= 1 + st.strain; // volumetric F = (1+a) I (docs/theory.md §4.2, D63)
  else if (st.kind == "dev")
    // deviatoric F = I + b (1 - delta_ij) (docs/theory.md §4.2); not upper triangular: the
    // box is F H rotated to the LAMMPS form (md::box_change, D63)
    F += st.strain * (Eigen::Matrix3d::Ones() - Eigen::Matrix3d::Identity());
  else if (st.kind != "ref")
    fail("<ti>", "state", st.kind, "must be ref, vol or dev");
  std::vector<std::string> out;
  if (st.kind == "ref") return out;
  if (st.kind == "dev") out.push_back("change_box all triclinic");
  const std::string cmd = md::box_change(box, F, "<ti state " + st.id + ">");
  if (!cmd.empty()) out.push_back(cmd);
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
  if (ranks < 1 || ranks > 4096)
    fail(source, "ranks", std::to_string(ranks), "must be 1 to 4096 (MPI ranks per point)");
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
  run_points(spec.sampling, {{point.job, sys}}, false, 1, progress, spec.ranks);
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
  run_points(spec.sampling, point_jobs, resume, spec.jobs, progress, spec.ranks);
  return finish_ti(spec, dir, source_json, seconds_since(t0));
}

} // namespace pnc::thermo
