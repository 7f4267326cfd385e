// work.h5 and work.csv of `pnc thermo work` (pnc/thermo/work.hpp).
#include "pnc/core/atomic_file.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"
#include "pnc/thermo/work.hpp"

#include <fmt/format.h>

#include <sstream>

namespace pnc::thermo {

namespace {

h5::RowMatrix rows(const damage::PathMatrix& m) {
  return h5::RowMatrix(m);
}

void put_matrix(h5::File& f, const std::string& name, const damage::PathMatrix& m,
                const char* units) {
  if (m.rows() == 0) return;
  f.write_matrix(name, rows(m));
  f.set_attr(name, "units", units);
}

void put_integral(h5::File& f, const std::string& g, const WorkIntegral& w, double v0) {
  f.write_vector(g + "/density", w.value);
  f.set_attr(g + "/density", "units", "J/m^3");
  std::vector<double> a, k;
  for (double x : w.value) {
    a.push_back(x * v0);
    k.push_back(x * v0 * units::kcal_mol_per_joule);
  }
  f.write_vector(g + "/energy", a);
  f.set_attr(g + "/energy", "units", "J");
  f.write_vector(g + "/energy_kcal_mol", k);
  f.set_attr(g + "/energy_kcal_mol", "units", "kcal/mol");
  if (!w.has_se) return;
  f.write_vector(g + "/density_stderr_indep", w.se_indep);
  f.set_attr(g + "/density_stderr_indep", "units", "J/m^3");
  f.set_attr(g + "/density_stderr_indep", "assumes", "independent points");
  f.write_vector(g + "/density_stderr_bound", w.se_bound);
  f.set_attr(g + "/density_stderr_bound", "units", "J/m^3");
  f.set_attr(g + "/density_stderr_bound", "assumes", "nothing (upper bound, any correlation)");
}

} // namespace

void write_work_h5(const std::string& path, const WorkResult& r) {
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    f.set_attr("/", "format", "pnc-thermo-work");
    std::string notes;
    for (const auto& n : r.notes)
      notes += n + ".\n";
    f.write_string("/notes", notes);
    f.write_scalar("/temperature", r.temperature);
    f.set_attr("/temperature", "units", "K");
    f.set_attr("/temperature", "meaning", r.runs == 2 ? "mean of the two runs" : "of the run");
    f.write_scalar("/volume", r.volume);
    f.set_attr("/volume", "units", "m^3");
    if (r.runs == 2) {
      f.write_scalar("/temperature_1", r.t1);
      f.set_attr("/temperature_1", "units", "K");
      f.write_scalar("/temperature_2", r.t2);
      f.set_attr("/temperature_2", "units", "K");
      f.set_attr("/volume", "meaning", "mean of the two runs' V0");
      f.write_scalar("/volume_1", r.volume1);
      f.set_attr("/volume_1", "units", "m^3");
      f.write_scalar("/volume_2", r.volume2);
      f.set_attr("/volume_2", "units", "m^3");
    }
    for (const auto& c : r.cases) {
      const std::string g = fmt::format("/case_{}", c.id);
      put_matrix(f, g + "/strain", c.strain, "1");
      put_matrix(f, g + "/stress", c.stress, "Pa");
      f.write_scalar(g + "/softening", c.softening ? 1.0 : 0.0);
      f.set_attr(g + "/softening", "units", "1 (flag)");
      put_integral(f, g + "/work", c.da, r.volume);
      if (r.runs == 2) {
        put_integral(f, g + "/work_T1", c.da1, r.volume1);
        put_integral(f, g + "/work_T2", c.da2, r.volume2);
        put_matrix(f, g + "/sigma_entropic", c.sigma_s, "Pa");
        put_matrix(f, g + "/sigma_entropic_stderr", c.sigma_s_se, "Pa");
        put_matrix(f, g + "/sigma_energetic", c.sigma_u, "Pa");
        put_matrix(f, g + "/sigma_energetic_stderr", c.sigma_u_se, "Pa");
        put_integral(f, g + "/work_entropic", c.da_s, r.volume);
        put_integral(f, g + "/work_energetic", c.da_u, r.volume);
      }
    }
  }
  out.commit();
}

void write_work_csv(const std::string& path, const WorkResult& r) {
  std::ostringstream o;
  o.precision(12);
  o << "case,point,e11_1,e22_1,e33_1,g23_1,g13_1,g12_1,da_J_per_m3,da_stderr_indep_J_per_m3,"
       "da_stderr_bound_J_per_m3,dA_J,dA_kcal_mol";
  if (r.runs == 2)
    o << ",da_entropic_J_per_m3,da_entropic_stderr_indep_J_per_m3,da_entropic_stderr_bound_J_per_"
         "m3,"
         "da_energetic_J_per_m3,da_energetic_stderr_indep_J_per_m3,da_energetic_stderr_bound_J_per_"
         "m3";
  o << '\n';
  for (const auto& c : r.cases)
    for (Eigen::Index k = 0; k < c.strain.rows(); ++k) {
      const auto i = static_cast<std::size_t>(k);
      o << c.id << ',' << k;
      for (int j = 0; j < 6; ++j)
        o << ',' << c.strain(k, j);
      o << ',' << c.da.value[i] << ',' << c.da.se_indep[i] << ',' << c.da.se_bound[i] << ','
        << c.da.value[i] * r.volume << ',' << c.da.value[i] * r.volume * units::kcal_mol_per_joule;
      if (r.runs == 2)
        o << ',' << c.da_s.value[i] << ',' << c.da_s.se_indep[i] << ',' << c.da_s.se_bound[i] << ','
          << c.da_u.value[i] << ',' << c.da_u.se_indep[i] << ',' << c.da_u.se_bound[i];
      o << '\n';
    }
  write_text_atomically(path, o.str());
}

} // namespace pnc::thermo
