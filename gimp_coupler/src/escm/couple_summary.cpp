// summary.json and the plots of a finished coupled run (observers.hpp; keys in docs/escm.md
// "Outputs").
#include "observers.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/plot.hpp"

#include <cmath>
#include <cstdlib>
#include <map>

namespace pnc::gimp::escm {

namespace {

using json = nlohmann::json;

/// Handshake continuity at the end (D106): for every IVC cell the mean displacement of its
/// atoms, the standard deviation of its atoms' displacements, and the displacement of the
/// continuum particle(s) of the SVC cell(s) just outside it (m).
json handshake(CoupledRun& run) {
  run.gather();
  const Coupler& cp = run.coupler();
  const Solver<2>& s = run.solver();
  const std::vector<Eigen::Vector3d>& gax = run.atoms_x();
  int imin = 1 << 30, imax = -(1 << 30), jmin = imin, jmax = imax;
  std::map<std::pair<int, int>, std::size_t> svc_particle;
  for (const Cell& cell : cp.cells()) {
    imin = std::min(imin, cell.ij[0]);
    imax = std::max(imax, cell.ij[0]);
    jmin = std::min(jmin, cell.ij[1]);
    jmax = std::max(jmax, cell.ij[1]);
    if (cell.zone == Zone::svc) svc_particle[{cell.ij[0], cell.ij[1]}] = cell.particle;
  }
  json hs = json::array();
  for (const Cell& cell : cp.cells()) {
    if (cell.zone != Zone::ivc) continue;
    const int i = cell.ij[0], j = cell.ij[1];
    Eigen::Vector2d sum = Eigen::Vector2d::Zero(), sq = Eigen::Vector2d::Zero();
    for (int id : cell.atoms) {
      const auto k = static_cast<std::size_t>(id - 1);
      const Eigen::Vector2d u = cp.to_continuum(gax[k]) - cp.to_continuum(cp.atoms_initial()[k]);
      sum += u;
      sq += u.cwiseProduct(u);
    }
    const double n = static_cast<double>(cell.atoms.size());
    const Eigen::Vector2d mean = sum / n;
    const Eigen::Vector2d var = (sq / n - mean.cwiseProduct(mean)).cwiseMax(0.0);
    Eigen::Vector2d uc = Eigen::Vector2d::Zero();
    int nc = 0;
    const int rr = run.input().svc;
    for (const auto& q : std::vector<std::pair<int, int>>{{i - imin == rr ? i - 1 : i, j},
                                                          {imax - i == rr ? i + 1 : i, j},
                                                          {i, j - jmin == rr ? j - 1 : j},
                                                          {i, jmax - j == rr ? j + 1 : j}}) {
      const auto it = svc_particle.find(q);
      if (it == svc_particle.end()) continue;
      uc += s.particles.x[it->second] - s.particles.x0[it->second];
      ++nc;
    }
    if (nc == 0) continue;
    uc /= nc;
    hs.push_back({{"cell", {i, j}},
                  {"atoms", cell.atoms.size()},
                  {"u_ivc_m", {mean[0], mean[1]}},
                  {"sd_atoms_m", {std::sqrt(var[0]), std::sqrt(var[1])}},
                  {"u_svc_m", {uc[0], uc[1]}}});
  }
  return hs;
}

} // namespace

void write_couple_summary(CoupledRun& run, const MdRegion& region, const CoupleOptions& o,
                          CoupleSummary& r) {
  const CoupleInput& p = run.input();
  const LjFcc& lj = run.calibration();
  const double h = run.cell_size();
  r.strain_modulus_pa = lj.strip_modulus();
  r.summary_json = run.out_dir() + "/summary.json";
  json sj;
  sj["input"] = o.input;
  sj["short"] = o.short_mode;
  sj["load"] = p.load;
  sj["strain"] = p.strain;
  sj["steps"] = r.steps;
  sj["time_s"] = r.time_s;
  sj["wall_s"] = r.wall_s;
  sj["outside_lammps_share"] = r.outside_share;
  sj["atoms"] = {{"interior", r.atoms[0]}, {"ivc", r.atoms[1]}, {"svc", r.atoms[2]}};
  sj["particles"] = r.particles;
  sj["cell_size_m"] = h;
  sj["block_origin_m"] = {p.block_x0() * h, p.block_y0() * h};
  sj["block_cells"] = {p.nbx, p.nby};
  sj["md_type"] = p.md_type;
  region.summarize(sj); // "lj_fcc" or "polymer"
  sj["continuum"] = {{"lambda_Pa", lj.C12},
                     {"mu_Pa", 0.5 * (lj.C11 - lj.C12)},
                     {"E_Pa", lj.E()},
                     {"nu", lj.nu()},
                     {"density_kg_per_m3", lj.density},
                     {"strip_modulus_Pa", lj.strip_modulus()}};
  // The fixed edge's reaction along the load (N per m); for Case I the left edge (as before).
  sj["reaction_fixed_N_per_m"] = r.reaction_left;
  if (p.load == "tension_x") {
    sj["reaction_left_N_per_m"] = r.reaction_left;
    sj["expected_reaction_N_per_m"] = -lj.strip_modulus() * p.strain * p.ncy * h;
  }
  const GradientTracker& grad = run.gradient();
  sj["gradient"] = {{"spacing_m", grad.spacing()},
                    {"increments", grad.increments()},
                    {"wall_s", run.gradient_wall_s()}};
  sj["handshake"] = handshake(run);
  sj["checkpoint"] = {
      {"file", r.checkpoint},        {"every_steps", run.schedule().checkpoint_every},
      {"written", r.checkpoints},    {"wall_s", r.checkpoint_s},
      {"bytes", r.checkpoint_bytes}, {"resumed", r.resumed},
      {"start_step", r.start_step}};
  for (const auto& ob : run.observers())
    ob->summarize(run, sj); // particle_frames, crack, crack_csv
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
}

void plot_couple(const std::string& out, bool crack, CoupleSummary& r) {
  // plot_escm.py through the one plot runner (pnc/core/plot.hpp, D337): a missing interpreter,
  // matplotlib or script is a warning, the run is written anyway
  pnc::PlotRun pr;
  try {
    pr = pnc::run_plot("plot_escm.py", {out});
  } catch (const pnc::InputError& e) {
    r.plot_warning = std::string("plots not written: ") + e.what();
    return;
  }
  const bool ends = pr.output.empty() || pr.output.back() == '\n';
  pnc::write_text_atomically(out + "/plot.log", pr.output + (ends ? "" : "\n"));
  if (pr.ok()) {
    r.plots = {out + "/profile.png", out + "/energy.png"};
    if (crack) r.plots.push_back(out + "/crack.png");
  } else {
    r.plot_warning = "plots not written (see " + out + "/plot.log): " + pr.warning;
  }
}

} // namespace pnc::gimp::escm
