// ESCM coupling of the 2-D GIMP solver to an in-process LAMMPS instance (escm.hpp,
// docs/escm.md, decisions D70-D79).
#include "pnc/gimp_coupler/escm.hpp"

#include "pnc/core/atomic_file.hpp"

#include <lammps/library.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

namespace pnc::gimp::escm {

namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

[[noreturn]] void bad(const std::string& field, const std::string& value, const std::string& rule) {
  throw std::runtime_error("escm: config field '" + field + "': value '" + value + "': " + rule);
}

/// Zero-stress material of the IVC material points (D70): they carry position and (a tiny)
/// mass only; the stiffness of the IVC region is the atoms'.
class Probe final : public Material {
public:
  explicit Probe(double rho) : Material(rho) {}
  std::string type() const override { return "escm_probe"; }
  void update(const Mat3&, const Mat3&, const double*, double*, Mat3& sigma,
              double& W) const override {
    sigma.setZero();
    W = 0.0;
  }
  double wave_speed() const override { return 0.0; }
  double youngs_modulus() const override { return std::nan(""); }
  double poisson_ratio() const override { return std::nan(""); }
};

#if defined(LAMMPS_BIGBIG)
using lmp_tag = int64_t;
#else
using lmp_tag = int;
#endif
#if defined(LAMMPS_SMALLSMALL)
using lmp_step = int;
#else
using lmp_step = int64_t;
#endif

} // namespace

struct Coupler::Impl {
  Solver<2>& solver;
  Config cfg;
  void* lmp = nullptr;
  std::vector<Cell> cells;
  std::vector<int> ivc_cells;          // indices into cells
  std::vector<int> cell_of_id;         // id -> cell index or -1 (INT)
  std::vector<Zone> zone_of_id;        // id -> zone
  std::vector<Eigen::Vector3d> x_init; // id - 1 -> initial position, A
  int natoms = 0;
  double Lz_A = 0.0;
  double dtau_fs = 0.0;
  // Gamma nodes
  std::vector<std::int64_t> gamma;
  std::vector<std::vector<std::pair<int, double>>> gamma_cells; // per Gamma node: (ivc k, w)
  // Callback accumulators per IVC cell (index into ivc_cells)
  std::vector<Eigen::Vector2d> csum;
  std::vector<double> fx, fy; // per-atom force by ivc slot, kcal/mol/A
  long block_start = 0;
  int nsub = 0;
  Timing timing;
  std::vector<EnergyRow> log;
  EnergyRow acc; // running sums
  double pe0 = 0.0;
  std::array<int, 3> counts{};
  bool ready = false;
  // Checkpoints (CouplerState): Langevin re-creations so far and the heat their predecessors
  // removed, J (slab).
  int segment = 0;
  double heat_off_int = 0.0, heat_off_ivc = 0.0;

  explicit Impl(Solver<2>& s, Config c) : solver(s), cfg(std::move(c)) {}

  void cmd(const std::string& c) { lammps_command(lmp, c.c_str()); }

  static void callback(void* ptr, lmp_step step, int nlocal, lmp_tag* ids, double** x,
                       double** fext) {
    auto* self = static_cast<Impl*>(ptr);
    const auto t0 = Clock::now();
    const bool count = step > self->block_start;
    for (int i = 0; i < nlocal; ++i) {
      const int k = self->cell_of_id[static_cast<std::size_t>(ids[i])];
      if (k < 0) {
        fext[i][0] = fext[i][1] = fext[i][2] = 0.0;
        continue;
      }
      fext[i][0] = self->fx[static_cast<std::size_t>(k)];
      fext[i][1] = self->fy[static_cast<std::size_t>(k)];
      fext[i][2] = 0.0;
      if (count) {
        auto& s = self->csum[static_cast<std::size_t>(k)];
        s[0] += x[i][0];
        s[1] += x[i][1];
      }
    }
    if (count) ++self->nsub;
    self->timing.callback += seconds(t0, Clock::now());
  }

  // Centroids of the IVC cells now (A), from the local arrays.
  std::vector<Eigen::Vector2d> centroids() const {
    const int nlocal = lammps_extract_setting(lmp, "nlocal");
    auto* id = static_cast<lmp_tag*>(lammps_extract_atom(lmp, "id"));
    auto** x = static_cast<double**>(lammps_extract_atom(lmp, "x"));
    std::vector<Eigen::Vector2d> c(ivc_cells.size(), Eigen::Vector2d::Zero());
    for (int i = 0; i < nlocal; ++i) {
      const int k = cell_of_id[static_cast<std::size_t>(id[i])];
      if (k >= 0) c[static_cast<std::size_t>(k)] += Eigen::Vector2d(x[i][0], x[i][1]);
    }
    for (std::size_t k = 0; k < c.size(); ++k)
      c[k] /= static_cast<double>(cells[static_cast<std::size_t>(ivc_cells[k])].atoms.size());
    return c;
  }

  double compute_scalar(const char* id) const {
    auto* p =
        static_cast<double*>(lammps_extract_compute(lmp, id, LMP_STYLE_GLOBAL, LMP_TYPE_SCALAR));
    return p ? *p : std::nan("");
  }
  double fix_scalar(const char* id) const {
    auto* p =
        static_cast<double*>(lammps_extract_fix(lmp, id, LMP_STYLE_GLOBAL, LMP_TYPE_SCALAR, 0, 0));
    if (!p) return 0.0;
    const double v = *p;
    lammps_free(p);
    return v;
  }

  void validate() {
    const auto& c = cfg;
    if (c.md_setup.empty())
      bad("md_setup", "[]", "LAMMPS commands creating the MD region are required");
    for (const auto& s : c.md_setup) {
      std::istringstream is(s);
      std::string w;
      is >> w;
      for (const char* forbidden : {"run", "minimize", "fix", "timestep", "clear", "quit", "shell",
                                    "include", "jump", "label", "next", "rerun", "write_restart"})
        if (w == forbidden)
          bad("md_setup", s, "only commands that build the box, atoms and force field are allowed");
    }
    if (c.svc_rings < 1) bad("svc_rings", std::to_string(c.svc_rings), "must be >= 1");
    if (c.ivc_rings < 1) bad("ivc_rings", std::to_string(c.ivc_rings), "must be >= 1");
    if (c.substeps < 1) bad("substeps", std::to_string(c.substeps), "must be >= 1");
    if (!(c.dt > 0) || !std::isfinite(c.dt)) bad("dt", std::to_string(c.dt), "must be > 0 (s)");
    if (!(c.interior_temperature >= 0) || !std::isfinite(c.interior_temperature))
      bad("interior_temperature", std::to_string(c.interior_temperature), "must be >= 0 (K)");
    if (!(c.ivc_damp_fs > 0) || !std::isfinite(c.ivc_damp_fs))
      bad("ivc_damp_fs", std::to_string(c.ivc_damp_fs), "must be > 0 (fs)");
    if (!std::isfinite(c.interior_damp_fs))
      bad("interior_damp_fs", std::to_string(c.interior_damp_fs), "must be finite");
    if (c.seed <= 0 || c.seed > 800000000)
      bad("seed", std::to_string(c.seed), "must be in [1, 8e8] (LAMMPS random seeds)");
    if (!(c.continuum_damping >= 0))
      bad("continuum_damping", std::to_string(c.continuum_damping), "must be >= 0 (1/s)");
    if (!(c.probe_mass_fraction > 0 && c.probe_mass_fraction <= 1))
      bad("probe_mass_fraction", std::to_string(c.probe_mass_fraction), "must be in (0, 1]");
    if (c.lammps_log.find_first_of(" \t\n'\"") != std::string::npos)
      bad("lammps_log", c.lammps_log, "must not contain blanks or quotes");
    dtau_fs = c.dt / c.substeps / units::s_per_fs;
    if (!(dtau_fs > 1e-6 && dtau_fs < 100))
      bad("dt", std::to_string(c.dt), "dt / substeps must be an MD step in (1e-6, 100) fs");
    const auto& g = solver.grid;
    for (std::size_t p = 0; p < solver.particles.size(); ++p)
      if (std::abs(solver.particles.l[p][0] - 0.5 * g.h) > 1e-9 * g.h ||
          std::abs(solver.particles.l[p][1] - 0.5 * g.h) > 1e-9 * g.h)
        bad("particles", std::to_string(p),
            "ESCM needs one particle per cell, half-length h/2 (D70)");
  }

  void setup() {
    validate();
    auto& g = solver.grid;
    auto& P = solver.particles;
    // Particle of each grid cell.
    std::map<std::pair<int, int>, std::size_t> cellmap;
    auto cell_of = [&](const Eigen::Vector2d& x) {
      return std::pair<int, int>{static_cast<int>(std::floor((x[0] - g.origin[0]) / g.h)),
                                 static_cast<int>(std::floor((x[1] - g.origin[1]) / g.h))};
    };
    for (std::size_t p = 0; p < P.size(); ++p) {
      const auto ij = cell_of(P.x[p]);
      if (!cellmap.emplace(ij, p).second)
        bad("particles", std::to_string(p), "two particles in one grid cell (D70)");
    }
    // LAMMPS.
    std::vector<std::string> args = {"escm", "-screen", "none", "-log", cfg.lammps_log, "-nocite"};
    std::vector<char*> argv;
    for (auto& a : args)
      argv.push_back(a.data());
    lmp = lammps_open_no_mpi(static_cast<int>(argv.size()), argv.data(), nullptr);
    if (!lmp) throw std::runtime_error("escm: could not start LAMMPS");
    for (const auto& c : cfg.md_setup)
      cmd(c);
    // Checks of what md_setup built (before any command of ours that depends on it).
    const char* u = static_cast<const char*>(lammps_extract_global(lmp, "units"));
    if (!u || std::string(u) != "real")
      bad("md_setup", "units", "the MD region must use `units real`");
    if (lammps_extract_setting(lmp, "dimension") != 3) bad("md_setup", "dimension", "must be 3");
    double lo[3], hi[3], xy, yz, xz;
    int per[3], changed;
    lammps_extract_box(lmp, lo, hi, &xy, &yz, &xz, per, &changed);
    if (per[0] || per[1] || !per[2])
      bad("md_setup", "boundary", "x and y must be non-periodic, z periodic (the slab)");
    if (xy != 0 || xz != 0 || yz != 0) bad("md_setup", "box", "must be orthogonal");
    Lz_A = hi[2] - lo[2];
    natoms = static_cast<int>(lammps_get_natoms(lmp));
    if (natoms <= 0) bad("md_setup", "atoms", "no atoms");
    if (lammps_extract_setting(lmp, "tagint") != static_cast<int>(sizeof(lmp_tag)))
      throw std::runtime_error("escm: LAMMPS tagint size differs from the build's");
    std::vector<lmp_tag> ids(static_cast<std::size_t>(natoms));
    std::vector<double> xs(static_cast<std::size_t>(natoms) * 3);
    std::string nid = "id", nx = "x";
    lammps_gather_atoms(lmp, nid.data(), 0, 1, ids.data());
    lammps_gather_atoms(lmp, nx.data(), 1, 3, xs.data());
    // gather_atoms orders by id: requires ids 1..natoms.
    for (int i = 0; i < natoms; ++i)
      if (ids[static_cast<std::size_t>(i)] != i + 1)
        bad("md_setup", "atom ids", "must be 1..n without gaps (reset_atom_ids)");
    x_init.resize(static_cast<std::size_t>(natoms));
    std::map<std::pair<int, int>, std::vector<int>> atoms_of_cell;
    for (int i = 0; i < natoms; ++i) {
      const Eigen::Vector3d xa(xs[3 * i], xs[3 * i + 1], xs[3 * i + 2]);
      x_init[static_cast<std::size_t>(i)] = xa;
      const Eigen::Vector2d xc = cfg.md_offset + units::m_per_A * xa.head<2>();
      atoms_of_cell[cell_of(xc)].push_back(i + 1);
    }
    int imin = 1 << 30, imax = -(1 << 30), jmin = imin, jmax = imax;
    for (const auto& [ij, v] : atoms_of_cell) {
      imin = std::min(imin, ij.first);
      imax = std::max(imax, ij.first);
      jmin = std::min(jmin, ij.second);
      jmax = std::max(jmax, ij.second);
    }
    const int rings = cfg.svc_rings + cfg.ivc_rings;
    if (imax - imin + 1 < 2 * rings + 1 || jmax - jmin + 1 < 2 * rings + 1)
      bad("md_setup", "atom block", "narrower than 2 (svc_rings + ivc_rings) + 1 cells");
    // Cells of the block: zone by ring; every cell needs a particle and atoms.
    cell_of_id.assign(static_cast<std::size_t>(natoms) + 1, -1);
    zone_of_id.assign(static_cast<std::size_t>(natoms) + 1, Zone::none);
    std::vector<char> remove(P.size(), 0);
    cells.clear();
    for (int j = jmin; j <= jmax; ++j)
      for (int i = imin; i <= imax; ++i) {
        const int ring = std::min({i - imin, imax - i, j - jmin, jmax - j});
        const Zone z = ring < cfg.svc_rings ? Zone::svc : ring < rings ? Zone::ivc : Zone::interior;
        const auto it = cellmap.find({i, j});
        if (it == cellmap.end())
          bad("particles", "cell (" + std::to_string(i) + ", " + std::to_string(j) + ")",
              "the atom block needs a continuum particle in each of its cells (D70)");
        const auto at = atoms_of_cell.find({i, j});
        if (z != Zone::interior && (at == atoms_of_cell.end() || at->second.empty()))
          bad("md_setup", "cell (" + std::to_string(i) + ", " + std::to_string(j) + ")",
              "every volume cell needs atoms");
        const std::vector<int> none;
        const auto& ats = at == atoms_of_cell.end() ? none : at->second;
        for (int id : ats)
          zone_of_id[static_cast<std::size_t>(id)] = z;
        counts[static_cast<int>(z)] += static_cast<int>(ats.size());
        if (z == Zone::interior) {
          remove[it->second] = 1;
          continue;
        }
        Cell c;
        c.zone = z;
        c.particle = it->second; // re-indexed below
        c.ij = {i, j};
        c.atoms = ats;
        Eigen::Vector2d s = Eigen::Vector2d::Zero();
        for (int id : ats)
          s += x_init[static_cast<std::size_t>(id - 1)].head<2>();
        c.c0_A = s / static_cast<double>(ats.size());
        c.mean_A = c.prev_mean_A = c.c0_A;
        c.force_N.setZero();
        c.atom_force.setZero();
        c.velocity_mps.setZero();
        cells.push_back(c);
      }
    // Atoms outside the block's cells cannot exist (the block is their bounding box).
    // Remove INT particles, re-index, turn IVC particles into probes.
    std::vector<std::size_t> newidx(P.size(), static_cast<std::size_t>(-1));
    Particles<2> Q;
    for (std::size_t p = 0; p < P.size(); ++p) {
      if (remove[p]) continue;
      newidx[p] = Q.size();
      Q.add(P.x[p], P.l[p], P.m[p], P.V0[p], P.mat[p], P.v[p]);
      Q.x0.back() = P.x0[p];
      Q.F.back() = P.F[p];
    }
    for (auto& tr : solver.tractions) {
      std::vector<std::size_t> keep;
      for (auto p : tr.particles)
        if (!remove[p]) keep.push_back(newidx[p]);
      tr.particles = keep;
    }
    double rho_max = 0;
    for (const auto& m : solver.materials)
      rho_max = std::max(rho_max, m->density());
    const int probe = static_cast<int>(solver.materials.size());
    solver.materials.push_back(std::make_shared<Probe>(rho_max * cfg.probe_mass_fraction));
    for (std::size_t k = 0; k < cells.size(); ++k) {
      auto& c = cells[k];
      c.particle = newidx[c.particle];
      if (c.zone == Zone::ivc) {
        const int slot = static_cast<int>(ivc_cells.size());
        ivc_cells.push_back(static_cast<int>(k));
        Q.m[c.particle] *= cfg.probe_mass_fraction;
        Q.mat[c.particle] = probe;
        for (int id : c.atoms)
          cell_of_id[static_cast<std::size_t>(id)] = slot;
      }
    }
    P = std::move(Q);
    solver.initialize();
    // Gamma (D71): the corner nodes of the IVC cells, fixed at setup; weight of cell p at node
    // i = 1 / (number of IVC cells sharing i) (the reference weights S_ip = 1/4 of a particle
    // at its cell centre, normalised over the IVC cells: a partition of unity).
    {
      std::map<std::int64_t, std::size_t> gidx;
      gamma.clear();
      gamma_cells.clear();
      for (std::size_t k = 0; k < ivc_cells.size(); ++k) {
        const auto& c = cells[static_cast<std::size_t>(ivc_cells[k])];
        for (int b = 0; b < 2; ++b)
          for (int a = 0; a < 2; ++a) {
            const std::int64_t node = g.index({c.ij[0] + a, c.ij[1] + b});
            auto [it, fresh] = gidx.emplace(node, gamma.size());
            if (fresh) {
              gamma.push_back(node);
              gamma_cells.emplace_back();
            }
            gamma_cells[it->second].emplace_back(static_cast<int>(k), 1.0);
          }
      }
      for (auto& gc : gamma_cells)
        for (auto& kw : gc)
          kw.second = 1.0 / static_cast<double>(gc.size());
    }
    csum.assign(ivc_cells.size(), Eigen::Vector2d::Zero());
    fx.assign(ivc_cells.size(), 0.0);
    fy.assign(ivc_cells.size(), 0.0);

    // Groups, fixes, computes.
    auto group = [&](const std::string& name, Zone z) {
      std::ostringstream s;
      int n = 0;
      for (int id = 1; id <= natoms; ++id) {
        if (zone_of_id[static_cast<std::size_t>(id)] != z) continue;
        if (n % 400 == 0) {
          if (n) cmd(s.str());
          s.str("");
          s << "group " << name << " id";
        }
        s << ' ' << id;
        ++n;
      }
      if (n)
        cmd(s.str());
      else
        cmd("group " + name + " empty");
    };
    group("escm_svc", Zone::svc);
    group("escm_ivc", Zone::ivc);
    group("escm_int", Zone::interior);
    cmd("group escm_free union escm_ivc escm_int");
    if (cfg.mode == Mode::neumann) // D71
      cmd("neigh_modify exclude group escm_svc escm_svc");
    if (cfg.mode == Mode::neumann) cmd("neigh_modify exclude group escm_svc escm_free");
    std::ostringstream s;
    s.precision(17);
    s << "timestep " << dtau_fs;
    cmd(s.str());
    cmd("compute escm_ke escm_free ke");
    cmd("compute escm_pea escm_free pe/atom");
    cmd("compute escm_pe escm_free reduce sum c_escm_pea");
    cmd("fix escm_nve escm_free nve");
    // Checkpoints need a fixed local atom order (a spatial sort at a restart's set-up would
    // order the atoms differently from the run that wrote it).
    cmd("atom_modify sort 0 0.0");
    segment = 0;
    heat_off_int = heat_off_ivc = 0.0;
    langevin_fixes();
    cmd("fix escm_ext all external pf/callback 1 1");
    lammps_set_fix_external_callback(lmp, "escm_ext", &Impl::callback, this);
    cmd("fix escm_svcnve escm_svc nve");
    cmd("fix escm_svcsf escm_svc setforce 0.0 0.0 0.0");
    cmd("thermo_style custom step c_escm_ke c_escm_pe");
    cmd("thermo_modify norm no");
    cmd("thermo " + std::to_string(cfg.substeps));
    block_start = 0;
    cmd("run 0");
    pe0 = compute_scalar("escm_pe");
    acc = EnergyRow{};
    solver.update_energies();
    const double Lz_m = Lz_A * units::m_per_A;
    acc.initial = (solver.energy.kinetic + solver.energy.strain) * Lz_m +
                  compute_scalar("escm_ke") * units::J_per_kcalmol;
    ready = true;
  }

  // The Langevin fixes of INT and IVC; re-created at each checkpoint (same IDs, same place in
  // the fix list) with the seeds of the segment, so that a resumed run draws the same numbers.
  void langevin_fixes() {
    auto seed = [&](int offset) {
      const long long k = static_cast<long long>(cfg.seed) - 1 + offset + 7919LL * 2 * segment;
      return 1 + k % 899999999LL; // RanMars: 0 < seed <= 9e8
    };
    std::ostringstream s;
    s.precision(17);
    if (cfg.interior_damp_fs > 0 && counts[0] > 0) {
      s << "fix escm_lint escm_int langevin " << cfg.interior_temperature << ' '
        << cfg.interior_temperature << ' ' << cfg.interior_damp_fs << ' ' << seed(0)
        << " tally yes";
      cmd(s.str());
    }
    s.str("");
    s << "fix escm_livc escm_ivc langevin 0.0 0.0 " << cfg.ivc_damp_fs << ' ' << seed(1)
      << " tally yes";
    cmd(s.str());
  }

  // Per-atom arrays by id - 1 straight from the local arrays (one MPI rank: every atom is
  // local; lammps_scatter_atoms goes through the atom map, which can name a ghost copy).
  void check_local() const {
    if (lammps_extract_setting(lmp, "nlocal") != natoms)
      throw std::runtime_error("escm: checkpoints need all atoms on one MPI rank");
    if (lammps_extract_setting(lmp, "imageint") != 4)
      throw std::runtime_error("escm: checkpoints need LAMMPS with 32-bit image flags");
  }
  // LAMMPS image flags (32-bit imageint): 10 bits per axis, offset 512.
  static constexpr int img_max = 512, img_bits = 10, img_mask = 1023;

  std::vector<double> gather(const char* name, int count) const {
    check_local();
    const int nlocal = natoms;
    auto* id = static_cast<lmp_tag*>(lammps_extract_atom(lmp, "id"));
    std::vector<double> out(static_cast<std::size_t>(natoms) * static_cast<std::size_t>(count));
    const std::string n = name;
    for (int i = 0; i < nlocal; ++i) {
      const std::size_t o = static_cast<std::size_t>(id[i] - 1) * static_cast<std::size_t>(count);
      if (n == "image") {
        const int im = static_cast<int*>(lammps_extract_atom(lmp, "image"))[i];
        out[o] = (im & img_mask) - img_max;
        out[o + 1] = ((im >> img_bits) & img_mask) - img_max;
        out[o + 2] = (im >> (2 * img_bits)) - img_max;
      } else if (n == "type") {
        out[o] = static_cast<int*>(lammps_extract_atom(lmp, "type"))[i];
      } else {
        auto** a = static_cast<double**>(lammps_extract_atom(lmp, name));
        for (int c = 0; c < count; ++c)
          out[o + static_cast<std::size_t>(c)] = a[i][c];
      }
    }
    return out;
  }

  void scatter(const char* name, const std::vector<double>& v) const {
    check_local();
    auto* id = static_cast<lmp_tag*>(lammps_extract_atom(lmp, "id"));
    const std::string n = name;
    for (int i = 0; i < natoms; ++i) {
      const std::size_t o = static_cast<std::size_t>(id[i] - 1) * 3;
      if (n == "image") {
        static_cast<int*>(lammps_extract_atom(lmp, "image"))[i] =
            (static_cast<int>(v[o]) + img_max) |
            ((static_cast<int>(v[o + 1]) + img_max) << img_bits) |
            ((static_cast<int>(v[o + 2]) + img_max) << (2 * img_bits));
      } else {
        auto** a = static_cast<double**>(lammps_extract_atom(lmp, name));
        for (int c = 0; c < 3; ++c)
          a[i][c] = v[o + static_cast<std::size_t>(c)];
      }
    }
  }

  // Puts atoms into LAMMPS and makes a restart point: x, v, image; new Langevin fixes
  // (segment); `run 0` (box, neighbour lists, ghosts rebuilt from x; its forces are discarded);
  // the saved forces back.
  void apply_atoms(const std::vector<double>& x, const std::vector<double>& v,
                   const std::vector<double>& f, const std::vector<double>& image) {
    scatter("x", x);
    scatter("v", v);
    scatter("image", image);
    langevin_fixes();
    block_start = static_cast<long>(lammps_get_thermo(lmp, "step"));
    cmd("run 0 post no");
    scatter("f", f);
  }

  CouplerState save() const {
    CouplerState st;
    for (int k : ivc_cells) {
      const Cell& c = cells[static_cast<std::size_t>(k)];
      st.mean_A.push_back(c.mean_A);
      st.prev_mean_A.push_back(c.prev_mean_A);
      st.velocity_mps.push_back(c.velocity_mps);
      st.force_N.push_back(c.force_N);
      st.atom_force.push_back(c.atom_force);
    }
    st.log = log;
    st.acc = acc;
    st.pe0 = pe0;
    st.heat_offset_int = heat_off_int;
    st.heat_offset_ivc = heat_off_ivc;
    st.prescribed_work = solver.prescribed_work;
    st.segment = segment;
    st.md_step = static_cast<long>(lammps_get_thermo(lmp, "step"));
    st.timing = timing;
    st.x = gather("x", 3);
    st.v = gather("v", 3);
    st.f = gather("f", 3);
    const auto im = gather("image", 3), ty = gather("type", 1);
    st.image.assign(im.begin(), im.end());
    st.type.assign(ty.begin(), ty.end());
    return st;
  }

  CouplerState checkpoint() {
    if (!ready) throw std::runtime_error("escm: checkpoint() before setup()");
    const auto x = gather("x", 3), v = gather("v", 3), f = gather("f", 3), im = gather("image", 3);
    ++segment;
    heat_off_int = acc.heat_removed_int;
    heat_off_ivc = acc.heat_removed_ivc;
    apply_atoms(x, v, f, im);
    return save();
  }

  void restore(const CouplerState& st) {
    if (!ready) throw std::runtime_error("escm: restore() before setup()");
    const std::size_t n3 = 3 * static_cast<std::size_t>(natoms);
    auto bad_size = [](const std::string& what, std::size_t got, std::size_t want) {
      throw std::runtime_error("escm: restore: " + what + " has " + std::to_string(got) +
                               " entries, this set-up needs " + std::to_string(want));
    };
    if (st.x.size() != n3) bad_size("x", st.x.size(), n3);
    if (st.v.size() != n3) bad_size("v", st.v.size(), n3);
    if (st.f.size() != n3) bad_size("f", st.f.size(), n3);
    if (st.image.size() != n3) bad_size("image", st.image.size(), n3);
    if (st.mean_A.size() != ivc_cells.size())
      bad_size("IVC cells", st.mean_A.size(), ivc_cells.size());
    if (st.prev_mean_A.size() != ivc_cells.size() || st.velocity_mps.size() != ivc_cells.size() ||
        st.force_N.size() != ivc_cells.size() || st.atom_force.size() != ivc_cells.size())
      bad_size("IVC cell arrays", st.prev_mean_A.size(), ivc_cells.size());
    if (!st.type.empty()) {
      const auto ty = gather("type", 1);
      for (std::size_t i = 0; i < ty.size() && i < st.type.size(); ++i)
        if (static_cast<int>(ty[i]) != st.type[i])
          throw std::runtime_error("escm: restore: atom " + std::to_string(i + 1) + " has type " +
                                   std::to_string(st.type[i]) + " in the checkpoint, " +
                                   std::to_string(static_cast<int>(ty[i])) + " in this set-up");
    }
    for (std::size_t k = 0; k < ivc_cells.size(); ++k) {
      Cell& c = cells[static_cast<std::size_t>(ivc_cells[k])];
      c.mean_A = st.mean_A[k];
      c.prev_mean_A = st.prev_mean_A[k];
      c.velocity_mps = st.velocity_mps[k];
      c.force_N = st.force_N[k];
      c.atom_force = st.atom_force[k];
      fx[k] = c.atom_force[0];
      fy[k] = c.atom_force[1];
    }
    log = st.log;
    acc = st.acc;
    pe0 = st.pe0;
    heat_off_int = st.heat_offset_int;
    heat_off_ivc = st.heat_offset_ivc;
    solver.prescribed_work = st.prescribed_work;
    segment = st.segment;
    timing = st.timing;
    apply_atoms(st.x, st.v, st.f, std::vector<double>(st.image.begin(), st.image.end()));
  }

  void step() {
    if (!ready) throw std::runtime_error("escm: step() before setup()");
    const auto t0 = Clock::now();
    auto& g = solver.grid;
    auto& P = solver.particles;
    const double dt = cfg.dt;
    const double Lz_m = Lz_A * units::m_per_A;
    // 1. Gamma nodes (fixed, D71) get the velocity of the IVC cells touching them.
    std::vector<Eigen::Vector2d> vg(gamma.size(), Eigen::Vector2d::Zero());
    for (std::size_t i = 0; i < gamma.size(); ++i) {
      for (const auto& [k, w] : gamma_cells[i])
        vg[i] +=
            w *
            cells[static_cast<std::size_t>(ivc_cells[static_cast<std::size_t>(k)])].velocity_mps;
    }
    solver.prescribed_nodes = gamma;
    solver.prescribed_velocity = vg;
    const double w_before = solver.prescribed_work;
    const auto t1 = Clock::now();
    solver.step(dt);
    const auto t2 = Clock::now();
    const double w_md_on_cont = (solver.prescribed_work - w_before) * Lz_m;
    // IVC material points: eq. 4.1 (positions from the MD averages), velocity of the cell.
    for (int k : ivc_cells) {
      const auto& c = cells[static_cast<std::size_t>(k)];
      P.x[c.particle] = P.x0[c.particle] + units::m_per_A * (c.mean_A - c.c0_A);
      P.v[c.particle] = c.velocity_mps;
    }
    if (cfg.continuum_damping > 0) { // D75
      const double f = std::exp(-cfg.continuum_damping * dt);
      double ke = 0.0;
      for (std::size_t p = 0; p < P.size(); ++p) {
        ke += 0.5 * P.m[p] * P.v[p].squaredNorm();
        P.v[p] *= f;
      }
      acc.heat_removed_cont += (1.0 - f * f) * ke * Lz_m;
      solver.update_energies();
    }
    // Forces on the IVC cells (eq. 4.2, D71).
    for (int k : ivc_cells)
      cells[static_cast<std::size_t>(k)].force_N.setZero();
    if (cfg.mode == Mode::neumann)
      for (std::size_t i = 0; i < gamma.size(); ++i)
        for (const auto& [k, w] : gamma_cells[i])
          cells[static_cast<std::size_t>(ivc_cells[static_cast<std::size_t>(k)])].force_N -=
              w * solver.prescribed_reaction[i];
    for (std::size_t k = 0; k < ivc_cells.size(); ++k) {
      auto& c = cells[static_cast<std::size_t>(ivc_cells[k])];
      c.atom_force = c.force_N * Lz_m / units::N_per_kcalmolA / static_cast<double>(c.atoms.size());
      fx[k] = c.atom_force[0];
      fy[k] = c.atom_force[1];
      csum[k].setZero();
    }
    // SVC atoms: velocity v* of the grid at the atom (eq. 4.3, D72), z velocity 0.
    const auto& vs = solver.grid_velocity_star();
    {
      const int nlocal = lammps_extract_setting(lmp, "nlocal");
      auto* id = static_cast<lmp_tag*>(lammps_extract_atom(lmp, "id"));
      auto** x = static_cast<double**>(lammps_extract_atom(lmp, "x"));
      auto** v = static_cast<double**>(lammps_extract_atom(lmp, "v"));
      for (int i = 0; i < nlocal; ++i) {
        if (zone_of_id[static_cast<std::size_t>(id[i])] != Zone::svc) continue;
        const Eigen::Vector2d xc =
            cfg.md_offset + units::m_per_A * Eigen::Vector2d(x[i][0], x[i][1]);
        const double sx = (xc[0] - g.origin[0]) / g.h, sy = (xc[1] - g.origin[1]) / g.h;
        const int i0 = static_cast<int>(std::floor(sx)), j0 = static_cast<int>(std::floor(sy));
        if (i0 < 0 || j0 < 0 || i0 + 1 >= g.n[0] || j0 + 1 >= g.n[1])
          throw std::runtime_error("escm: an SVC atom left the grid");
        const double fxi = sx - i0, fyj = sy - j0;
        Eigen::Vector2d vel = Eigen::Vector2d::Zero();
        for (int b = 0; b < 2; ++b)
          for (int a = 0; a < 2; ++a) {
            const double w = (a ? fxi : 1 - fxi) * (b ? fyj : 1 - fyj);
            vel += w * vs[static_cast<std::size_t>(g.index({i0 + a, j0 + b}))];
          }
        v[i][0] = vel[0] / units::mps_per_Afs;
        v[i][1] = vel[1] / units::mps_per_Afs;
        v[i][2] = 0.0;
      }
    }
    const std::vector<Eigen::Vector2d> cstart = centroids();
    // 2. MD block.
    nsub = 0;
    block_start = static_cast<long>(lammps_get_thermo(lmp, "step"));
    const auto t3 = Clock::now();
    const double cb0 = timing.callback;
    cmd("run " + std::to_string(cfg.substeps) + " pre no post no");
    const auto t4 = Clock::now();
    if (nsub != cfg.substeps)
      throw std::runtime_error("escm: fix external callback ran " + std::to_string(nsub) +
                               " times in a block of " + std::to_string(cfg.substeps));
    const std::vector<Eigen::Vector2d> cend = centroids();
    // 3. IVC averages (eq. 4.11, D73) and the work of the IVC forces.
    double w_cont_on_md = 0.0;
    for (std::size_t k = 0; k < ivc_cells.size(); ++k) {
      auto& c = cells[static_cast<std::size_t>(ivc_cells[k])];
      const double na = static_cast<double>(c.atoms.size());
      w_cont_on_md += na * c.atom_force.dot(cend[k] - cstart[k]);
      c.prev_mean_A = c.mean_A;
      c.mean_A = csum[k] / (na * cfg.substeps);
      c.velocity_mps = units::m_per_A * (c.mean_A - c.prev_mean_A) / dt;
    }
    // Energies.
    EnergyRow r = acc;
    r.step = solver.steps;
    r.time_s = solver.time;
    r.cont_kinetic = solver.energy.kinetic * Lz_m;
    r.cont_strain = solver.energy.strain * Lz_m;
    r.md_kinetic = compute_scalar("escm_ke") * units::J_per_kcalmol;
    r.md_potential = (compute_scalar("escm_pe") - pe0) * units::J_per_kcalmol;
    r.work_boundary = (solver.energy.boundary_work + solver.energy.external_work) * Lz_m;
    r.work_cont_on_md = acc.work_cont_on_md + w_cont_on_md * units::J_per_kcalmol;
    r.work_md_on_cont = acc.work_md_on_cont + w_md_on_cont;
    r.heat_removed_int = counts[0] > 0 && cfg.interior_damp_fs > 0
                             ? heat_off_int + fix_scalar("escm_lint") * units::J_per_kcalmol
                             : 0.0;
    r.heat_removed_ivc = heat_off_ivc + fix_scalar("escm_livc") * units::J_per_kcalmol;
    acc = r;
    log.push_back(r);
    const auto t5 = Clock::now();
    const double cb = timing.callback - cb0;
    timing.continuum += seconds(t1, t2);
    timing.lammps += seconds(t3, t4) - cb;
    timing.coupling += seconds(t0, t1) + seconds(t2, t3) + seconds(t4, t5);
  }
};

Coupler::Coupler(Solver<2>& solver, Config cfg)
    : d_(std::make_unique<Impl>(solver, std::move(cfg))) {}
Coupler::~Coupler() {
  if (d_->lmp) lammps_close(d_->lmp);
}
void Coupler::setup() {
  d_->setup();
}
void Coupler::step() {
  d_->step();
}
CouplerState Coupler::checkpoint() {
  return d_->checkpoint();
}
void Coupler::restore(const CouplerState& st) {
  d_->restore(st);
}
const std::vector<Cell>& Coupler::cells() const {
  return d_->cells;
}
const Config& Coupler::config() const {
  return d_->cfg;
}
double Coupler::slab_thickness_A() const {
  return d_->Lz_A;
}
double Coupler::md_timestep_fs() const {
  return d_->dtau_fs;
}
const std::vector<EnergyRow>& Coupler::energy_log() const {
  return d_->log;
}
const Timing& Coupler::timing() const {
  return d_->timing;
}
std::array<int, 3> Coupler::zone_counts() const {
  return d_->counts;
}
Zone Coupler::zone_of(int id) const {
  if (id < 1 || id > d_->natoms) return Zone::none;
  return d_->zone_of_id[static_cast<std::size_t>(id)];
}
void* Coupler::lammps() const {
  return d_->lmp;
}
const std::vector<Eigen::Vector3d>& Coupler::atoms_initial() const {
  return d_->x_init;
}
Eigen::Vector2d Coupler::to_continuum(const Eigen::Vector3d& xA) const {
  return d_->cfg.md_offset + units::m_per_A * xA.head<2>();
}

void Coupler::atoms(std::vector<int>& ids, std::vector<Eigen::Vector3d>& x,
                    std::vector<Eigen::Vector3d>& v) const {
  const int n = d_->natoms;
  std::vector<double> xs(static_cast<std::size_t>(n) * 3), vs(xs.size());
  std::string nx = "x", nv = "v";
  lammps_gather_atoms(d_->lmp, nx.data(), 1, 3, xs.data());
  lammps_gather_atoms(d_->lmp, nv.data(), 1, 3, vs.data());
  ids.resize(static_cast<std::size_t>(n));
  x.resize(ids.size());
  v.resize(ids.size());
  for (int i = 0; i < n; ++i) {
    ids[static_cast<std::size_t>(i)] = i + 1;
    x[static_cast<std::size_t>(i)] = Eigen::Vector3d(xs[3 * i], xs[3 * i + 1], xs[3 * i + 2]);
    v[static_cast<std::size_t>(i)] = Eigen::Vector3d(vs[3 * i], vs[3 * i + 1], vs[3 * i + 2]);
  }
}

void Coupler::write_energy_csv(const std::string& path) const {
  std::ostringstream o;
  o.precision(10);
  o << "step,time_s,cont_kinetic_J,cont_strain_J,md_kinetic_J,md_potential_J,work_boundary_J,"
       "work_cont_on_md_J,work_md_on_cont_J,heat_removed_int_J,heat_removed_ivc_J,"
       "heat_removed_cont_J,balance_J\n";
  for (const auto& r : d_->log)
    o << r.step << ',' << r.time_s << ',' << r.cont_kinetic << ',' << r.cont_strain << ','
      << r.md_kinetic << ',' << r.md_potential << ',' << r.work_boundary << ',' << r.work_cont_on_md
      << ',' << r.work_md_on_cont << ',' << r.heat_removed_int << ',' << r.heat_removed_ivc << ','
      << r.heat_removed_cont << ',' << r.balance() << '\n';
  pnc::write_text_atomically(path, o.str());
}

void write_point_cloud_vtu(const std::string& path, const std::vector<Eigen::Vector3d>& x,
                           const std::vector<int>& zone, const std::vector<PointArray>& arrays,
                           int precision) {
  const std::size_t n = x.size();
  auto bad = [&](const std::string& name, std::size_t values, int components) {
    throw std::invalid_argument("write_point_cloud_vtu: array '" + name + "' has " +
                                std::to_string(values) + " values for " + std::to_string(n) +
                                " points x " + std::to_string(components) + " components");
  };
  if (zone.size() != n) bad("zone", zone.size(), 1);
  for (const PointArray& a : arrays)
    if (a.components < 1 || a.values.size() != n * static_cast<std::size_t>(a.components))
      bad(a.name, a.values.size(), a.components);
  std::ostringstream o;
  o.precision(precision);
  o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">\n"
    << "<UnstructuredGrid><Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n"
    << "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : x)
    o << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  o << "</DataArray></Points>\n<Cells><DataArray type=\"Int64\" Name=\"connectivity\" "
       "format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i)
    o << i << '\n';
  o << "</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i)
    o << i + 1 << '\n';
  o << "</DataArray><DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i)
    o << "1\n";
  o << "</DataArray></Cells>\n<PointData><DataArray type=\"Int32\" Name=\"zone\" "
       "format=\"ascii\">\n";
  for (int z : zone)
    o << z << '\n';
  for (const PointArray& a : arrays) {
    o << "</DataArray><DataArray type=\"Float64\" Name=\"" << a.name << "\" NumberOfComponents=\""
      << a.components << "\" format=\"ascii\">\n";
    const auto c = static_cast<std::size_t>(a.components);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t k = 0; k < c; ++k)
        o << (k ? " " : "") << a.values[i * c + k];
      o << '\n';
    }
  }
  o << "</DataArray></PointData>\n</Piece></UnstructuredGrid>\n</VTKFile>\n";
  pnc::write_text_atomically(path, o.str());
}

void Coupler::write_atoms_vtu(const std::string& path, const std::vector<PointArray>& extra) const {
  std::vector<int> ids;
  std::vector<Eigen::Vector3d> x, v;
  atoms(ids, x, v);
  const std::size_t n = x.size();
  std::vector<int> zone(n);
  std::vector<PointArray> arrays = {{"displacement_A", 3, {}}, {"velocity_A_per_fs", 3, {}}};
  for (std::size_t i = 0; i < n; ++i) {
    zone[i] = static_cast<int>(zone_of(ids[i]));
    const Eigen::Vector3d u = x[i] - d_->x_init[i];
    arrays[0].values.insert(arrays[0].values.end(), {u[0], u[1], u[2]});
    arrays[1].values.insert(arrays[1].values.end(), {v[i][0], v[i][1], v[i][2]});
  }
  arrays.insert(arrays.end(), extra.begin(), extra.end());
  write_point_cloud_vtu(path, x, zone, arrays, 9);
}

} // namespace pnc::gimp::escm
