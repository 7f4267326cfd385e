#include "pnc/damage/data.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/csv.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/damage/reference.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace pnc::damage {

namespace {
const char* kStrainCols[6] = {"e11", "e22", "e33", "g23", "g13", "g12"};
const char* kStressCols[6] = {"s11", "s22", "s33", "s23", "s13", "s12"};
const char* kStderrCols[6] = {"sd11", "sd22", "sd33", "sd23", "sd13", "sd12"};
constexpr double kMPa = 1e6;
const char* kStrainUnitsRule =
    "the strain needs the attribute units = \"1 (engineering shear)\" (dimensionless)";

// Pa per unit of a stress dataset's `units` attribute (required: Pa, MPa or GPa).
double stress_scale(const h5::File& f, const std::string& path, const std::string& ds) {
  const auto su = f.attr_string(ds, "units");
  if (!su) fail(path, ds + "@units", "<missing>", "a stress dataset needs units Pa, MPa or GPa");
  if (*su == "Pa") return 1.0;
  if (*su == "MPa") return 1e6;
  if (*su == "GPa") return 1e9;
  fail(path, ds + "@units", *su, "stress units must be Pa, MPa or GPa");
}

// D342: a stress column of the CSV is <base>_<unit> with unit Pa, MPa or GPa, or (files
// written before the unit rule) the bare <base> in MPa. One spelling per column.
const char* kStressColumnRule =
    "a stress column is named <name>_Pa, <name>_MPa or <name>_GPa (the unit rule of "
    "docs/formats.md); the bare <name> of older files is read as MPa";

struct StressColumn {
  bool found = false;
  bool legacy = false; ///< the bare name (MPa)
  std::size_t index = 0;
  double scale = 1.0; ///< Pa per unit of the column
};

StressColumn find_stress_column(const CsvTable& t, const std::string& base, bool required) {
  StressColumn c;
  std::string first;
  for (std::size_t j = 0; j < t.header.size(); ++j) {
    const std::string& h = t.header[j];
    double scale = 0;
    if (h == base)
      scale = kMPa;
    else if (h.rfind(base + "_", 0) == 0) {
      const std::string unit = h.substr(base.size() + 1);
      scale = unit == "Pa" ? 1.0 : unit == "MPa" ? 1e6 : unit == "GPa" ? 1e9 : 0.0;
      if (scale == 0)
        fail(t.source, h, unit, std::string("unknown unit suffix: ") + kStressColumnRule);
    } else
      continue;
    if (c.found)
      fail(t.source, first + "/" + h, "both",
           "two columns give " + base + ": " + kStressColumnRule + "; keep one of them");
    c = {true, h == base, j, scale};
    first = h;
  }
  if (required && !c.found)
    fail(t.source, base + "_Pa", "",
         std::string("required column is missing from the header: ") + kStressColumnRule);
  return c;
}

std::string legacy_warning(const std::string& path, const std::vector<std::string>& cols) {
  std::string names;
  for (const auto& n : cols)
    names += (names.empty() ? "" : ",") + n;
  return path + ": columns " + names +
         " have no unit suffix and are read as MPa (deprecated; name them " + cols.front() +
         "_MPa ..., or write Pa as " + cols.front() + "_Pa ...)";
}
} // namespace

const CaseCurve* StressStrainData::find(int id) const {
  for (const auto& c : cases)
    if (c.id == id) return &c;
  return nullptr;
}

std::size_t StressStrainData::points() const {
  std::size_t n = 0;
  for (const auto& c : cases)
    n += static_cast<std::size_t>(c.strain.rows());
  return n;
}

StressStrainData read_stress_strain(const std::string& path) {
  auto ends_with = [&](const std::string& s) {
    return path.size() >= s.size() && path.compare(path.size() - s.size(), s.size(), s) == 0;
  };
  if (ends_with(".csv")) return read_stress_strain_csv(path);
  if (ends_with(".h5") || ends_with(".hdf5")) return read_stress_strain_h5(path);
  fail(path, "", "", "unknown data format: use a .csv or .h5 file");
}

StressStrainData read_stress_strain_csv(const std::string& path) {
  const CsvTable t = read_csv(path);
  const std::size_t jc = t.column("case");
  std::size_t je[6];
  StressColumn js[6], jd[6];
  std::vector<std::string> legacy;
  bool has_sd = true;
  for (int i = 0; i < 6; ++i) {
    je[i] = t.column(kStrainCols[i]);
    js[i] = find_stress_column(t, kStressCols[i], true);
    jd[i] = find_stress_column(t, kStderrCols[i], false);
    has_sd = has_sd && jd[i].found;
    if (js[i].legacy) legacy.push_back(kStressCols[i]);
  }
  for (int i = 0; i < 6; ++i)
    if (has_sd && jd[i].legacy) legacy.push_back(kStderrCols[i]);
  std::map<int, std::vector<std::size_t>> rows_of;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const double c = t.rows[r][jc];
    const std::string where = "case (line " + std::to_string(t.line_numbers[r]) + ")";
    std::ostringstream v;
    v << c;
    if (c != std::floor(c) || !(std::fabs(c) < 1e9) || !is_deformation_case(static_cast<int>(c)))
      fail(path, where, v.str(), deformation_case_rule());
    rows_of[static_cast<int>(c)].push_back(r);
    if (has_sd) {
      for (int i = 0; i < 6; ++i)
        if (t.rows[r][jd[i].index] < 0)
          fail(path, t.header[jd[i].index] + " (line " + std::to_string(t.line_numbers[r]) + ")",
               std::to_string(t.rows[r][jd[i].index]), "a standard error must be >= 0");
    }
  }
  if (rows_of.empty()) fail(path, "", "", "no data rows");
  StressStrainData d;
  d.source = path;
  d.stress_definition = "as supplied (CSV)";
  if (!legacy.empty()) d.warnings.push_back(legacy_warning(path, legacy));
  for (const auto& [id, rows] : rows_of) {
    CaseCurve c;
    c.id = id;
    const auto n = static_cast<Eigen::Index>(rows.size());
    c.strain.resize(n, 6);
    c.stress.resize(n, 6);
    if (has_sd) c.stress_stderr.resize(n, 6);
    for (Eigen::Index k = 0; k < n; ++k) {
      const auto& row = t.rows[rows[static_cast<std::size_t>(k)]];
      for (int i = 0; i < 6; ++i) {
        c.strain(k, i) = row[je[i]];
        c.stress(k, i) = row[js[i].index] * js[i].scale;
        if (has_sd) c.stress_stderr(k, i) = row[jd[i].index] * jd[i].scale;
      }
    }
    d.cases.push_back(std::move(c));
  }
  return d;
}

StressStrainData read_stress_strain_h5(const std::string& path) {
  h5::File f(path, h5::File::Mode::read);
  StressStrainData d;
  d.source = path;
  d.stress_definition = f.attr_string("/", "stress_definition").value_or("unknown");
  for (const std::string& name : f.children("/")) {
    if (name.rfind("case_", 0) != 0) continue;
    const std::string idtxt = name.substr(5);
    int id = 0;
    try {
      id = std::stoi(idtxt);
    } catch (...) {
      fail(path, "/" + name, idtxt,
           "group name must be case_<n> with n a case id: " + deformation_case_rule());
    }
    if (!is_deformation_case(id)) fail(path, "/" + name, idtxt, deformation_case_rule());
    if (d.find(id)) fail(path, "/" + name, idtxt, "two groups name the same case");
    CaseCurve c;
    c.id = id;
    const std::string g = "/" + name;
    const auto strain = f.read_matrix(g + "/strain");
    const auto stress = f.read_matrix(g + "/stress");
    if (strain.cols() != 6 || stress.cols() != 6 || strain.rows() != stress.rows())
      fail(path, g,
           std::to_string(strain.rows()) + "x" + std::to_string(strain.cols()) + " / " +
               std::to_string(stress.rows()) + "x" + std::to_string(stress.cols()),
           "strain and stress must both be k x 6 with the same k");
    const auto eu = f.attr_string(g + "/strain", "units");
    if (!eu) fail(path, g + "/strain@units", "<missing>", kStrainUnitsRule);
    if (eu->rfind("1", 0) != 0) fail(path, g + "/strain@units", *eu, kStrainUnitsRule);
    c.strain = strain;
    c.stress = stress * stress_scale(f, path, g + "/stress");
    if (!c.strain.allFinite() || !c.stress.allFinite())
      fail(path, g, "", "strain and stress must be finite numbers");
    if (f.exists(g + "/stress_stderr")) {
      const std::string ds = g + "/stress_stderr";
      const auto se = f.read_matrix(ds);
      if (se.rows() != stress.rows() || se.cols() != 6)
        fail(path, ds, std::to_string(se.rows()) + "x" + std::to_string(se.cols()),
             "must have the shape of stress (" + std::to_string(stress.rows()) + "x6)");
      for (Eigen::Index r = 0; r < se.rows(); ++r)
        for (Eigen::Index k = 0; k < 6; ++k)
          if (!(se(r, k) >= 0) || !std::isfinite(se(r, k))) {
            std::ostringstream v;
            v << se(r, k) << " (row " << r + 1 << ", column " << k + 1 << ")";
            fail(path, ds, v.str(), "a standard error must be a finite number >= 0");
          }
      c.stress_stderr = se * stress_scale(f, path, ds);
    }
    d.cases.push_back(std::move(c));
  }
  if (d.cases.empty()) fail(path, "/case_<n>", "", "no case groups found");
  std::sort(d.cases.begin(), d.cases.end(),
            [](const CaseCurve& a, const CaseCurve& b) { return a.id < b.id; });
  return d;
}

void write_stress_strain_csv(const std::string& path, const StressStrainData& d) {
  std::ostringstream s;
  s.precision(17); // max_digits10: the file reads back to the same doubles as the .h5 (D342)
  s << "# pnc stress-strain data; units in the column names (D342): strain dimensionless "
       "(engineering shear g = 2 e), stress and its standard error in Pa\n";
  s << "# source: " << d.stress_definition << "\n";
  bool sd = !d.cases.empty();
  for (const auto& c : d.cases)
    sd = sd && c.stress_stderr.rows() == c.stress.rows();
  s << "case";
  for (auto* n : kStrainCols)
    s << ',' << n;
  for (auto* n : kStressCols)
    s << ',' << n << "_Pa";
  if (sd)
    for (auto* n : kStderrCols)
      s << ',' << n << "_Pa";
  s << '\n';
  for (const auto& c : d.cases) {
    for (Eigen::Index k = 0; k < c.strain.rows(); ++k) {
      s << c.id;
      for (int i = 0; i < 6; ++i)
        s << ',' << c.strain(k, i);
      for (int i = 0; i < 6; ++i)
        s << ',' << c.stress(k, i);
      if (sd)
        for (int i = 0; i < 6; ++i)
          s << ',' << c.stress_stderr(k, i);
      s << '\n';
    }
  }
  write_text_atomically(path, s.str());
}

void write_stress_strain_h5(const std::string& path, const StressStrainData& d) {
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    f.set_attr("/", "stress_definition", d.stress_definition);
    f.set_attr("/", "format", "pnc cases v1: /case_<n>/{strain,stress,stress_stderr}");
    for (const auto& c : d.cases) {
      const std::string g = "/case_" + std::to_string(c.id);
      f.write_matrix(g + "/strain", c.strain);
      f.set_attr(g + "/strain", "units", "1 (engineering shear)");
      f.set_attr(g + "/strain", "columns", kStrainColumns);
      f.write_matrix(g + "/stress", c.stress);
      f.set_attr(g + "/stress", "units", "Pa");
      f.set_attr(g + "/stress", "columns", kStressColumns);
      if (c.stress_stderr.rows() == c.stress.rows()) {
        f.write_matrix(g + "/stress_stderr", c.stress_stderr);
        f.set_attr(g + "/stress_stderr", "units", "Pa");
        f.set_attr(g + "/stress_stderr", "columns", kStressColumns);
      }
    }
  }
  out.commit();
}

} // namespace pnc::damage
