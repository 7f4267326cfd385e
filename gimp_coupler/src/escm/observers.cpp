// The energy log, profile and VTU frame observers of a coupled run (observers.hpp).
#include "observers.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/vtu.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

namespace pnc::gimp::escm {

namespace {

/// energy.csv: the coupler's energy log (its rows live in the coupler and its checkpoint).
class EnergyLog final : public Observer {
public:
  void write(const CoupledRun& run, CoupleSummary& r) const override {
    r.energy_csv = run.out_dir() + "/energy.csv";
    run.coupler().write_energy_csv(r.energy_csv);
  }
};

/// profile.csv: along the block's middle cell row (the row just above the crack line in Cases
/// II/III), at every frame, the displacement along the load and its gradient across the crack
/// line, for the continuum particles and the atoms (mean per cell column).
class Profile final : public Observer {
public:
  explicit Profile(const CoupledRun& run) {
    const CoupleInput& p = run.input();
    ucomp_ = p.load == "tension_y" ? 1 : 0;
    gcol_ = p.load == "tension_x" ? 0 : 1;
    const std::string uname = ucomp_ ? "uy_m" : "ux_m";
    const std::string gname = std::string(ucomp_ ? "duy" : "dux") + (gcol_ ? "_dY" : "_dX");
    prof_.precision(10);
    prof_ << "time_s,x_m," << uname << ",source," << gname << '\n';
    jmid_ = p.block_y0() + p.nby / 2;
  }

  void on_frame(const CoupledRun& run, long) override {
    const Solver<2>& s = run.solver();
    const Coupler& cp = run.coupler();
    const GradientTracker& grad = run.gradient();
    const std::vector<Eigen::Vector3d>& gax = run.atoms_x();
    const double h = run.cell_size();
    for (std::size_t k = 0; k < s.particles.size(); ++k) {
      const auto& x0 = s.particles.x0[k];
      if (static_cast<int>(std::floor(x0[1] / h)) != jmid_) continue;
      prof_ << s.time << ',' << x0[0] << ',' << s.particles.x[k][ucomp_] - x0[ucomp_]
            << ",continuum," << grad.H(k)(ucomp_, gcol_) << '\n';
    }
    std::map<int, std::array<double, 4>> acc; // cell i -> (x0 sum, u sum, n, gradient sum)
    for (std::size_t k = 0; k < gax.size(); ++k) {
      const Eigen::Vector2d x0 = cp.to_continuum(cp.atoms_initial()[k]);
      if (static_cast<int>(std::floor(x0[1] / h)) != jmid_) continue;
      auto& a = acc[static_cast<int>(std::floor(x0[0] / h))];
      a[0] += x0[0];
      a[1] += (cp.to_continuum(gax[k]) - x0)[ucomp_];
      a[2] += 1;
      a[3] += grad.H(run.continuum_points() + k)(ucomp_, gcol_);
    }
    for (const auto& [i, a] : acc)
      prof_ << s.time << ',' << a[0] / a[2] << ',' << a[1] / a[2] << ",md," << a[3] / a[2] << '\n';
  }

  void save(CoupledCheckpoint& ck) const override { ck.texts["profile_csv"] = prof_.str(); }
  void restore(const CoupledCheckpoint& ck, const std::string&) override {
    prof_.str("");
    prof_ << checkpoint_text(ck, "profile_csv");
  }
  void write(const CoupledRun& run, CoupleSummary& r) const override {
    r.profile_csv = run.out_dir() + "/profile.csv";
    pnc::write_text_atomically(r.profile_csv, prof_.str());
  }

private:
  int ucomp_ = 0, gcol_ = 0, jmid_ = 0;
  std::ostringstream prof_;
};

/// Continuum particles as a VTU point cloud (SI: m, m/s): zone_index (-1 ordinary continuum,
/// 1 IVC probe, 2 SVC), displacement_m, velocity_m_per_s, deformation_gradient_solver_1 (the
/// GIMP solver's F as a 9-component tensor, F33 = 1 in plane strain), then `extra`, and the field
/// data `field`.
void write_particles_vtu(const std::string& path, const Solver<2>& s, const std::vector<int>& zone,
                         const std::vector<PointArray>& extra,
                         const std::vector<FieldScalar>& field) {
  const std::size_t n = s.particles.size();
  std::vector<Eigen::Vector3d> x(n);
  std::vector<PointArray> arrays = {{"displacement_m", "m", 3, {}, {}},
                                    {"velocity_m_per_s", "m/s", 3, {}, {}},
                                    {"deformation_gradient_solver_1", "1", 9, {}, {}}};
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& xi = s.particles.x[i];
    const Eigen::Vector2d u = xi - s.particles.x0[i];
    const Eigen::Vector2d& v = s.particles.v[i];
    const auto& F = s.particles.F[i];
    x[i] = Eigen::Vector3d(xi[0], xi[1], 0.0);
    arrays[0].values.insert(arrays[0].values.end(), {u[0], u[1], 0.0});
    arrays[1].values.insert(arrays[1].values.end(), {v[0], v[1], 0.0});
    arrays[2].values.insert(arrays[2].values.end(),
                            {F(0, 0), F(0, 1), 0.0, F(1, 0), F(1, 1), 0.0, 0.0, 0.0, 1.0});
  }
  arrays.insert(arrays.end(), extra.begin(), extra.end());
  write_point_cloud_vtu(path, x, zone, arrays, 12, field);
}

std::string join_lines(const std::vector<std::string>& v) {
  std::string o;
  for (const auto& x : v)
    o += x + "\n";
  return o;
}

std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> v;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);)
    if (!l.empty()) v.push_back(l);
  return v;
}

/// The frame index k of a frame file ".../<name>_<k>.vtu" (written by Frames below).
double frame_index_of(const std::string& path) {
  const auto us = path.find_last_of('_'), dot = path.rfind(".vtu");
  return std::stod(path.substr(us + 1, dot - us - 1));
}

/// `dir`/<name>: the PVD series of `files` (frames of this run, resumed ones included), the
/// timestep of each its frame index, strictly increasing; the physical time is each frame's
/// field data `time_s` (D236).
void write_frame_pvd(const std::string& dir, const std::string& name,
                     const std::vector<std::string>& files) {
  std::vector<pnc::vtu::PvdEntry> entries;
  for (const auto& f : files)
    entries.push_back({std::filesystem::path(f).filename().string(), frame_index_of(f)});
  pnc::vtu::write_pvd(dir + "/" + name, entries);
}

/// atoms_<k>.vtu (Coupler::write_atoms_vtu) and particles_<k>.vtu at every frame, both with
/// the displacement gradients (D79), the field data time_s and frame_index, and the series
/// atoms.pvd and particles.pvd rewritten after each frame.
class Frames final : public Observer {
public:
  void on_frame(const CoupledRun& run, long index) override {
    const std::string idx = std::to_string(index);
    const std::vector<FieldScalar> field = {{"time_s", "s", run.solver().time},
                                            {"frame_index", "index", static_cast<double>(index)}};
    const std::string f = run.out_dir() + "/atoms_" + idx + ".vtu";
    run.coupler().write_atoms_vtu(
        f, run.gradient_arrays(run.continuum_points(), run.gradient_points()), field);
    frames_.push_back(f);
    const std::string fp = run.out_dir() + "/particles_" + idx + ".vtu";
    write_particles_vtu(fp, run.solver(), run.particle_zones(),
                        run.gradient_arrays(0, run.continuum_points()), field);
    particle_frames_.push_back(fp);
    write_frame_pvd(run.out_dir(), "atoms.pvd", frames_);
    write_frame_pvd(run.out_dir(), "particles.pvd", particle_frames_);
  }
  void save(CoupledCheckpoint& ck) const override {
    ck.texts["frames"] = join_lines(frames_);
    ck.texts["particle_frames"] = join_lines(particle_frames_);
  }
  void restore(const CoupledCheckpoint& ck, const std::string&) override {
    frames_ = split_lines(checkpoint_text(ck, "frames"));
    particle_frames_ = split_lines(checkpoint_text(ck, "particle_frames"));
  }
  void write(const CoupledRun&, CoupleSummary& r) const override {
    r.frames = frames_;
    r.particle_frames = particle_frames_;
  }
  void summarize(const CoupledRun&, nlohmann::json& sj) const override {
    sj["particle_frames"] = particle_frames_;
  }

private:
  std::vector<std::string> frames_, particle_frames_;
};

} // namespace

std::unique_ptr<Observer> make_energy_log() {
  return std::make_unique<EnergyLog>();
}
std::unique_ptr<Observer> make_profile(const CoupledRun& run) {
  return std::make_unique<Profile>(run);
}
std::unique_ptr<Observer> make_frames() {
  return std::make_unique<Frames>();
}

} // namespace pnc::gimp::escm
