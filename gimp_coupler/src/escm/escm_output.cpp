// CSV and VTU outputs of the ESCM coupler (escm.hpp): the energy log, point-cloud VTU files.
#include "coupler_impl.hpp"

#include "pnc/core/atomic_file.hpp"

#include <sstream>
#include <stdexcept>

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
