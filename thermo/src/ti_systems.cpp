// The sampled systems of thermodynamic integration (units real): the LJ coupling path read
// from pair energies and virials or from pair distances, and the polymer RVE deformed to a
// state (docs/thermo.md; the engine that runs them is ti.cpp).
#include "pnc/thermo/ti.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/progress.hpp"
#include "pnc/core/units.hpp"
#include "pnc/md/lammps_path.hpp"
#include "pnc/md/runner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace pnc::thermo {

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
  // the pair distances of every rank (D324); sums over them agree to round-off in any row order
  auto distances = [](md::Lammps& l) { return l.compute_local_vector("pnc_pl"); };
  sys.sample = [=](md::Lammps& l, double lambda, double lp, double ln) {
    const std::vector<double> r = distances(l);
    const double* d = r.data();
    const long n = static_cast<long>(r.size());
    const PairSums s = lj_sums(d, n, lambda, p);
    LambdaSample out;
    out.dhdl = s.dudl;
    out.u = s.u;
    out.du_prev = std::isfinite(lp) ? lj_energy_sum(d, n, lp, p) - s.u : std::nan("");
    out.du_next = std::isfinite(ln) ? lj_energy_sum(d, n, ln, p) - s.u : std::nan("");
    return out;
  };
  sys.checks = [=](md::Lammps& l, double lambda) {
    std::map<std::string, double> c;
    l.cmd("run 0");
    const double e0 = l.thermo("evdwl");
    const std::vector<double> r = distances(l);
    const double* d = r.data();
    const long n = static_cast<long>(r.size());
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
    const double nktv2p = l.extract_global_double("nktv2p");
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
    sys.production = [p](md::Lammps& l, double lambda, double lp, double ln, long steps,
                         int every) {
      l.cmd("compute pnc_epair all pair lj/cut evdwl");
      l.cmd("compute pnc_ppair all pressure NULL pair");
      l.cmd("variable pnc_vol equal vol");
      // the pair energy is extensive, pressure and volume intensive: two fix vectors
      l.cmd(fmt::format("fix pnc_ue all vector {} c_pnc_epair", every));
      l.cmd(fmt::format("fix pnc_uw all vector {} c_pnc_ppair v_pnc_vol", every));
      const double nktv2p = l.extract_global_double("nktv2p");
      // five pieces for progress; fix vector appends across runs
      const int pieces = steps >= 5L * every ? 5 : 1;
      pnc::Progress bar(fmt::format("lambda {:.4f}", lambda), static_cast<double>(steps),
                        "production steps"); // D344
      long done = 0;
      for (int k = 0; k < pieces; ++k) {
        long chunk = (steps / every / pieces) * every;
        if (k == pieces - 1) chunk = steps - done;
        l.cmd(fmt::format("run {}", chunk)); // pre yes: fix vector sizes its storage per run
        done += chunk;
        bar.advance(static_cast<double>(chunk));
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
  md::lammps_path(restart, "restart"); // refused here, in the parent, if it cannot be quoted
  LambdaSystem sys = lj_sampling(spec.path, spec.fd_h, spec.dhdl_method);
  const LjPath p = spec.path;
  const double T = spec.sampling.temperature, damp = spec.damp_fs;
  const std::string style = spec.atom_style;
  sys.setup = [=](md::Lammps& l, double lambda, std::uint64_t seed) {
    l.cmd("units real");
    l.cmd("atom_style " + style);
    l.cmd("read_restart " + md::lammps_path(restart, "restart"));
    l.cmds(ff);
    l.cmd(fmt::format("pair_style lj/cut {:.15g}", p.cutoff)); // D62: fixed cut-off
    l.cmd("pair_modify shift no tail no");
    l.cmds(deform_commands(st, l.box()));
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

} // namespace pnc::thermo
