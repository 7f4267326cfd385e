// ti.h5: the result of a thermodynamic integration on disk (format "pnc-thermo-ti"; units
// LAMMPS real, moduli in Pa; the layout is documented in docs/thermo.md).
#include "pnc/thermo/ti.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"

#include <fmt/format.h>

#include <cmath>

namespace pnc::thermo {

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
