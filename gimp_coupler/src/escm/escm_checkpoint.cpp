// Checkpoint files of a coupled ESCM run (escm_checkpoint.hpp, docs/formats.md "ESCM
// checkpoint").
#include "pnc/gimp_coupler/escm_checkpoint.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/version.hpp"
#include "pnc/gimp_coupler/output.hpp"

#include <filesystem>

namespace pnc::gimp::escm {

namespace {

namespace fs = std::filesystem;
const char* kFormat = "pnc escm checkpoint 1";
constexpr int kEnergyCols = 13;

h5::RowMatrix vec2(const std::vector<Eigen::Vector2d>& v) {
  h5::RowMatrix m(static_cast<Eigen::Index>(v.size()), 2);
  for (std::size_t i = 0; i < v.size(); ++i)
    m.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  return m;
}

std::vector<Eigen::Vector2d> vec2(const h5::RowMatrix& m) {
  std::vector<Eigen::Vector2d> v(static_cast<std::size_t>(m.rows()));
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    v[static_cast<std::size_t>(i)] = Eigen::Vector2d(m(i, 0), m(i, 1));
  return v;
}

h5::RowMatrix per_atom(const std::vector<double>& v, Eigen::Index cols) {
  h5::RowMatrix m(static_cast<Eigen::Index>(v.size()) / cols, cols);
  for (std::size_t i = 0; i < v.size(); ++i)
    m.data()[i] = v[i];
  return m;
}

std::vector<double> flat(const h5::RowMatrix& m) {
  return std::vector<double>(m.data(), m.data() + m.size());
}

std::vector<double> energy_row(const EnergyRow& r) {
  return {static_cast<double>(r.step),
          r.time_s,
          r.cont_kinetic,
          r.cont_strain,
          r.md_kinetic,
          r.md_potential,
          r.work_boundary,
          r.work_cont_on_md,
          r.work_md_on_cont,
          r.heat_removed_int,
          r.heat_removed_ivc,
          r.heat_removed_cont,
          r.initial};
}

EnergyRow energy_row(const double* d) {
  EnergyRow r;
  r.step = static_cast<long>(d[0]);
  r.time_s = d[1];
  r.cont_kinetic = d[2];
  r.cont_strain = d[3];
  r.md_kinetic = d[4];
  r.md_potential = d[5];
  r.work_boundary = d[6];
  r.work_cont_on_md = d[7];
  r.work_md_on_cont = d[8];
  r.heat_removed_int = d[9];
  r.heat_removed_ivc = d[10];
  r.heat_removed_cont = d[11];
  r.initial = d[12];
  return r;
}

} // namespace

std::string checkpoint_path(const std::string& dir) {
  return (fs::path(dir) / "checkpoint.h5").string();
}

std::size_t write_coupled_checkpoint(const std::string& dir, const Solver<2>& s,
                                     CoupledCheckpoint& c) {
  const std::string main = checkpoint_path(dir);
  // The continuum part goes to the name the current checkpoint.h5 does not use.
  std::string previous;
  if (fs::exists(main)) {
    try {
      h5::File f(main, h5::File::Mode::read);
      if (f.exists("/continuum_file")) previous = f.read_string("/continuum_file");
    } catch (const std::exception&) {
      previous.clear();
    }
  }
  c.continuum_file = previous == "checkpoint_continuum_0.h5" ? "checkpoint_continuum_1.h5"
                                                             : "checkpoint_continuum_0.h5";
  const std::string cont = (fs::path(dir) / c.continuum_file).string();
  CheckpointExtra x; // no GIMP output bookkeeping: the coupled run keeps its own
  write_checkpoint<2>(cont, s, x);

  AtomicOutput out(main);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    const CouplerState& st = c.coupler;
    f.write_string("/format", kFormat);
    f.write_string("/continuum_file", c.continuum_file);
    f.write_string("/run/input_path", c.input_path);
    f.write_string("/run/input", c.input_text);
    f.write_scalar("/run/short", c.short_mode ? 1.0 : 0.0);
    f.write_scalar("/run/step", c.step);
    f.write_scalar("/run/nsteps", c.nsteps);
    f.write_scalar("/run/time", c.time_s);
    f.set_attr("/run/time", "units", "s");
    f.write_scalar("/run/wall", c.wall_s);
    f.set_attr("/run/wall", "units", "s");
    for (const auto& [name, text] : c.texts)
      if (!text.empty()) f.write_string("/run/text/" + name, text);
    for (const auto& [name, t] : c.tables)
      if (t.rows() > 0 && t.cols() > 0) f.write_matrix("/run/table/" + name, t);
    // Coupler
    auto cells = [&](const std::string& name, const std::vector<Eigen::Vector2d>& v,
                     const char* units) {
      if (v.empty()) return;
      f.write_matrix("/coupler/ivc/" + name, vec2(v));
      f.set_attr("/coupler/ivc/" + name, "units", units);
    };
    cells("mean", st.mean_A, "A");
    cells("prev_mean", st.prev_mean_A, "A");
    cells("velocity", st.velocity_mps, "m/s");
    cells("force", st.force_N, "N/m");
    cells("atom_force", st.atom_force, "kcal/mol/A");
    if (!st.log.empty()) {
      h5::RowMatrix e(static_cast<Eigen::Index>(st.log.size()), kEnergyCols);
      for (std::size_t i = 0; i < st.log.size(); ++i) {
        const auto row = energy_row(st.log[i]);
        for (int j = 0; j < kEnergyCols; ++j)
          e(static_cast<Eigen::Index>(i), j) = row[static_cast<std::size_t>(j)];
      }
      f.write_matrix("/coupler/energy_log", e);
      f.set_attr("/coupler/energy_log", "units", "1, s, J (slab) x 11");
    }
    f.write_vector("/coupler/acc", energy_row(st.acc));
    f.set_attr("/coupler/acc", "units", "1, s, J (slab) x 11");
    f.write_scalar("/coupler/pe0", st.pe0);
    f.set_attr("/coupler/pe0", "units", "kcal/mol");
    f.write_vector("/coupler/heat_offset", {st.heat_offset_int, st.heat_offset_ivc});
    f.set_attr("/coupler/heat_offset", "units", "J");
    f.write_scalar("/coupler/prescribed_work", st.prescribed_work);
    f.set_attr("/coupler/prescribed_work", "units", "J/m");
    f.write_scalar("/coupler/segment", st.segment);
    f.write_scalar("/coupler/md_step", st.md_step);
    f.write_vector("/coupler/timing",
                   {st.timing.lammps, st.timing.callback, st.timing.continuum, st.timing.coupling});
    f.set_attr("/coupler/timing", "units", "s");
    // LAMMPS atoms by id - 1
    f.write_matrix("/lammps/x", per_atom(st.x, 3));
    f.set_attr("/lammps/x", "units", "A");
    f.write_matrix("/lammps/v", per_atom(st.v, 3));
    f.set_attr("/lammps/v", "units", "A/fs");
    f.write_matrix("/lammps/f", per_atom(st.f, 3));
    f.set_attr("/lammps/f", "units", "kcal/mol/A");
    f.write_matrix("/lammps/image",
                   per_atom(std::vector<double>(st.image.begin(), st.image.end()), 3));
    f.write_integers("/lammps/type", {st.type.begin(), st.type.end()});
  }
  out.commit();
  return static_cast<std::size_t>(fs::file_size(main) + fs::file_size(cont));
}

CoupledCheckpoint read_coupled_checkpoint(const std::string& dir) {
  const std::string path = checkpoint_path(dir);
  h5::File f(path, h5::File::Mode::read);
  if (!f.exists("/format") || f.read_string("/format") != kFormat)
    fail(path, "/format", f.exists("/format") ? f.read_string("/format") : "<missing>",
         "not a pnc ESCM checkpoint (\"" + std::string(kFormat) + "\")");
  CoupledCheckpoint c;
  c.continuum_file = f.read_string("/continuum_file");
  c.input_path = f.read_string("/run/input_path");
  c.input_text = f.read_string("/run/input");
  c.short_mode = f.read_scalar("/run/short") != 0.0;
  c.step = static_cast<long>(f.read_scalar("/run/step"));
  c.nsteps = static_cast<long>(f.read_scalar("/run/nsteps"));
  c.time_s = f.read_scalar("/run/time");
  c.wall_s = f.read_scalar("/run/wall");
  if (f.exists("/run/text"))
    for (const std::string& n : f.children("/run/text"))
      c.texts[n] = f.read_string("/run/text/" + n);
  if (f.exists("/run/table"))
    for (const std::string& n : f.children("/run/table"))
      c.tables[n] = f.read_matrix("/run/table/" + n);
  CouplerState& st = c.coupler;
  auto cells = [&](const std::string& name) {
    const std::string d = "/coupler/ivc/" + name;
    return f.exists(d) ? vec2(f.read_matrix(d)) : std::vector<Eigen::Vector2d>{};
  };
  st.mean_A = cells("mean");
  st.prev_mean_A = cells("prev_mean");
  st.velocity_mps = cells("velocity");
  st.force_N = cells("force");
  st.atom_force = cells("atom_force");
  if (f.exists("/coupler/energy_log")) {
    const h5::RowMatrix e = f.read_matrix("/coupler/energy_log");
    if (e.cols() != kEnergyCols)
      fail(path, "/coupler/energy_log", std::to_string(e.cols()) + " columns",
           "must have " + std::to_string(kEnergyCols));
    for (Eigen::Index i = 0; i < e.rows(); ++i)
      st.log.push_back(energy_row(e.row(i).data()));
  }
  const auto acc = f.read_vector("/coupler/acc");
  if (acc.size() != kEnergyCols)
    fail(path, "/coupler/acc", std::to_string(acc.size()) + " values",
         "must have " + std::to_string(kEnergyCols));
  st.acc = energy_row(acc.data());
  st.pe0 = f.read_scalar("/coupler/pe0");
  const auto ho = f.read_vector("/coupler/heat_offset");
  st.heat_offset_int = ho.at(0);
  st.heat_offset_ivc = ho.at(1);
  st.prescribed_work = f.read_scalar("/coupler/prescribed_work");
  st.segment = static_cast<int>(f.read_scalar("/coupler/segment"));
  st.md_step = static_cast<long>(f.read_scalar("/coupler/md_step"));
  const auto tm = f.read_vector("/coupler/timing");
  st.timing.lammps = tm.at(0);
  st.timing.callback = tm.at(1);
  st.timing.continuum = tm.at(2);
  st.timing.coupling = tm.at(3);
  st.x = flat(f.read_matrix("/lammps/x"));
  st.v = flat(f.read_matrix("/lammps/v"));
  st.f = flat(f.read_matrix("/lammps/f"));
  for (double d : flat(f.read_matrix("/lammps/image")))
    st.image.push_back(static_cast<int>(d));
  for (double d : f.read_vector("/lammps/type"))
    st.type.push_back(static_cast<int>(d));
  return c;
}

void restore_continuum(const std::string& dir, const CoupledCheckpoint& c, Solver<2>& s) {
  const std::string cont = (fs::path(dir) / c.continuum_file).string();
  if (!fs::exists(cont))
    fail(checkpoint_path(dir), "/continuum_file", c.continuum_file,
         "the continuum part of the checkpoint is missing (" + cont + ")");
  CheckpointExtra x;
  read_checkpoint<2>(cont, s, x);
  if (s.steps != c.step)
    fail(cont, "/steps", std::to_string(s.steps),
         "does not belong to " + checkpoint_path(dir) + " (step " + std::to_string(c.step) + ")");
  s.initialize(false);
}

} // namespace pnc::gimp::escm
