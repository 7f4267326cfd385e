// The coarse-grained polypropylene MD region of `pnc gimp couple` (escm_polymer.hpp, D100-D108).
#include "pnc/gimp_coupler/escm_polymer.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/units.hpp"
#include "pnc/md/atoms.hpp"
#include "pnc/md/box.hpp"
#include "pnc/md/builder.hpp"
#include "pnc/md/lammps_path.hpp"
#include "pnc/md/runner.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

namespace pnc::gimp::escm {

namespace {

using Vec = std::array<double, 3>;

std::string num(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

/// Unwrapped positions (A) of all atoms by id, from x and the unpacked image flags
/// (md/atoms.hpp; the in-process stage instance holds every atom).
std::vector<Vec> unwrapped(pnc::md::Lammps& L) {
  const std::vector<double> x = L.gather("x", 3);
  const std::vector<double> img = pnc::md::gather_local(L.handle(), "image", 3);
  const pnc::md::LmpBox box = L.box();
  const auto per = L.periodic();
  const std::size_t n = x.size() / 3;
  std::vector<Vec> u(n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t a = 0; a < 3; ++a)
      u[i][a] = x[3 * i + a] + (per[a] ? img[3 * i + a] * (box.hi[a] - box.lo[a]) : 0.0);
  return u;
}

void write_positions(const std::string& path, const std::vector<Vec>& u,
                     const std::map<std::string, double>& values) {
  std::ofstream f(path);
  f.precision(17);
  for (const auto& [k, v] : values)
    f << k << ' ' << v << '\n';
  f << "atoms " << u.size() << '\n';
  for (const Vec& p : u)
    f << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  if (!f) pnc::fail(path, "", "", "write failed (disk full?)");
}

void read_positions(const std::string& path, std::vector<Vec>& u,
                    std::map<std::string, double>& values) {
  std::ifstream f(path);
  if (!f) pnc::fail_tool("LAMMPS", "reading a polymer stage's result", "no file " + path, "");
  std::string k;
  while (f >> k) {
    if (k == "atoms") {
      std::size_t n = 0;
      f >> n;
      u.resize(n);
      for (Vec& p : u)
        f >> p[0] >> p[1] >> p[2];
      break;
    }
    double v = 0;
    f >> v;
    values[k] = v;
  }
  if (!f) pnc::fail_tool("LAMMPS", "reading a polymer stage's result", "truncated " + path, "");
}

std::vector<std::string> header(const std::string& boundary, const std::string& data) {
  return {"units real", "atom_style molecular", "boundary " + boundary,
          "read_data " + pnc::md::lammps_path(data, "data file")};
}

void run(const pnc::md::StageSpec& st, const pnc::md::StageBody& body) {
  const auto out = pnc::md::run_stage(st, body);
  if (!out.ok) // ToolError with LAMMPS's message and the stage log: exit code 7
    pnc::md::throw_stage_failure(out, "escm polymer stage " + st.name);
}

/// The steps of build_polymer_block (escm_polymer.hpp), in order: grow(), relax(), cut_block(),
/// surface(), count_cells(), finish(); each reads what the previous ones left in the members.
struct BlockBuilder {
  BlockBuilder(const PolymerBlockSpec& spec, const std::string& source) : sp(spec), src(source) {}

  /// Checks the spec (D100, D105) and grows the chains in the periodic box (D100).
  void grow(const std::string& dir);
  /// 2. Periodic relaxation and elastic constants (D101, D102), in a child process.
  void relax();
  void relax_stage(pnc::md::Lammps& L, const std::string& out) const;
  /// 3. Cut at the x/y faces and, in neumann mode, between SVC and free atoms (D103); the weak
  /// interface (D114).
  void cut_block();
  /// 4. Free-surface minimisation with the SVC atoms held (D104), repeated until the zones
  /// hold (D107).
  void surface();
  void surface_stage(pnc::md::Lammps& L, const std::string& out) const;
  /// D105: bead count of every SVC/IVC cell.
  void count_cells();
  PolymerBlock finish();

  // Helpers of the cuts (positions in the block frame, A).
  bool crosses(int i, int j) const; ///< the pair's unwrapped bond crosses an x/y face
  std::array<int, 2> cell(const Vec& p) const;
  std::vector<char> svc_of(const std::vector<Vec>& pos) const;
  std::vector<char> above_of(const std::vector<Vec>& pos) const; ///< D114
  void set_types(const std::vector<char>& up);
  /// Removes the bonded terms that cross a face, or (faces false) whose atoms are not all on
  /// the same side of `flags` (SVC vs free in neumann mode, D103; above vs below the weak
  /// interface, D114).
  void cut(const std::vector<char>& flags, bool faces, int counts[3]);
  /// Cuts by side (SVC vs free in neumann mode, D103; the weak interface, D114), counted into
  /// the block's totals.
  void cut_sides(const std::vector<char>& flags, bool on, int& bonds, int& angles, int& dihedrals);
  void cut_svc(const std::vector<char>& svc);
  void cut_interface(const std::vector<char>& up);

  const PolymerBlockSpec& sp;
  const std::string& src;
  const std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  std::string dabs; ///< the run directory, absolute
  PolymerBlock b;
  pnc::md::BuildSpec bs;
  double per_cell = 0.0; ///< expected beads per cell (D105)
  pnc::md::System s;
  std::string build_data, cut_data;
  std::vector<std::string> ffc, weak; ///< force field; the weak interface's pair (D114)
  std::vector<Vec> u;                 ///< relaxed positions, unwrapped
  std::vector<Vec> w;                 ///< x, y wrapped into [0, L); z unwrapped (from lo_z)
  std::vector<Vec> u2;                ///< positions after the surface minimisation
  std::map<std::string, double> v;    ///< the relax stage's numbers
  double Lx = 0.0, Ly = 0.0, Lz = 0.0, h = 0.0;
  double lo_xy[2] = {0.0, 0.0}, Lxy[2] = {0.0, 0.0};
  bool interface = false;
  std::vector<char> svc0, up0;
};

void BlockBuilder::grow(const std::string& dir) {
  namespace fs = std::filesystem;
  pnc::make_output_directory(dir);
  dabs = fs::absolute(dir).string();
  pnc::md::lammps_path(dabs + "/polymer_block.data", "--out"); // refused here if unquotable
  sp.ff.validate(src);
  if (sp.density > 0) bs.density = sp.density;
  if (sp.beads_per_chain > 0) bs.beads_per_chain = sp.beads_per_chain;
  bs.seed = sp.seed;
  b.build_density = bs.density;
  b.beads_per_chain = bs.beads_per_chain;
  // D105: every volume cell needs atoms; check the expectation before building.
  per_cell = expected_beads_per_cell(sp);
  if (per_cell < 2.0 * sp.min_beads_per_cell)
    fail(src, "md.cell_A", num(sp.cell_A),
         "a cell of " + num(sp.cell_A) + " x " + num(sp.cell_A) + " x " + num(sp.slab_A) +
             " A^3 holds on average " + num(per_cell) + " beads at " + num(bs.density) +
             " g/cm^3; at least 2 x min_beads_per_cell = " +
             std::to_string(2 * sp.min_beads_per_cell) +
             " are needed so that every SVC/IVC cell holds atoms (D105): raise md.cell_A or "
             "md.slab_A");
  if (sp.slab_A < 2.0 * sp.ff.cutoff())
    fail(src, "md.slab_A", num(sp.slab_A),
         "must be at least twice the LJ cut-off (" + num(2 * sp.ff.cutoff()) +
             " A): a bead must not meet its own periodic image through the slab (D100)");
  // 1. Build (D100): chains grown in the periodic block box.
  s.lo = {0, 0, 0};
  s.hi = {sp.nbx * sp.cell_A, sp.nby * sp.cell_A, sp.slab_A};
  s.type_mass = {sp.ff.bead_mass};
  const double nbead = bs.density * pnc::md::avogadro_per_A3_cm3 / sp.ff.bead_mass * s.volume();
  bs.chains = std::max(1, static_cast<int>(std::lround(nbead / bs.beads_per_chain)));
  bs.validate(src);
  pnc::md::grow_chains(s, bs, sp.ff, 0.0);
  b.chains = bs.chains;
  b.atoms = static_cast<int>(s.x.size());
  build_data = dabs + "/polymer_build.data";
  pnc::md::write_data_file(build_data, s, "ESCM polymer block, as built");
  ffc = pnc::md::polymer_forcefield_commands(sp.ff);
}

void BlockBuilder::relax_stage(pnc::md::Lammps& L, const std::string& out) const {
  L.cmds(header("p p p", build_data));
  L.cmds(ffc);
  L.cmd("pair_modify shift yes"); // D107: continuous energy for the line searches
  L.cmds({"neighbor 2.0 bin", "neigh_modify delay 0 every 1 check yes",
          "thermo_style custom step temp pe press pxx pyy pzz lx ly lz", "thermo 1000",
          "min_style cg", "min_modify line quadratic", "minimize 0 1e-6 1000 10000"});
  const long nsteps = std::lround(sp.anneal_ps * 1000.0 / sp.anneal_timestep_fs);
  if (nsteps >= 2) {
    const std::string T = num(sp.temperature);
    const std::string baro = " x 0 0 1000 y 0 0 1000 z 0 0 1000 couple xy";
    L.cmds({"timestep " + num(sp.anneal_timestep_fs),
            "velocity all create " + T + " " + std::to_string(sp.seed % 800000000 + 1) +
                " dist gaussian",
            "fix escm_npt all npt temp " + T + " " + T + " 100" + baro,
            "run " + std::to_string(nsteps / 2), "unfix escm_npt",
            "fix escm_npt all npt temp " + T + " 1 100" + baro,
            "run " + std::to_string(nsteps - nsteps / 2), "unfix escm_npt",
            "velocity all set 0 0 0"});
  }
  L.cmds({"fix escm_br all box/relax x 0 y 0 z 0 couple xy vmax 0.001 nreset 50",
          "minimize 0 1e-8 1000 10000", "unfix escm_br"});
  std::map<std::string, double> vals;
  const std::vector<Vec> uu = unwrapped(L);
  const pnc::md::LmpBox box = L.box();
  for (int a = 0; a < 3; ++a) {
    vals[std::string("lo") + "xyz"[a]] = box.lo[static_cast<std::size_t>(a)];
    vals[std::string("L") + "xyz"[a]] = box.length(a);
  }
  vals["pxx"] = L.thermo("pxx");
  vals["pyy"] = L.thermo("pyy");
  vals["pzz"] = L.thermo("pzz");
  vals["press"] = L.thermo("press");
  if (sp.measure_elastic) {
    const double d = sp.strain_probe;
    for (int ax = 0; ax < 3; ++ax) {
      std::array<std::array<double, 3>, 2> sig{};
      for (int k = 0; k < 2; ++k) {
        // stretch f along ax about the box centre and back, through the one box routine
        // (md/box.hpp, D316)
        Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
        F(ax, ax) = k == 0 ? 1 + d : 1 - d;
        L.cmd(pnc::md::box_change(L.box(), F, "<escm polymer elastic probe>"));
        L.cmd("minimize 0 1e-10 20000 100000");
        sig[static_cast<std::size_t>(k)] = {-L.thermo("pxx"), -L.thermo("pyy"), -L.thermo("pzz")};
        L.cmd(pnc::md::box_change(L.box(), F.inverse(), "<escm polymer elastic probe>"));
      }
      for (int a = 0; a < 3; ++a)
        vals[std::string("C") + "xyz"[a] + "xyz"[ax]] =
            (sig[0][static_cast<std::size_t>(a)] - sig[1][static_cast<std::size_t>(a)]) / (2 * d) *
            pnc::md::pa_per_atm;
    }
  }
  write_positions(out, uu, vals);
}

void BlockBuilder::relax() {
  const std::string relax_out = dabs + "/polymer_relax.txt";
  const auto tr = std::chrono::steady_clock::now();
  run({"polymer/relax", dabs + "/polymer_relax.log", {}, 1},
      [&](pnc::md::Lammps& L) { relax_stage(L, relax_out); });
  b.relax_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tr).count();
  read_positions(relax_out, u, v);
  if (u.size() != s.x.size())
    pnc::fail_simulation("ESCM polymer block", -1, std::numeric_limits<double>::quiet_NaN(), "",
                         "the atom count changed");
  Lx = v.at("Lx");
  Ly = v.at("Ly");
  Lz = v.at("Lz");
  b.h_A = Lx / sp.nbx; // D101 (x and y coupled: Ly / nby is the same)
  b.Lz_A = Lz;
  const double mass_kg = static_cast<double>(u.size()) * sp.ff.bead_mass * pnc::units::kg_per_g_mol;
  b.density_kg_m3 = mass_kg / (Lx * Ly * Lz * pnc::units::m3_per_angstrom3);
  b.pxx_atm = v.at("pxx");
  b.pyy_atm = v.at("pyy");
  b.pzz_atm = v.at("pzz");
  b.pressure_atm = v.at("press");
  if (sp.measure_elastic) {
    b.C11 = v.at("Cxx");
    b.C22 = v.at("Cyy");
    b.C33 = v.at("Czz");
    b.C21 = v.at("Cyx"); // sigma_y / eps_x
    b.C12 = v.at("Cxy");
    b.C31 = v.at("Czx");
    b.C32 = v.at("Czy");
    b.lambda = 0.5 * (b.C12 + b.C21);
    b.mu = 0.5 * (0.5 * (b.C11 + b.C22) - b.lambda);
  }
}

bool BlockBuilder::crosses(int i, int j) const {
  for (std::size_t a = 0; a < 2; ++a) {
    const double du = u[static_cast<std::size_t>(j)][a] - u[static_cast<std::size_t>(i)][a];
    const double dw = w[static_cast<std::size_t>(j)][a] - w[static_cast<std::size_t>(i)][a];
    if (std::abs(du - dw) > 0.5 * Lxy[a]) return true;
  }
  return false;
}

std::array<int, 2> BlockBuilder::cell(const Vec& p) const {
  return std::array<int, 2>{static_cast<int>(std::floor(p[0] / h)),
                            static_cast<int>(std::floor(p[1] / h))};
}

std::vector<char> BlockBuilder::svc_of(const std::vector<Vec>& pos) const {
  std::vector<char> svc(pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i) {
    const auto c = cell(pos[i]);
    const int ring = std::min({c[0], sp.nbx - 1 - c[0], c[1], sp.nby - 1 - c[1]});
    svc[i] = ring < sp.svc_rings;
  }
  return svc;
}

std::vector<char> BlockBuilder::above_of(const std::vector<Vec>& pos) const {
  std::vector<char> up(pos.size(), 0);
  if (interface)
    for (std::size_t i = 0; i < pos.size(); ++i)
      up[i] = pos[i][1] > b.interface_y_A;
  return up;
}

void BlockBuilder::set_types(const std::vector<char>& up) {
  if (!interface) return;
  s.type_mass = {sp.ff.bead_mass, sp.ff.bead_mass};
  for (std::size_t i = 0; i < up.size(); ++i)
    s.type[i] = up[i] ? 2 : 1;
}

void BlockBuilder::cut(const std::vector<char>& flags, bool faces, int counts[3]) {
  auto mixed = [&](std::initializer_list<int> ids) {
    bool any = false, all = true;
    for (int i : ids) {
      any = any || flags[static_cast<std::size_t>(i)];
      all = all && flags[static_cast<std::size_t>(i)];
    }
    return any && !all;
  };
  auto drop = [&](auto& list, auto&& bad) {
    const std::size_t n0 = list.size();
    list.erase(std::remove_if(list.begin(), list.end(), bad), list.end());
    return static_cast<int>(n0 - list.size());
  };
  counts[0] = drop(s.bonds, [&](const std::array<int, 3>& t) {
    return (faces && crosses(t[1], t[2])) || (!faces && mixed({t[1], t[2]}));
  });
  counts[1] = drop(s.angles, [&](const std::array<int, 4>& t) {
    return (faces && (crosses(t[1], t[2]) || crosses(t[2], t[3]))) ||
           (!faces && mixed({t[1], t[2], t[3]}));
  });
  counts[2] = drop(s.dihedrals, [&](const std::array<int, 5>& t) {
    return (faces && (crosses(t[1], t[2]) || crosses(t[2], t[3]) || crosses(t[3], t[4]))) ||
           (!faces && mixed({t[1], t[2], t[3], t[4]}));
  });
}

void BlockBuilder::cut_sides(const std::vector<char>& flags, bool on, int& bonds, int& angles,
                             int& dihedrals) {
  if (!on) return;
  int c[3];
  cut(flags, false, c);
  bonds += c[0];
  angles += c[1];
  dihedrals += c[2];
}

void BlockBuilder::cut_svc(const std::vector<char>& svc) {
  cut_sides(svc, sp.neumann, b.cut_svc_bonds, b.cut_svc_angles, b.cut_svc_dihedrals);
}

void BlockBuilder::cut_interface(const std::vector<char>& up) {
  cut_sides(up, interface, b.cut_interface_bonds, b.cut_interface_angles,
            b.cut_interface_dihedrals);
}

void BlockBuilder::cut_block() {
  lo_xy[0] = v.at("lox");
  lo_xy[1] = v.at("loy");
  Lxy[0] = Lx;
  Lxy[1] = Ly;
  w.resize(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) {
    for (int a = 0; a < 2; ++a) {
      double q = u[i][static_cast<std::size_t>(a)] - lo_xy[a];
      q -= std::floor(q / Lxy[a]) * Lxy[a];
      if (q >= Lxy[a]) q -= Lxy[a];
      w[i][static_cast<std::size_t>(a)] = q;
    }
    w[i][2] = u[i][2] - v.at("loz");
  }
  h = b.h_A;
  // D114: the weak interface, beads above it flagged (and typed 2 in the data files).
  interface = sp.interface_row >= 0;
  b.interface_y_A = interface ? sp.interface_row * h : -1.0;
  int cp[3];
  cut({}, true, cp);
  b.cut_periodic_bonds = cp[0];
  b.cut_periodic_angles = cp[1];
  b.cut_periodic_dihedrals = cp[2];
  svc0 = svc_of(w);
  up0 = above_of(w);
  cut_svc(svc0);
  cut_interface(up0);
  set_types(up0);
  // Non-periodic x, y: a box with a margin (shrink-wrapped when read, D78); z periodic.
  const double margin = 2.0;
  s.lo = {-margin, -margin, 0.0};
  s.hi = {Lx + margin, Ly + margin, Lz};
  for (std::size_t i = 0; i < u.size(); ++i)
    s.x[i] = w[i];
  cut_data = dabs + "/polymer_cut.data";
  pnc::md::write_data_file(cut_data, s, "ESCM polymer block, faces cut");
}

void BlockBuilder::surface_stage(pnc::md::Lammps& L, const std::string& out) const {
  L.cmds(header("s s p", cut_data));
  L.cmds(ffc);
  L.cmds(weak);
  L.cmd("pair_modify shift yes"); // D107
  const double a = sp.svc_rings * h;
  L.cmds({"neighbor 2.0 bin", "neigh_modify delay 0 every 1 check yes",
          "region escm_inner block " + num(a) + " " + num(Lx - a) + " " + num(a) + " " +
              num(Ly - a) + " INF INF units box",
          "group escm_free region escm_inner", "group escm_svc subtract all escm_free"});
  if (sp.neumann) L.cmd("neigh_modify exclude group escm_svc escm_free");
  L.cmds({"fix escm_hold escm_svc setforce 0 0 0", "thermo_style custom step pe press fmax",
          "thermo 1000", "min_style cg", "min_modify line quadratic",
          "minimize 0 1e-6 4000 40000"});
  std::map<std::string, double> vv;
  vv["pe"] = L.thermo("pe");
  vv["fmax"] = L.thermo("fmax");
  vv["fnorm"] = L.thermo("fnorm");
  write_positions(out, unwrapped(L), vv);
}

// With the zones (and SVC-free cuts) of the relaxed positions until no atom changes zone, so
// that the block the coupler reads is a converged minimum for the coupler's own zones (D107).
void BlockBuilder::surface() {
  const std::string surf_out = dabs + "/polymer_surface.txt";
  const auto ts = std::chrono::steady_clock::now();
  std::vector<char> svc_prev = svc0, up_prev = up0;
  // D114: pairs across the interface (types 1-2) at interface_fraction x epsilon
  weak.clear();
  if (interface)
    weak.push_back("pair_coeff 1 2 " + num(sp.interface_fraction * sp.ff.epsilon) + " " +
                   num(sp.ff.sigma));
  for (int pass = 1;; ++pass) {
    const std::string surf_log =
        dabs + (pass == 1 ? std::string("/polymer_surface.log")
                          : "/polymer_surface_" + std::to_string(pass) + ".log");
    run({"polymer/surface", surf_log, {}, 1},
        [&](pnc::md::Lammps& L) { surface_stage(L, surf_out); });
    std::map<std::string, double> v2;
    read_positions(surf_out, u2, v2);
    if (u2.size() != s.x.size())
      pnc::fail_simulation("ESCM polymer block", -1, std::numeric_limits<double>::quiet_NaN(), "",
                           "the atom count changed");
    b.surface_fmax = v2.at("fmax");
    b.surface_fnorm = v2.at("fnorm");
    b.surface_passes = pass;
    for (std::size_t i = 0; i < u2.size(); ++i)
      s.x[i] = u2[i];
    // Zones by the relaxed positions (as the coupler assigns them): cut what became mixed.
    // D114: so are the terms that now cross the interface, and the types follow the side.
    const std::vector<char> svc1 = svc_of(u2), up1 = above_of(u2);
    int moved = 0;
    for (std::size_t i = 0; i < svc1.size(); ++i)
      moved += (svc1[i] != svc_prev[i]) + (up1[i] != up_prev[i]);
    if (pass == 1) b.moved_zone = moved;
    b.moved_zone_last = moved;
    svc_prev = svc1;
    up_prev = up1;
    if (moved == 0) break;
    cut_svc(svc1);
    cut_interface(up1);
    set_types(up1);
    if (pass == 4) break; // reported (moved_zone_last); the coupler still runs
    pnc::md::write_data_file(cut_data, s, "ESCM polymer block, faces cut, re-zoned");
  }
  b.surface_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count();
}

void BlockBuilder::count_cells() {
  std::map<std::array<int, 2>, int> count;
  for (const Vec& p : u2) {
    const auto c = cell(p);
    if (c[0] < 0 || c[1] < 0 || c[0] >= sp.nbx || c[1] >= sp.nby)
      pnc::fail_simulation("escm polymer block", -1, std::numeric_limits<double>::quiet_NaN(), "",
                           "a bead left the block's cells in the surface minimisation (x = " +
                               num(p[0]) + ", y = " + num(p[1]) + " A)");
    ++count[c];
  }
  b.min_cell_beads = 1 << 30;
  int ncell = 0;
  const int rings = sp.svc_rings + sp.ivc_rings;
  for (int j = 0; j < sp.nby; ++j)
    for (int i = 0; i < sp.nbx; ++i) {
      if (std::min({i, sp.nbx - 1 - i, j, sp.nby - 1 - j}) >= rings) continue;
      const auto it = count.find({i, j});
      const int n = it == count.end() ? 0 : it->second;
      b.min_cell_beads = std::min(b.min_cell_beads, n);
      b.max_cell_beads = std::max(b.max_cell_beads, n);
      b.mean_cell_beads += n;
      ++ncell;
      if (n < sp.min_beads_per_cell)
        fail(src, "md.min_beads_per_cell", std::to_string(sp.min_beads_per_cell),
             "volume cell (" + std::to_string(i) + ", " + std::to_string(j) +
                 ") of the built block holds " + std::to_string(n) + " beads (cell " + num(h) +
                 " A, slab " + num(Lz) + " A, expected mean " + num(per_cell) +
                 "): raise md.cell_A or md.slab_A, or change md.seed (D105)");
    }
  b.mean_cell_beads /= std::max(1, ncell);
}

PolymerBlock BlockBuilder::finish() {
  b.data_file = dabs + "/polymer_block.data";
  pnc::md::write_data_file(b.data_file, s, "ESCM polymer block, relaxed, boundary s s p");
  b.md_setup = header("s s p", b.data_file);
  b.md_setup.insert(b.md_setup.end(), ffc.begin(), ffc.end());
  b.md_setup.insert(b.md_setup.end(), weak.begin(), weak.end());
  b.total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return b;
}

} // namespace

double expected_beads_per_cell(const PolymerBlockSpec& sp) {
  const double rho = sp.density > 0 ? sp.density : pnc::md::BuildSpec{}.density;
  return rho * pnc::md::avogadro_per_A3_cm3 / sp.ff.bead_mass * sp.cell_A * sp.cell_A * sp.slab_A;
}

PolymerBlock build_polymer_block(const PolymerBlockSpec& sp, const std::string& dir,
                                 const std::string& src) {
  BlockBuilder k(sp, src);
  k.grow(dir);
  k.relax();
  k.cut_block();
  k.surface();
  k.count_cells();
  return k.finish();
}

} // namespace pnc::gimp::escm
