// Stepwise strain-controlled deformation driver (units real inside, Pa outside).
#include "pnc/rve/deform.hpp"
#include "pnc/md/box.hpp"

#include "pnc/damage/cases.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/progress.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/version.hpp"
#include "pnc/md/forcefield.hpp"
#include "pnc/md/lammps_path.hpp"
#include "pnc/md/stage_stop.hpp"
#include "pnc/md/statistics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>

namespace pnc::rve {

namespace {
// DeformSpec::amplitude() for the case's registry row `row`, which the driver holds (no lookup
// per strain step): a shear case is a row that drives a shear component (Voigt 3..5), not an
// id range (D362)
double amplitude_of(const DeformSpec& spec, const damage::DeformationCase& row) {
  const bool shear =
      std::any_of(row.driven.begin(), row.driven.end(), [](int v) { return v >= 3; });
  return shear && spec.shear_strain_max != 0 ? spec.shear_strain_max : spec.strain_max;
}
} // namespace

double DeformSpec::amplitude() const {
  return amplitude_of(*this, damage::deformation_case(case_id, "deform.case"));
}

namespace fs = std::filesystem;
using PathM = Eigen::Matrix<double, Eigen::Dynamic, 6>;

void DeformSpec::validate(const std::string& source) const {
  damage::deformation_case(case_id, source);
  if (!(std::isfinite(strain_max) && strain_max != 0.0 && std::fabs(strain_max) <= 0.5))
    fail(source, "deform.strain_max", fmt::format("{}", strain_max),
         "must be non-zero with |strain_max| <= 0.5");
  if (!(std::isfinite(shear_strain_max) && std::fabs(shear_strain_max) <= 0.5))
    fail(source, "deform.shear_strain_max", fmt::format("{}", shear_strain_max),
         "must satisfy |shear_strain_max| <= 0.5 (0: the shear cases use strain_max)");
  if (steps < 1 || steps > 100000)
    fail(source, "deform.steps", std::to_string(steps), "must be in 1..100000");
  // 50 fs: the bead-spring glass (tau 2.45 ps) takes 20 fs steps (decision D137)
  if (!(timestep_fs > 0 && timestep_fs <= 50))
    fail(source, "deform.timestep_fs", fmt::format("{}", timestep_fs), "must be in (0, 50] fs");
  if (sample_every < 1)
    fail(source, "deform.sample_every", std::to_string(sample_every), "must be >= 1");
  if (blocks < 2) fail(source, "deform.blocks", std::to_string(blocks), "must be >= 2");
  if (reference_holds < 1 || reference_holds > 1000)
    fail(source, "deform.reference_holds", std::to_string(reference_holds),
         "must be in 1..1000 (the zero-strain hold lasts reference_holds x hold_steps)");
  if (hold_steps < static_cast<long>(sample_every) * blocks)
    fail(source, "deform.hold_steps", std::to_string(hold_steps),
         fmt::format("must be >= sample_every * blocks = {} (one sample per block at least)",
                     sample_every * blocks));
  if (!(temperature >= 0))
    fail(source, "deform.temperature", fmt::format("{}", temperature), "must be >= 0 K");
  if (!(damp_fs > 0)) fail(source, "deform.damp_fs", fmt::format("{}", damp_fs), "must be > 0");
  if (seed < 1 || seed > 900000000)
    fail(source, "deform.seed", std::to_string(seed), "must be in 1..900000000 (LAMMPS seeds)");
  if (start_state.empty()) fail(source, "deform.start_state", "", "must name a restart file");
}

PathM moving_average(const PathM& m, int points) {
  if (points < 1 || points % 2 == 0)
    fail("<deform>", "moving_average", std::to_string(points), "must be an odd number >= 1");
  const Eigen::Index n = m.rows(), h = points / 2;
  PathM out(n, 6);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index a = std::max<Eigen::Index>(0, i - h), b = std::min(n - 1, i + h);
    out.row(i) = m.middleRows(a, b - a + 1).colwise().mean();
  }
  return out;
}

namespace {

/// Force tolerance of the static minimisation, kcal/mol/A (2-norm of the global force vector).
constexpr double kStaticFtol = 1e-10;

std::string ckpt_path(const std::string& dir) {
  return (fs::path(dir) / "checkpoint.h5").string();
}
/// State after row k (k = 0: the reference hold at zero strain).
std::string state_path(const std::string& dir, int k) {
  return (fs::path(dir) / fmt::format("state_{}.restart", k)).string();
}
/// State that row k starts from: the start state (made triclinic for shear) for k = 0.
std::string prev_state(const std::string& dir, int k) {
  return k == 0 ? (fs::path(dir) / "state_init.restart").string() : state_path(dir, k - 1);
}

h5::RowMatrix to_row(const Eigen::MatrixXd& m) {
  return m;
}

struct Checkpoint {
  CaseResult r;
  std::vector<double> ref_box; // xlo ylo zlo xhi yhi zhi xy xz yz
  std::string lmp_version;     // the running LAMMPS's release date YYYYMMDD (D366)
};

// `amplitude`: spec.amplitude() of the case's row, which the driver holds
void write_checkpoint(const std::string& dir, const DeformSpec& spec, double amplitude,
                      const Checkpoint& c) {
  AtomicOutput out(ckpt_path(dir));
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    f.set_attr("/", "format", "pnc-rve-case");
    f.set_attr("/", "updated_utc", utc_timestamp());
    f.set_attr("/", "stress_sign", "tension positive: sigma = -P (LAMMPS pressure tensor)");
    f.write_scalar("/case", spec.case_id);
    f.write_scalar("/rows_done", c.r.rows_done);
    f.write_scalar("/steps_planned", spec.steps);
    f.write_scalar("/strain_max", amplitude);
    f.write_string("/seed", std::to_string(spec.seed));
    f.write_scalar("/hold_steps", spec.hold_steps);
    f.write_scalar("/timestep", spec.timestep_fs);
    f.set_attr("/timestep", "units", "fs");
    f.write_scalar("/sample_every", spec.sample_every);
    f.write_scalar("/blocks", spec.blocks);
    f.write_scalar("/reference_holds", spec.reference_holds);
    f.write_scalar("/temperature", spec.temperature);
    f.set_attr("/temperature", "units", "K");
    f.write_string("/mode", spec.temperature == 0
                                ? std::string("static (0 K): affine remap, ") +
                                      (spec.minimize ? "minimisation at fixed box, " : "") +
                                      "run 0; standard errors not measured (NaN)"
                                : std::string("hold: NVE + Langevin, block-averaged samples"));
    f.write_string("/start_state", spec.start_state);
    f.write_string("/recipe", spec.recipe_json.empty() ? "{}" : spec.recipe_json);
    f.write_string("/lammps_version", c.lmp_version);
    f.write_vector("/reference_box", c.ref_box);
    f.set_attr("/reference_box", "units", "A (xlo ylo zlo xhi yhi zhi xy xz yz)");
    if (c.r.rows_done > 0) {
      f.write_matrix("/strain", to_row(c.r.strain));
      f.set_attr("/strain", "units", "1 (engineering; shear as gamma)");
      const std::pair<const char*, const PathM*> mats[] = {
          {"/stress_virial", &c.r.stress_virial},
          {"/stress_virial_stderr", &c.r.stress_virial_se},
          {"/stress_total", &c.r.stress_total},
          {"/stress_total_stderr", &c.r.stress_total_se}};
      for (const auto& [name, m] : mats) {
        f.write_matrix(name, to_row(*m));
        f.set_attr(name, "units", "Pa");
      }
      f.set_attr("/stress_virial", "definition",
                 "virial only, no kinetic term (docs/theory.md §3.5, Zhou 2003): compute pressure "
                 "NULL virial");
      f.set_attr("/stress_total", "definition",
                 "virial + kinetic term (compute pressure thermo_temp)");
      const std::pair<const char*, const PathM*> checks[] = {
          {"/stress_virial_tau", &c.r.stress_virial_tau_fs},
          {"/stress_total_tau", &c.r.stress_total_tau_fs},
          {"/stress_virial_stderr_inflated", &c.r.stress_virial_inflated},
          {"/stress_total_stderr_inflated", &c.r.stress_total_inflated}};
      for (const auto& [name, m] : checks)
        f.write_matrix(name, to_row(*m));
      f.set_attr("/stress_virial_tau", "units", "fs (integrated autocorrelation time, D132)");
      f.set_attr("/stress_total_tau", "units", "fs (integrated autocorrelation time, D132)");
      f.set_attr("/stress_total_stderr_inflated", "definition",
                 "1: blocks shorter than 5 statistical inefficiencies, the standard error was "
                 "inflated to sqrt(2 tau var / n) (D132); 0: block standard error");
      f.write_matrix("/thermo", to_row(c.r.thermo));
      f.set_attr("/thermo", "units",
                 "columns: T (K), PE (kcal/mol), V (A^3), density (g/cm^3); step means");
    }
  }
  out.commit();
}

Checkpoint read_checkpoint(const std::string& dir) {
  const std::string p = ckpt_path(dir);
  if (!fs::exists(p)) fail(p, "", "", "no checkpoint (the case has not started)");
  h5::File f(p, h5::File::Mode::read);
  Checkpoint c;
  c.r.case_id = static_cast<int>(f.read_scalar("/case"));
  c.r.rows_done = static_cast<int>(f.read_scalar("/rows_done"));
  c.ref_box = f.read_vector("/reference_box");
  if (!f.exists("/lammps_version"))
    fail(p, "/lammps_version", "missing", "a case checkpoint names the LAMMPS that wrote it");
  c.lmp_version = f.read_string("/lammps_version");
  if (c.r.rows_done > 0) {
    c.r.strain = f.read_matrix("/strain");
    c.r.stress_virial = f.read_matrix("/stress_virial");
    c.r.stress_virial_se = f.read_matrix("/stress_virial_stderr");
    c.r.stress_total = f.read_matrix("/stress_total");
    c.r.stress_total_se = f.read_matrix("/stress_total_stderr");
    c.r.thermo = f.read_matrix("/thermo");
    // rows written before decision D132 have no autocorrelation check: NaN (not measured)
    const auto opt = [&](const char* name) -> PathM {
      if (f.exists(name)) return f.read_matrix(name);
      return PathM::Constant(c.r.rows_done, 6, std::nan(""));
    };
    c.r.stress_virial_tau_fs = opt("/stress_virial_tau");
    c.r.stress_total_tau_fs = opt("/stress_total_tau");
    c.r.stress_virial_inflated = opt("/stress_virial_stderr_inflated");
    c.r.stress_total_inflated = opt("/stress_total_stderr_inflated");
  } else {
    c.r.strain.resize(0, 6);
    c.r.stress_virial.resize(0, 6);
    c.r.stress_virial_se.resize(0, 6);
    c.r.stress_total.resize(0, 6);
    c.r.stress_total_se.resize(0, 6);
    c.r.thermo.resize(0, 4);
    c.r.stress_virial_tau_fs.resize(0, 6);
    c.r.stress_total_tau_fs.resize(0, 6);
    c.r.stress_virial_inflated.resize(0, 6);
    c.r.stress_total_inflated.resize(0, 6);
  }
  return c;
}

template <class M> void append_row(M& m, const Eigen::RowVectorXd& row) {
  m.conservativeResize(m.rows() + 1, Eigen::NoChange);
  m.row(m.rows() - 1) = row;
}

void read_state(md::Lammps& l, const DeformSpec& spec, const std::string& file) {
  l.cmd("clear");
  l.cmd("units real");
  l.cmd("atom_style " + spec.atom_style);
  l.cmd("read_restart " + md::lammps_path(file, "restart"));
  l.cmds(spec.force_field);
}

/// Static row (decision D120): no velocities, optional minimisation of the atom positions at
/// the fixed (remapped) box, then the stress of `run 0`. With zero velocities the kinetic term
/// vanishes, so the total and the virial stress agree.
void static_row(md::Lammps& l, const DeformSpec& spec, Eigen::RowVectorXd& sv,
                Eigen::RowVectorXd& st, Eigen::RowVectorXd& th) {
  l.cmd("velocity all set 0.0 0.0 0.0");
  l.cmd("compute pnc_pv all pressure NULL virial");
  l.cmd("thermo_style custom step temp pe press vol density pxx pyy pzz pxy pxz pyz "
        "c_pnc_pv[1] c_pnc_pv[2] c_pnc_pv[3] c_pnc_pv[4] c_pnc_pv[5] c_pnc_pv[6]");
  if (spec.minimize) {
    l.cmd("min_style cg");
    // etol 0: stop on the force norm (kcal/mol/A) or the iteration limits
    l.cmd(fmt::format("minimize 0.0 {:.10g} 10000 100000", kStaticFtol));
  }
  l.cmd("run 0");
  static constexpr int lmp_of_voigt[6] = {0, 1, 2, 5, 4, 3}; // pxx pyy pzz pxy pxz pyz
  for (int v = 0; v < 6; ++v) {
    sv[v] = -l.compute_value("pnc_pv", lmp_of_voigt[v]) * md::pa_per_atm;
    st[v] = -l.compute_value("thermo_press", lmp_of_voigt[v]) * md::pa_per_atm;
  }
  th[0] = l.thermo("temp");
  th[1] = l.thermo("pe");
  th[2] = l.thermo("vol");
  th[3] = l.thermo("density");
}

/// The progress line's stresses (MPa): every driven component of the case (D360), e.g.
/// "s11 = +12.3456 MPa" for a static row, "s11 = +12.34 +- 0.56 MPa (total; virial only
/// +12.10)" for a thermal one; a mixed case lists its components separated by ", ".
std::string driven_stresses(const damage::DeformationCase& dc, bool is_static,
                            const Eigen::RowVectorXd& st, const Eigen::RowVectorXd& stse,
                            const Eigen::RowVectorXd& sv, const Eigen::RowVectorXd& inflated) {
  static const char* const voigt_names[6] = {"11", "22", "33", "23", "13", "12"};
  std::string out;
  for (int v : dc.driven) {
    if (!out.empty()) out += ", ";
    if (is_static)
      out += fmt::format("s{} = {:+11.4f} MPa", voigt_names[v], st[v] * 1e-6);
    else
      out += fmt::format("s{} = {:+9.2f} +- {:.2f} MPa (total; virial only {:+.2f}{})",
                         voigt_names[v], st[v] * 1e-6, stse[v] * 1e-6, sv[v] * 1e-6,
                         inflated[v] > 0.5 ? "; blocks too short, error inflated" : "");
  }
  return out;
}

// D366: the rows of one case come from one LAMMPS. `stored` is the checkpoint's version key
// (YYYYMMDD; checkpoints before D366 hold "20210929 (Debian 20220106)": its leading date counts).
void check_lammps_version(const std::string& path, const std::string& stored,
                          const std::string& running) {
  const std::string date = stored.substr(0, stored.find_first_not_of("0123456789"));
  if (date != running)
    fail(path, "/lammps_version", stored,
         fmt::format("the case was started with LAMMPS {} and this pnc runs LAMMPS {}: a case is "
                     "resumed with the LAMMPS that started it (D366); resume with that LAMMPS, or "
                     "start the run again into a new --out without --resume",
                     stored, running));
}

/// A static (0 K) start state is often a perfect lattice with atoms exactly on the box's lower
/// faces, which a restart of a tilted box can lose by round-off (LAMMPS 2021 does not remap the
/// atoms of a one-file restart): a rigid translation by 1e-6 of the box keeps them inside in
/// every row, whose affine remaps keep fractional coordinates (decision D425).
void off_the_faces(md::Lammps& l) {
  const md::LmpBox b = l.box();
  l.cmd(fmt::format("displace_atoms all move {:.17g} {:.17g} {:.17g} units box", 1e-6 * b.length(0),
                    1e-6 * b.length(1), 1e-6 * b.length(2)));
}

void case_child(md::Lammps& l, const DeformSpec& spec, const std::string& dir, bool resume) {
  const damage::DeformationCase& dc = damage::deformation_case(spec.case_id); // D316
  // the stress is read in the box frame: a case must not rotate the box (upper triangular G)
  if (!dc.gradient.isUpperTriangular(0.0))
    fail("<deformation cases>", "case " + std::to_string(dc.id), dc.name,
         "the gradient of a deformation case must be upper triangular (D316)");
  const bool tilted = dc.gradient(0, 1) != 0 || dc.gradient(0, 2) != 0 || dc.gradient(1, 2) != 0;
  const double amplitude = amplitude_of(spec, dc);             // final strain of the case (D362)
  const std::string lmp_version = std::to_string(l.version()); // D366
  Checkpoint c;
  c.r.case_id = spec.case_id;
  c.lmp_version = lmp_version;
  if (resume && fs::exists(ckpt_path(dir))) {
    c = read_checkpoint(dir);
    if (c.r.case_id != spec.case_id)
      fail(ckpt_path(dir), "/case", std::to_string(c.r.case_id),
           fmt::format("the checkpoint is of another case than {}", spec.case_id));
    check_lammps_version(ckpt_path(dir), c.lmp_version, lmp_version);
    c.lmp_version = lmp_version; // the same date, written in today's form
    if (!fs::exists(prev_state(dir, c.r.rows_done)))
      fail(prev_state(dir, c.r.rows_done), "", "", "the checkpoint names a missing restart file");
  } else {
    read_state(l, spec, spec.start_state);
    if (tilted) {
      l.cmd("change_box all triclinic");
      // a long-range solver set up on the orthogonal box must be defined again on the
      // triclinic one (LAMMPS refuses to run otherwise): the force field once more
      l.cmds(spec.force_field);
    }
    if (spec.temperature == 0) off_the_faces(l); // D425
    c.ref_box = l.box().to_vector();
    l.cmd("write_restart " + md::lammps_path(prev_state(dir, 0), "--out"));
    c.r.strain.resize(0, 6);
    c.r.stress_virial.resize(0, 6);
    c.r.stress_virial_se.resize(0, 6);
    c.r.stress_total.resize(0, 6);
    c.r.stress_total_se.resize(0, 6);
    c.r.thermo.resize(0, 4);
    c.r.stress_virial_tau_fs.resize(0, 6);
    c.r.stress_total_tau_fs.resize(0, 6);
    c.r.stress_virial_inflated.resize(0, 6);
    c.r.stress_total_inflated.resize(0, 6);
    c.r.rows_done = 0;
    write_checkpoint(dir, spec, amplitude, c);
  }
  const int first = c.r.rows_done;
  // strain points 0..steps; those of an earlier session are reused, not in the rate (D345)
  pnc::Progress bar(fmt::format("case {} deformation", spec.case_id), spec.steps + 1,
                    "strain points");
  if (first > 0) bar.skip(first, "resumed");
  for (int k = first; k <= spec.steps; ++k) {
    const double t = amplitude * k / spec.steps;
    read_state(l, spec, prev_state(dir, k));
    l.cmd("reset_timestep 0");
    l.cmd(fmt::format("timestep {:.10g}", spec.timestep_fs));
    // Apply F(t) of the case to the reference box, remapping the atoms (D316).
    const std::string change = md::box_change(md::LmpBox::from_vector(c.ref_box, ckpt_path(dir)),
                                              damage::deformation_gradient(dc, t), ckpt_path(dir));
    if (!change.empty()) l.cmd(change);
    static constexpr int lmp_of_voigt[6] = {0, 1, 2, 5, 4, 3}; // pxx pyy pzz pxy pxz pyz
    Eigen::RowVectorXd sv(6), svse(6), st(6), stse(6), strain = Eigen::RowVectorXd::Zero(6), th(4);
    Eigen::RowVectorXd tv(6), tt(6), iv(6), it(6); // autocorrelation times (fs), inflated flags
    if (spec.temperature == 0) {
      static_row(l, spec, sv, st, th); // decision D120
      svse.setConstant(std::nan(""));  // not measured: never a weight (decision D120)
      stse.setConstant(std::nan(""));
      tv.setConstant(std::nan(""));
      tt.setConstant(std::nan(""));
      iv.setZero();
      it.setZero();
    } else {
      l.cmd("fix pnc_nve all nve");
      l.cmd(fmt::format("fix pnc_lan all langevin {0:.10g} {0:.10g} {1:.10g} {2} zero yes",
                        spec.temperature, spec.damp_fs, spec.seed + static_cast<std::uint64_t>(k)));
      l.cmd(fmt::format("fix pnc_mom all momentum {} linear 1 1 1", spec.momentum_every));
      l.cmd("compute pnc_pv all pressure NULL virial");
      l.cmd("variable pnc_vol equal vol");
      l.cmd("variable pnc_rho equal density");
      l.cmd(
          fmt::format("fix pnc_samp all vector {} c_pnc_pv[1] c_pnc_pv[2] c_pnc_pv[3] c_pnc_pv[4] "
                      "c_pnc_pv[5] c_pnc_pv[6] c_thermo_press[1] c_thermo_press[2] "
                      "c_thermo_press[3] c_thermo_press[4] c_thermo_press[5] c_thermo_press[6] "
                      "c_thermo_temp v_pnc_vol v_pnc_rho",
                      spec.sample_every));
      // potential energy is extensive: fix vector keeps it apart from the intensive columns
      l.cmd(fmt::format("fix pnc_pe all vector {} c_thermo_pe", spec.sample_every));
      l.cmd("thermo_style custom step temp pe press vol density pxx pyy pzz pxy pxz pyz");
      // decision D131: the zero-strain hold that measures the reference stress is longer
      const long hold = k == 0 ? spec.hold_steps * spec.reference_holds : spec.hold_steps;
      l.cmd(fmt::format("thermo {}", std::max<long>(1, hold / 10)));
      l.cmd(fmt::format("run {}", hold));
      // Samples: stored on every multiple of sample_every from step 0 through the hold;
      // the step-0 sample (the state just after the remap, before any hold) is left out.
      const int nrows = static_cast<int>(hold / spec.sample_every) + 1;
      std::vector<std::vector<double>> col(16); // 12 stresses, T, V, density, PE
      for (int i = 1; i < nrows; ++i) {
        for (int j = 0; j < 15; ++j)
          col[j].push_back(l.fix_value("pnc_samp", i, j));
        col[15].push_back(l.fix_value("pnc_pe", i));
      }
      const double dt_sample = spec.timestep_fs * spec.sample_every; // fs between samples
      for (int v = 0; v < 6; ++v) {
        // decision D132: block errors checked against the autocorrelation time
        const md::HoldEstimate h1 = md::checked_block_se(col[lmp_of_voigt[v]], spec.blocks);
        const md::HoldEstimate h2 = md::checked_block_se(col[6 + lmp_of_voigt[v]], spec.blocks);
        sv[v] = -h1.mean * md::pa_per_atm;
        svse[v] = h1.se * md::pa_per_atm;
        st[v] = -h2.mean * md::pa_per_atm;
        stse[v] = h2.se * md::pa_per_atm;
        tv[v] = h1.tau_int * dt_sample;
        tt[v] = h2.tau_int * dt_sample;
        iv[v] = h1.blocks_ok ? 0.0 : 1.0;
        it[v] = h2.blocks_ok ? 0.0 : 1.0;
      }
      th[0] = md::block_mean_se(col[12], spec.blocks).first; // T
      th[1] = md::block_mean_se(col[15], spec.blocks).first; // PE
      th[2] = md::block_mean_se(col[13], spec.blocks).first; // V
      th[3] = md::block_mean_se(col[14], spec.blocks).first; // density
    }
    strain = damage::case_strain(spec.case_id, t).transpose();
    l.cmd("write_restart " + md::lammps_path(state_path(dir, k), "--out"));
    append_row(c.r.strain, strain);
    append_row(c.r.stress_virial, sv);
    append_row(c.r.stress_virial_se, svse);
    append_row(c.r.stress_total, st);
    append_row(c.r.stress_total_se, stse);
    append_row(c.r.thermo, th);
    append_row(c.r.stress_virial_tau_fs, tv);
    append_row(c.r.stress_total_tau_fs, tt);
    append_row(c.r.stress_virial_inflated, iv);
    append_row(c.r.stress_total_inflated, it);
    c.r.rows_done = k + 1;
    write_checkpoint(dir, spec, amplitude, c);
    std::error_code ec;
    fs::remove(prev_state(dir, k), ec);
    const std::string stress = driven_stresses(dc, spec.temperature == 0, st, stse, sv, it);
    // the driven strain itself, so that a negative shear (D424) shows its sign
    const double e = strain[dc.driven.front()];
    if (spec.temperature == 0)
      bar.set(k + 1,
              fmt::format("step {}/{} strain {:+.6f}  {} (static)", k, spec.steps, e, stress));
    else
      bar.set(k + 1, fmt::format("step {}/{} strain {:+.5f}  {}  T = {:.1f} K", k, spec.steps, e,
                                 stress, th[0]));
    if (spec.abort_after_step == k) std::raise(SIGKILL);
  }
}

} // namespace

md::StageSpec case_stage(const DeformSpec& spec, const std::string& dir, int ranks) {
  md::StageSpec s;
  s.ranks = ranks;
  s.name = fmt::format("case {}", spec.case_id);
  s.log_path = (fs::path(dir) / "lammps.log").string();
  return s;
}

md::StageBody case_body(const DeformSpec& spec, const std::string& dir, bool resume) {
  spec.validate("<deform>");
  // paths that reach LAMMPS commands: refused here, in the parent, if they cannot be quoted
  md::lammps_path(spec.start_state, "restart");
  md::lammps_path(prev_state(dir, 0), "--out");
  make_output_directory(dir);
  return md::stoppable([spec, dir, resume](md::Lammps& l) { case_child(l, spec, dir, resume); });
}

md::StageOutcome run_case(const DeformSpec& spec, const std::string& dir, bool resume) {
  auto body = case_body(spec, dir, resume);
  md::StageOutcome o = md::run_stage(case_stage(spec, dir), body);
  pnc::throw_if_stopped(
      fmt::format("case {} stopped; its checkpoint {} is kept", spec.case_id, ckpt_path(dir)));
  return o;
}

CaseResult read_case(const std::string& dir) {
  return read_checkpoint(dir).r;
}

} // namespace pnc::rve
