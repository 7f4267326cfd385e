#include "drive_output.hpp"

#include "pnc/core/plot.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/csv.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/progress.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>

namespace pnc::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kUnitsLine =
    "# units: SI. strain dimensionless (engineering shear g23 = 2 eps23, ...), stress Pa, "
    "tangent ds_i/de_j Pa, energy densities (work, stored, dissipated) J/m^3; Voigt order "
    "11,22,33,23,13,12; step 0 is the virgin start";
// the CSV carries the units in its column names (D336); the comment line keeps what a name
// cannot say
constexpr const char* kCsvNoteLine =
    "# units: SI, in the column names (_Pa, _J_per_m3; no suffix: dimensionless). engineering "
    "shear g23 = 2 eps23, ...; tangent ds_i/de_j; Voigt order 11,22,33,23,13,12; step 0 is "
    "the virgin start";

/// The column-name suffix of a unit (docs/formats.md: `/` written `_per_`, powers as digits).
std::string unit_suffix(const std::string& u) {
  if (u == "1") return "";
  if (u == "Pa") return "_Pa";
  if (u == "J/m^3") return "_J_per_m3";
  throw std::logic_error("drive_table: no column suffix for unit " + u);
}

std::string tangent_name(int i, int j) {
  return fmt::format("d{}_d{}", kStressNames[static_cast<std::size_t>(i)],
                     kStrainNames[static_cast<std::size_t>(j)]);
}

enum class Kind { none, strain, stress, state, energy };

Kind column_kind(const std::string& name, const DriveTable& t, std::size_t c) {
  if (name == "step" || name == "segment" || name.rfind("newton_", 0) == 0) return Kind::none;
  if (t.units[c] == "J/m^3") return Kind::energy; // work, stored, dissipated
  if (t.units[c] == "Pa") return Kind::stress;    // stress and tangent
  if (name[0] == 'e' || name[0] == 'g') return Kind::strain;
  return Kind::state;
}

} // namespace

DriveTable drive_table(const DriveResult& r) {
  DriveTable t;
  auto col = [&](const std::string& n, const std::string& u) {
    t.names.push_back(n + unit_suffix(u)); // D336
    t.units.push_back(u);
  };
  col("step", "1");
  col("segment", "1");
  for (const char* n : kStrainNames)
    col(n, "1");
  for (const char* n : kStressNames)
    col(n, "Pa");
  for (const auto& n : r.state_names)
    col(n, "1");
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      col(tangent_name(i, j), "Pa");
  col("work", "J/m^3");
  col("stored", "J/m^3");
  col("dissipated", "J/m^3");
  col("newton_iterations", "1");
  col("newton_residual", "Pa");
  for (const auto& d : r.rows) {
    std::vector<double> row = {static_cast<double>(d.step), static_cast<double>(d.segment)};
    row.insert(row.end(), d.strain.begin(), d.strain.end());
    row.insert(row.end(), d.stress.begin(), d.stress.end());
    row.insert(row.end(), d.state.begin(), d.state.end());
    row.insert(row.end(), d.tangent.begin(), d.tangent.end());
    row.insert(row.end(), {d.work, d.stored, d.dissipated, static_cast<double>(d.newton_iterations),
                           d.newton_residual});
    t.rows.push_back(std::move(row));
  }
  return t;
}

std::string drive_csv(const DriveResult& r, const DriveMeta& meta) {
  const DriveTable t = drive_table(r);
  std::string s = fmt::format("# pnc material drive: card {} (model {}, verdict {}), plugin {}, "
                              "path {}\n",
                              meta.card, meta.model, meta.verdict, meta.plugin, meta.path);
  s += std::string(kCsvNoteLine) + "\n";
  if (!r.converged) s += "# stopped early: " + r.failure + "\n";
  for (std::size_t c = 0; c < t.names.size(); ++c)
    s += (c ? "," : "") + t.names[c];
  s += "\n";
  for (const auto& row : t.rows) {
    for (std::size_t c = 0; c < row.size(); ++c)
      s += fmt::format("{}{:.17g}", c ? "," : "", row[c]);
    s += "\n";
  }
  return s;
}

void write_drive_output(const std::string& out, const DriveResult& r, const DriveMeta& meta) {
  const std::string ext = fs::path(out).extension().string();
  if (ext == ".csv") {
    write_text_atomically(out, drive_csv(r, meta));
    return;
  }
  if (ext != ".h5") fail("<command line>", "--out", out, "the output file ends in .csv or .h5");
  AtomicOutput tmp(out);
  {
    h5::File f(tmp.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    const auto n = static_cast<Eigen::Index>(r.rows.size());
    const auto ns = static_cast<Eigen::Index>(r.state_names.size());
    h5::RowMatrix strain(n, 6), stress(n, 6), state(n, ns), tangent(n, 36), energy(n, 3);
    h5::RowMatrix step(n, 2), newton(n, 2);
    for (Eigen::Index k = 0; k < n; ++k) {
      const DriveRecord& d = r.rows[static_cast<std::size_t>(k)];
      for (int i = 0; i < 6; ++i) {
        strain(k, i) = d.strain[static_cast<std::size_t>(i)];
        stress(k, i) = d.stress[static_cast<std::size_t>(i)];
      }
      for (Eigen::Index i = 0; i < ns; ++i)
        state(k, i) = d.state[static_cast<std::size_t>(i)];
      for (int i = 0; i < 36; ++i)
        tangent(k, i) = d.tangent[static_cast<std::size_t>(i)];
      energy.row(k) << d.work, d.stored, d.dissipated;
      step.row(k) << d.step, d.segment;
      newton.row(k) << d.newton_iterations, d.newton_residual;
    }
    auto put = [&](const std::string& name, const h5::RowMatrix& m, const std::string& units,
                   const std::string& columns) {
      f.write_matrix(name, m);
      f.set_attr(name, "units", units);
      f.set_attr(name, "columns", columns);
    };
    std::string snames, tnames;
    for (const auto& s : r.state_names)
      snames += (snames.empty() ? "" : ",") + s;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        tnames += (tnames.empty() ? "" : ",") + tangent_name(i, j);
    put("/step", step, "1", "step,segment");
    put("/strain", strain, "1", "e11,e22,e33,g23,g13,g12 (engineering shear)");
    put("/stress", stress, "Pa", "s11,s22,s33,s23,s13,s12");
    put("/state", state, "1", snames);
    put("/tangent", tangent, "Pa", tnames + " (row-major d stress_i / d strain_j)");
    put("/energy", energy, "J/m^3", "work,stored,dissipated");
    put("/newton", newton, "1, Pa", "iterations (1),residual (Pa)");
    f.set_attr("/", "units", std::string(kUnitsLine + 9));
    f.set_attr("/", "card", meta.card);
    f.set_attr("/", "model", meta.model);
    f.set_attr("/", "verdict", meta.verdict);
    f.set_attr("/", "plugin", meta.plugin);
    f.set_attr("/", "path", meta.path);
    f.set_attr("/", "command", meta.command);
    f.set_attr("/", "converged", r.converged ? "yes" : "no: " + r.failure);
  }
  tmp.commit();
}

std::string plot_drive(const DriveResult& r, const DriveMeta& meta, const std::string& png) {
  check_output_file(png, "--plot");
  // the plot reads a private CSV next to the PNG, removed when done (never committed)
  AtomicOutput data(png + ".csv");
  {
    std::ofstream o(data.temp_path(), std::ios::trunc);
    o << drive_csv(r, meta);
    if (!o) fail(data.final_path(), "", "", "cannot write the plot data");
  }
  const std::string title =
      fs::path(meta.card).filename().string() + " along " + fs::path(meta.path).filename().string();
  // announced, as every plotting phase: it takes seconds (starting matplotlib), and the summary
  // lines come after it
  Phase phase("pnc material drive", "plotting " + png); // D344
  const auto wrote = run_plot_script("plot_drive.py", {data.temp_path(), png, title});
  if (!wrote.empty()) phase.done("plotted " + wrote.front());
  return wrote.empty() ? std::string() : wrote.front(); // no PNG: run_plot_script warned
}

std::vector<Mismatch> compare_reference(const DriveResult& r, const std::string& reference,
                                        const Tolerances& tol) {
  const CsvTable ref = read_csv(reference);
  const DriveTable t = drive_table(r);
  std::vector<std::size_t> col(ref.header.size());
  for (std::size_t rc = 0; rc < ref.header.size(); ++rc) {
    std::size_t c = 0;
    while (c < t.names.size() && t.names[c] != ref.header[rc])
      ++c;
    if (c == t.names.size()) {
      std::string hint; // a reference written before the units moved into the names (D336)
      for (std::size_t k = 0; k < t.names.size(); ++k)
        if (t.units[k] != "1" && t.names[k] == ref.header[rc] + unit_suffix(t.units[k]))
          hint = "; the column is now named " + t.names[k] + " (its unit in the name)";
      fail(reference, ref.header[rc], "",
           "not an output column of pnc material drive (docs/drive.md)" + hint);
    }
    col[rc] = c;
  }
  if (ref.rows.size() != t.rows.size())
    fail(reference, "rows", std::to_string(ref.rows.size()),
         fmt::format("the reference has {} steps (rows), this run {}: the path differs",
                     ref.rows.size(), t.rows.size()));
  std::vector<Mismatch> out;
  for (std::size_t rc = 0; rc < ref.header.size(); ++rc) {
    const std::string& name = ref.header[rc];
    const std::size_t c = col[rc];
    const Kind kind = column_kind(name, t, c);
    if (kind == Kind::none) continue;
    const double abs = kind == Kind::strain   ? tol.strain
                       : kind == Kind::stress ? tol.stress
                       : kind == Kind::state  ? tol.state
                                              : tol.energy;
    for (std::size_t k = 0; k < t.rows.size(); ++k) {
      const double v = t.rows[k][c], ref_v = ref.rows[k][rc];
      const double allowed = abs + tol.rel * std::abs(ref_v);
      if (!(std::abs(v - ref_v) <= allowed))
        out.push_back({static_cast<int>(t.rows[k][0]), name, v, ref_v, allowed});
    }
  }
  return out;
}

} // namespace pnc::app
