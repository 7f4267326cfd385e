// `pnc gimp couple`: an ESCM tension run from a JSON input (escm_run.hpp, docs/escm.md).
#include "pnc/gimp_coupler/escm_run.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/gimp_coupler/escm_gradient.hpp"
#include "pnc/gimp_coupler/escm_lj.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#ifndef PNC_GIMP_PYTHON
#define PNC_GIMP_PYTHON "/usr/bin/python3"
#endif

namespace pnc::gimp::escm {

namespace {

using json = nlohmann::json;

struct Params {
  double eps = 0.2381, sig = 3.405, rc = 2.5 * 3.405, mass = 39.948;
  int ncx = 40, ncy = 20, nbx = 14, nby = 14, nz = 3;
  int svc = 2, ivc = 1, substeps = 20;
  double dtau_fs = 4.0;
  std::string mode = "neumann";
  double temperature = 0.0;
  double strain = 1e-2, settle_ps = 10, load_ps = 40, hold_ps = 30, damping_fraction = 0.7;
  int frames = 8;
  double gradient_cells = 1.0; ///< background grid spacing of eqs. 6.3-6.7, in cell sizes
};

const std::set<std::string> kKeys = {"lj",
                                     "cells",
                                     "block_cells",
                                     "slab_cells",
                                     "svc_rings",
                                     "ivc_rings",
                                     "substeps",
                                     "md_timestep_fs",
                                     "mode",
                                     "interior_temperature",
                                     "strain",
                                     "settle_ps",
                                     "load_ps",
                                     "hold_ps",
                                     "damping_fraction",
                                     "frames",
                                     "short",
                                     "comment",
                                     "gradient_spacing_cells"};

void apply(const json& j, Params& p, const std::string& src, const std::string& prefix) {
  auto num = [&](const std::string& k, double lo, double hi, const char* rule) {
    const json& v = j.at(k);
    if (!v.is_number() || !(v.get<double>() >= lo && v.get<double>() <= hi))
      fail(src, prefix + k, v.dump(), rule);
    return v.get<double>();
  };
  auto integer = [&](const std::string& k, int lo, int hi, const char* rule) {
    const json& v = j.at(k);
    if (!v.is_number_integer() || v.get<long>() < lo || v.get<long>() > hi)
      fail(src, prefix + k, v.dump(), rule);
    return static_cast<int>(v.get<long>());
  };
  auto pair = [&](const std::string& k, int lo, int hi, const char* rule) {
    const json& v = j.at(k);
    if (!v.is_array() || v.size() != 2 || !v[0].is_number_integer() || !v[1].is_number_integer() ||
        v[0].get<long>() < lo || v[1].get<long>() < lo || v[0].get<long>() > hi ||
        v[1].get<long>() > hi)
      fail(src, prefix + k, v.dump(), rule);
    return std::array<int, 2>{static_cast<int>(v[0].get<long>()),
                              static_cast<int>(v[1].get<long>())};
  };
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!kKeys.count(it.key()) || (!prefix.empty() && (it.key() == "short" || it.key() == "lj")))
      fail(src, prefix + it.key(), "", "unknown key (docs/escm.md, \"Input file\")");
  if (j.contains("lj")) {
    const json& l = j.at("lj");
    if (!l.is_object()) fail(src, "lj", l.dump(), "must be an object");
    for (auto it = l.begin(); it != l.end(); ++it) {
      const std::string k = it.key();
      if (k != "epsilon" && k != "sigma" && k != "cutoff" && k != "mass")
        fail(src, "lj." + k, "", "unknown key (epsilon, sigma, cutoff, mass)");
      if (!it->is_number() || !(it->get<double>() > 0))
        fail(src, "lj." + k, it->dump(), "must be a number > 0 (real units)");
    }
    p.eps = l.value("epsilon", p.eps);
    p.sig = l.value("sigma", p.sig);
    p.mass = l.value("mass", p.mass);
    p.rc = l.value("cutoff", 2.5 * p.sig);
    if (p.rc < 1.2 * p.sig || p.rc > 6 * p.sig)
      fail(src, "lj.cutoff", std::to_string(p.rc), "must be in [1.2, 6] sigma");
  }
  if (j.contains("cells")) {
    const auto c = pair("cells", 8, 2000, "two integers in [8, 2000]");
    p.ncx = c[0];
    p.ncy = c[1];
  }
  if (j.contains("block_cells")) {
    const auto c = pair("block_cells", 3, 200, "two integers in [3, 200]");
    p.nbx = c[0];
    p.nby = c[1];
  }
  if (j.contains("slab_cells")) p.nz = integer("slab_cells", 2, 50, "an integer in [2, 50]");
  if (j.contains("svc_rings")) p.svc = integer("svc_rings", 1, 10, "an integer in [1, 10]");
  if (j.contains("ivc_rings")) p.ivc = integer("ivc_rings", 1, 10, "an integer in [1, 10]");
  if (j.contains("substeps")) p.substeps = integer("substeps", 1, 10000, "an integer in [1, 1e4]");
  if (j.contains("md_timestep_fs"))
    p.dtau_fs = num("md_timestep_fs", 1e-4, 20, "a number in [1e-4, 20] fs");
  if (j.contains("mode")) {
    const json& v = j.at("mode");
    if (!v.is_string() || (v.get<std::string>() != "neumann" && v.get<std::string>() != "schwarz"))
      fail(src, prefix + "mode", v.dump(), "\"neumann\" or \"schwarz\"");
    p.mode = v.get<std::string>();
  }
  if (j.contains("interior_temperature"))
    p.temperature = num("interior_temperature", 0, 5000, "a number in [0, 5000] K");
  if (j.contains("strain")) p.strain = num("strain", -0.1, 0.1, "a number in [-0.1, 0.1]");
  if (j.contains("settle_ps")) p.settle_ps = num("settle_ps", 0, 1e5, "a number in [0, 1e5] ps");
  if (j.contains("load_ps")) p.load_ps = num("load_ps", 1e-3, 1e5, "a number in (0, 1e5] ps");
  if (j.contains("hold_ps")) p.hold_ps = num("hold_ps", 0, 1e5, "a number in [0, 1e5] ps");
  if (j.contains("damping_fraction"))
    p.damping_fraction = num("damping_fraction", 0, 10, "a number in [0, 10] (of critical)");
  if (j.contains("frames")) p.frames = integer("frames", 0, 1000, "an integer in [0, 1000]");
  if (j.contains("gradient_spacing_cells"))
    p.gradient_cells =
        num("gradient_spacing_cells", 0.5, 10,
            "a number in [0.5, 10] (spacing of the gradient grid in continuum cell sizes)");
}

/// Continuum particles as a VTU point cloud (SI: m, m/s): zone (-1 ordinary continuum, 1 IVC
/// probe, 2 SVC), displacement_m, velocity_m_per_s, F_solver (the GIMP solver's F11 F12 F21
/// F22), then `extra`.
void write_particles_vtu(const std::string& path, const Solver<2>& s, const std::vector<int>& zone,
                         const std::vector<PointArray>& extra) {
  const std::size_t n = s.particles.size();
  std::vector<Eigen::Vector3d> x(n);
  std::vector<PointArray> arrays = {
      {"displacement_m", 3, {}}, {"velocity_m_per_s", 3, {}}, {"F_solver", 4, {}}};
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& xi = s.particles.x[i];
    const Eigen::Vector2d u = xi - s.particles.x0[i];
    const Eigen::Vector2d& v = s.particles.v[i];
    const auto& F = s.particles.F[i];
    x[i] = Eigen::Vector3d(xi[0], xi[1], 0.0);
    arrays[0].values.insert(arrays[0].values.end(), {u[0], u[1], 0.0});
    arrays[1].values.insert(arrays[1].values.end(), {v[0], v[1], 0.0});
    arrays[2].values.insert(arrays[2].values.end(), {F(0, 0), F(0, 1), F(1, 0), F(1, 1)});
  }
  arrays.insert(arrays.end(), extra.begin(), extra.end());
  write_point_cloud_vtu(path, x, zone, arrays, 12);
}

} // namespace

CoupleSummary run_couple(const CoupleOptions& o) {
  const std::string& src = o.input;
  json j;
  {
    std::ifstream f(src);
    if (!f) fail(src, "", "", "cannot open the input file");
    try {
      j = json::parse(f);
    } catch (const std::exception& e) {
      fail(src, "", "", std::string("not valid JSON: ") + e.what());
    }
  }
  if (!j.is_object()) fail(src, "", "", "the input must be a JSON object");
  Params p;
  apply(j, p, src, "");
  if (o.short_mode && j.contains("short")) {
    if (!j.at("short").is_object()) fail(src, "short", j.at("short").dump(), "must be an object");
    apply(j.at("short"), p, src, "short.");
  }
  const int rings = p.svc + p.ivc;
  if (p.nbx < 2 * rings + 1 || p.nby < 2 * rings + 1)
    fail(src, "block_cells", std::to_string(p.nbx) + " x " + std::to_string(p.nby),
         "must be at least 2 (svc_rings + ivc_rings) + 1 cells per axis");
  if (p.nbx + 4 > p.ncx || p.nby + 4 > p.ncy)
    fail(src, "cells", std::to_string(p.ncx) + " x " + std::to_string(p.ncy),
         "the continuum needs >= 2 cells around the atom block on each side");
  const LjFcc lj = lj_fcc(p.eps, p.sig, p.rc, p.mass);
  if (p.mode == "schwarz" && p.svc * lj.a0_A < p.rc)
    fail(src, "svc_rings", std::to_string(p.svc),
         "in schwarz mode the SVC rings must be at least as wide as the cut-off (D72)");
  const double h = lj.a0_A * units::m_per_A;
  const int bx0 = (p.ncx - p.nbx) / 2, by0 = (p.ncy - p.nby) / 2;
  std::filesystem::create_directories(o.out_dir);
  const std::string out = o.out_dir;

  Solver<2> s;
  s.grid.h = h;
  s.grid.origin = Eigen::Vector2d(-2 * h, -2 * h);
  s.grid.n = {p.ncx + 5, p.ncy + 5};
  s.materials.push_back(std::make_shared<LinearElastic>(lj.density, lj.E(), lj.nu())); // D76
  for (int jy = 0; jy < p.ncy; ++jy)
    for (int ix = 0; ix < p.ncx; ++ix)
      s.particles.add(Eigen::Vector2d((ix + 0.5) * h, (jy + 0.5) * h),
                      Eigen::Vector2d::Constant(0.5 * h), lj.density * h * h, h * h, 0);
  NodeBC<2> left, corner, right;
  left.name = "left";
  left.lo = Eigen::Vector2d(-0.1 * h, -10 * h);
  left.hi = Eigen::Vector2d(0.1 * h, (p.ncy + 10) * h);
  left.mask = {true, false};
  corner.name = "corner";
  corner.lo = Eigen::Vector2d(-0.1 * h, -0.1 * h);
  corner.hi = Eigen::Vector2d(0.1 * h, 0.1 * h);
  corner.mask = {false, true};
  right.name = "right";
  right.lo = Eigen::Vector2d((p.ncx - 0.1) * h, -10 * h);
  right.hi = Eigen::Vector2d((p.ncx + 1.1) * h, (p.ncy + 10) * h); // padding column (D77)
  right.mask = {true, false};
  s.bcs = {left, corner, right};
  const double L = p.ncx * h;
  const double omega1 = M_PI * std::sqrt(lj.strip_modulus() / lj.density) / L;
  const double damping = 2 * p.damping_fraction * omega1; // D75
  Config c;
  c.md_setup = lj_fcc_block_commands(lj, p.nbx, p.nby, p.nz, p.mass, p.eps, p.sig, p.rc);
  c.md_offset = Eigen::Vector2d(bx0 * h + 0.25 * h, by0 * h + 0.25 * h);
  c.svc_rings = p.svc;
  c.ivc_rings = p.ivc;
  c.substeps = p.substeps;
  c.dt = p.substeps * p.dtau_fs * units::s_per_fs;
  c.mode = p.mode == "schwarz" ? Mode::schwarz : Mode::neumann;
  c.interior_temperature = p.temperature;
  c.interior_damp_fs = damping > 0 ? 1.0 / damping / units::s_per_fs : 0.0;
  c.ivc_damp_fs = damping > 0 ? c.interior_damp_fs : 1000.0;
  if (p.temperature > 0 && c.interior_damp_fs <= 0) c.interior_damp_fs = 1000.0;
  c.continuum_damping = damping;
  c.lammps_log = out + "/lammps.log";
  const double cfl_dt = 0.5 * h / std::sqrt(lj.C11 / lj.density);
  if (c.dt > cfl_dt)
    fail(src, "substeps", std::to_string(p.substeps),
         "substeps x md_timestep_fs exceeds the continuum CFL step " +
             std::to_string(cfl_dt / units::s_per_fs) + " fs");
  Coupler cp(s, c);
  cp.setup();

  // Displacement gradients of eqs. 6.3-6.7 (D79): all continuum particles and all atoms
  // (projected on x, y) on a bilinear grid aligned with the continuum grid, updated at every
  // coupled step. IVC probes receive gradients but do not enter the nodal fit (their position
  // is a block-averaged copy of their atoms, D73).
  const std::size_t ncont = s.particles.size();
  std::vector<int> pzone(ncont, static_cast<int>(Zone::none));
  for (const Cell& cell : cp.cells())
    pzone[cell.particle] = static_cast<int>(cell.zone);
  GradientTracker grad(s.grid.origin, p.gradient_cells * h);
  std::vector<Eigen::Vector2d> gx;
  std::vector<int> gids;
  std::vector<Eigen::Vector3d> gax, gav;
  auto gather = [&] {
    cp.atoms(gids, gax, gav);
    gx.resize(ncont + gax.size());
    for (std::size_t k = 0; k < ncont; ++k)
      gx[k] = s.particles.x[k];
    for (std::size_t k = 0; k < gax.size(); ++k)
      gx[ncont + k] = cp.to_continuum(gax[k]);
  };
  gather();
  {
    std::vector<char> contributes(gx.size(), 1);
    for (std::size_t k = 0; k < ncont; ++k)
      contributes[k] = pzone[k] != static_cast<int>(Zone::ivc);
    grad.reset(gx, contributes);
  }
  double grad_wall = 0.0;
  // The four components and the support flag of particles [b, e) as VTU point arrays.
  auto grad_arrays = [&](std::size_t b, std::size_t e) {
    std::vector<PointArray> a = {{"du_dX", 1, {}},
                                 {"du_dY", 1, {}},
                                 {"dv_dX", 1, {}},
                                 {"dv_dY", 1, {}},
                                 {"gradient_supported", 1, {}}};
    for (std::size_t k = b; k < e; ++k) {
      const Eigen::Matrix2d H = grad.H(k);
      a[0].values.push_back(H(0, 0));
      a[1].values.push_back(H(0, 1));
      a[2].values.push_back(H(1, 0));
      a[3].values.push_back(H(1, 1));
      a[4].values.push_back(grad.supported()[k]);
    }
    return a;
  };

  const double ps = 1e-12;
  const double t_settle = p.settle_ps * ps, t_load = p.load_ps * ps;
  const double t_end = t_settle + t_load + p.hold_ps * ps;
  const long nsteps = std::max(1L, std::lround(t_end / c.dt));
  const long frame_every = p.frames > 0 ? std::max(1L, nsteps / p.frames) : nsteps + 1;
  CoupleSummary r;
  std::ostringstream prof;
  prof.precision(10);
  prof << "time_s,x_m,ux_m,source,dux_dX\n";
  const int jmid = by0 + p.nby / 2;
  auto profile = [&] {
    for (std::size_t k = 0; k < s.particles.size(); ++k) {
      const auto& x0 = s.particles.x0[k];
      if (static_cast<int>(std::floor(x0[1] / h)) != jmid) continue;
      prof << s.time << ',' << x0[0] << ',' << s.particles.x[k][0] - x0[0] << ",continuum,"
           << grad.H(k)(0, 0) << '\n';
    }
    std::vector<int> ids;
    std::vector<Eigen::Vector3d> x, v;
    cp.atoms(ids, x, v);
    std::map<int, std::array<double, 4>> acc; // cell i -> (x0 sum, u sum, n, du/dX sum)
    for (std::size_t k = 0; k < x.size(); ++k) {
      const Eigen::Vector2d x0 = cp.to_continuum(cp.atoms_initial()[k]);
      if (static_cast<int>(std::floor(x0[1] / h)) != jmid) continue;
      auto& a = acc[static_cast<int>(std::floor(x0[0] / h))];
      a[0] += x0[0];
      a[1] += (cp.to_continuum(x[k]) - x0)[0];
      a[2] += 1;
      a[3] += grad.H(ncont + k)(0, 0);
    }
    for (const auto& [i, a] : acc)
      prof << s.time << ',' << a[0] / a[2] << ',' << a[1] / a[2] << ",md," << a[3] / a[2] << '\n';
  };
  const auto w0 = std::chrono::steady_clock::now();
  auto last = w0;
  for (long k = 0; k < nsteps; ++k) {
    const double tl = s.time + 0.5 * c.dt - t_settle;
    s.bcs[2].velocity[0] = (tl > 0 && tl < t_load)
                               ? p.strain * L / t_load * (1 - std::cos(2 * M_PI * tl / t_load))
                               : 0.0;
    cp.step();
    {
      const auto g0 = std::chrono::steady_clock::now();
      gather();
      grad.update(gx);
      grad_wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - g0).count();
    }
    if ((k + 1) % frame_every == 0) {
      const std::string idx = std::to_string((k + 1) / frame_every);
      const std::string f = out + "/atoms_" + idx + ".vtu";
      cp.write_atoms_vtu(f, grad_arrays(ncont, gx.size()));
      r.frames.push_back(f);
      const std::string fp = out + "/particles_" + idx + ".vtu";
      write_particles_vtu(fp, s, pzone, grad_arrays(0, ncont));
      r.particle_frames.push_back(fp);
      profile();
    }
    const auto now = std::chrono::steady_clock::now();
    if (o.progress && (std::chrono::duration<double>(now - last).count() > 2 || k + 1 == nsteps)) {
      last = now;
      const double el = std::chrono::duration<double>(now - w0).count();
      std::fprintf(stderr, "step %ld/%ld  t = %.2f ps  elapsed %.1f s  ETA %.1f s\n", k + 1, nsteps,
                   s.time / ps, el,
                   el / static_cast<double>(k + 1) * static_cast<double>(nsteps - k - 1));
    }
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  r.steps = nsteps;
  r.time_s = s.time;
  r.outside_share = cp.timing().outside_share();
  r.atoms = cp.zone_counts();
  r.particles = s.particles.size();
  r.energy = cp.energy_log().back();
  r.reaction_left = s.bcs[0].reaction[0];
  r.strain_modulus_pa = lj.strip_modulus();
  r.profile_csv = out + "/profile.csv";
  r.energy_csv = out + "/energy.csv";
  r.lammps_log = c.lammps_log;
  r.summary_json = out + "/summary.json";
  pnc::write_text_atomically(r.profile_csv, prof.str());
  cp.write_energy_csv(r.energy_csv);
  json sj;
  sj["input"] = src;
  sj["short"] = o.short_mode;
  sj["steps"] = r.steps;
  sj["time_s"] = r.time_s;
  sj["wall_s"] = r.wall_s;
  sj["outside_lammps_share"] = r.outside_share;
  sj["atoms"] = {{"interior", r.atoms[0]}, {"ivc", r.atoms[1]}, {"svc", r.atoms[2]}};
  sj["particles"] = r.particles;
  sj["lj_fcc"] = {{"a0_A", lj.a0_A}, {"C11_Pa", lj.C11}, {"C12_Pa", lj.C12},     {"C44_Pa", lj.C44},
                  {"E_Pa", lj.E()},  {"nu", lj.nu()},    {"density", lj.density}};
  sj["reaction_left_N_per_m"] = r.reaction_left;
  sj["gradient"] = {
      {"spacing_m", grad.spacing()}, {"increments", grad.increments()}, {"wall_s", grad_wall}};
  sj["particle_frames"] = r.particle_frames;
  sj["expected_reaction_N_per_m"] = -lj.strip_modulus() * p.strain * p.ncy * h;
  const EnergyRow& e = r.energy;
  sj["energy_J"] = {{"cont_kinetic", e.cont_kinetic},
                    {"cont_strain", e.cont_strain},
                    {"md_kinetic", e.md_kinetic},
                    {"md_potential", e.md_potential},
                    {"work_boundary", e.work_boundary},
                    {"work_cont_on_md", e.work_cont_on_md},
                    {"work_md_on_cont", e.work_md_on_cont},
                    {"heat_removed_int", e.heat_removed_int},
                    {"heat_removed_ivc", e.heat_removed_ivc},
                    {"heat_removed_cont", e.heat_removed_cont},
                    {"balance", e.balance()}};
  pnc::write_text_atomically(r.summary_json, sj.dump(2) + "\n");
  if (o.plot) {
#ifdef PNC_ESCM_PLOT_SCRIPT
    const std::string cmd = std::string(PNC_GIMP_PYTHON) + " " + PNC_ESCM_PLOT_SCRIPT + " '" + out +
                            "' > '" + out + "/plot.log' 2>&1";
    if (std::system(cmd.c_str()) == 0) {
      r.plots = {out + "/profile.png", out + "/energy.png"};
    } else {
      r.plot_warning =
          "plots not written (needs " PNC_GIMP_PYTHON " with matplotlib; see " + out + "/plot.log)";
    }
#else
    r.plot_warning = "plots not configured";
#endif
  }
  return r;
}

} // namespace pnc::gimp::escm
