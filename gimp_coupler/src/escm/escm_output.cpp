// CSV and VTU outputs of the ESCM coupler (escm.hpp): the energy log, point-cloud VTU files.
#include "coupler_impl.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/units.hpp"

#include <cstdint>
#include <sstream>

namespace pnc::gimp::escm {

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
                           int precision, const std::vector<FieldScalar>& field) {
  pnc::vtu::Frame f;
  f.field = field;
  f.points.reserve(x.size());
  for (const auto& p : x)
    f.points.push_back({p[0], p[1], p[2]});
  f.arrays.push_back(
      {"zone_index", "index", 1, {}, std::vector<std::int32_t>(zone.begin(), zone.end())});
  f.arrays.insert(f.arrays.end(), arrays.begin(), arrays.end());
  pnc::vtu::write_vtu(path, f, {pnc::vtu::Encoding::ascii, precision});
}

void Coupler::write_atoms_vtu(const std::string& path, const std::vector<PointArray>& extra,
                              const std::vector<FieldScalar>& field) const {
  using pnc::units::m_per_angstrom;
  using pnc::units::m_per_s_per_angstrom_per_fs;
  std::vector<int> ids;
  std::vector<Eigen::Vector3d> x, v;
  atoms(ids, x, v);
  const std::size_t n = x.size();
  std::vector<int> zone(n);
  std::vector<PointArray> arrays = {{"displacement_m", "m", 3, {}, {}},
                                    {"velocity_m_per_s", "m/s", 3, {}, {}}};
  for (std::size_t i = 0; i < n; ++i) {
    zone[i] = static_cast<int>(zone_of(ids[i]));
    const Eigen::Vector3d u = (x[i] - d_->x_init[i]) * m_per_angstrom;
    const Eigen::Vector3d vi = v[i] * m_per_s_per_angstrom_per_fs;
    arrays[0].values.insert(arrays[0].values.end(), {u[0], u[1], u[2]});
    arrays[1].values.insert(arrays[1].values.end(), {vi[0], vi[1], vi[2]});
    x[i] *= m_per_angstrom;
  }
  arrays.insert(arrays.end(), extra.begin(), extra.end());
  write_point_cloud_vtu(path, x, zone, arrays, 9, field);
}

} // namespace pnc::gimp::escm
