#include "pnc/damage/card.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/version.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace pnc::damage {

namespace {
constexpr int kCardVersion = 2; // 2: /verdict, per-constant status, fit statistics
const double kNaN = std::numeric_limits<double>::quiet_NaN();

// A count or id stored as a double: converting NaN or a value beyond int is undefined
// behaviour, so it is checked first.
int to_int(double v, const std::string& path, const std::string& field) {
  if (!(v >= -2147483648.0 && v <= 2147483647.0)) {
    std::ostringstream s;
    s << v;
    fail(path, field, s.str(), "must be a whole number within the range of int");
  }
  return static_cast<int>(v);
}

// A /fit table: at least `cols` columns.
h5::RowMatrix read_table(const h5::File& f, const std::string& ds, Eigen::Index cols) {
  h5::RowMatrix m = f.read_matrix(ds);
  if (m.rows() > 0 && m.cols() < cols)
    fail(f.path(), ds, std::to_string(m.rows()) + "x" + std::to_string(m.cols()),
         "must have at least " + std::to_string(cols) + " columns");
  return m;
}
} // namespace

Card card_from_parameters(const NdmParameters& p, const std::string& note) {
  Card c;
  c.params = p;
  const std::size_t n = p.size();
  c.std_error.assign(n, kNaN);
  c.fitted.assign(n, false);
  c.status.assign(n, "given");
  c.note.assign(n, note);
  c.verdict.level = VerdictLevel::usable;
  c.verdict.reasons = {"constants given, not fitted here: " + note};
  return c;
}

Card card_from_fit(const FitReport& rep, const StressStrainData& data, const std::string& loss) {
  Card c;
  c.params = rep.params;
  c.std_error = rep.std_error;
  c.fitted = rep.fitted;
  c.status = rep.status;
  c.note = rep.note;
  c.verdict = rep.verdict;
  FitRecord& f = c.fit;
  f.present = true;
  f.data_source = data.source;
  try {
    f.data_hash = "fnv1a64:" + file_fnv1a64(data.source);
  } catch (const std::exception&) {
    f.data_hash = "unavailable";
  }
  f.stress_definition = data.stress_definition;
  f.termination = rep.termination;
  f.message = rep.message;
  f.loss = loss;
  f.error_model = rep.error_model;
  f.alpha_choice = rep.alpha_choice;
  f.strain_max = rep.strain_max;
  f.rows_beyond_strain_max = rep.rows_beyond_strain_max;
  f.stretch_max = rep.stretch_max;
  f.isotropic = rep.isotropic;
  f.chi2 = rep.chi2;
  f.chi2_p = rep.chi2_p;
  f.dof = rep.dof;
  f.converged = rep.converged;
  f.iterations = rep.iterations;
  f.residuals = rep.residuals;
  f.free_parameters = rep.free_parameters;
  f.initial_cost = rep.initial_cost;
  f.final_cost = rep.final_cost;
  f.seconds = rep.seconds;
  f.components = rep.components;
  f.regression = rep.regression;
  f.solver_report = rep.full_report;
  f.warnings = rep.warnings;
  return c;
}

void write_card(const std::string& path, Card card, const std::string& command) {
  validate(card.params, path);
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    const auto& names = constant_names(card.params.model);
    f.write_string("/model/law", "NDM (Nair 2010)");
    f.set_attr("/model", "variant", model_name(card.params.model));
    f.set_attr("/model", "card_version", kCardVersion);
    f.set_attr("/model", "decisions", "docs/decisions.md D1-D12");
    f.set_attr("/model", "voigt",
               "11,22,33,23,13,12; engineering shear strain; sigma = (C0 + C1(D)) eps");
    for (std::size_t i = 0; i < names.size(); ++i) {
      const std::string ds = "/constants/" + names[i];
      f.write_scalar(ds, card.params.k[i]);
      f.set_attr(ds, "units", constant_unit(names[i]));
      f.set_attr(ds, "std_error", i < card.std_error.size() ? card.std_error[i] : kNaN);
      f.set_attr(ds, "fitted", i < card.fitted.size() && card.fitted[i] ? "yes" : "no");
      f.set_attr(ds, "status", i < card.status.size() ? card.status[i] : "given");
      f.set_attr(ds, "note", i < card.note.size() ? card.note[i] : "");
    }
    {
      std::string reasons;
      for (const auto& r : card.verdict.reasons)
        reasons += r + "\n";
      f.write_string("/verdict/summary", verdict_name(card.verdict.level));
      f.set_attr("/verdict", "level", verdict_name(card.verdict.level));
      f.set_attr("/verdict", "reasons", reasons);
    }
    h5::RowMatrix R = card.params.R;
    f.write_matrix("/platelet_rotation", R);
    f.set_attr("/platelet_rotation", "units", "1 (x_local = R x_global)");
    if (card.fit.present) {
      const FitRecord& r = card.fit;
      f.write_string("/fit/solver_report", r.solver_report);
      f.set_attr("/fit", "data_source", r.data_source);
      f.set_attr("/fit", "data_hash", r.data_hash);
      f.set_attr("/fit", "stress_definition", r.stress_definition);
      f.set_attr("/fit", "termination", r.termination);
      f.set_attr("/fit", "message", r.message);
      f.set_attr("/fit", "loss", r.loss);
      f.set_attr("/fit", "converged", r.converged ? "yes" : "no");
      f.set_attr("/fit", "iterations", r.iterations);
      f.set_attr("/fit", "residuals", r.residuals);
      f.set_attr("/fit", "free_parameters", r.free_parameters);
      f.set_attr("/fit", "initial_cost", r.initial_cost);
      f.set_attr("/fit", "final_cost", r.final_cost);
      f.set_attr("/fit", "seconds", r.seconds);
      f.set_attr("/fit", "warnings", r.warnings);
      f.set_attr("/fit", "error_model", r.error_model);
      f.set_attr("/fit", "alpha_choice", r.alpha_choice);
      f.set_attr("/fit", "strain_max", r.strain_max);
      f.set_attr("/fit", "rows_beyond_strain_max", r.rows_beyond_strain_max);
      if (r.stretch_max > 0) f.set_attr("/fit", "stretch_max", r.stretch_max);          // D12m
      if (r.isotropic) f.set_attr("/fit", "isotropic", "yes");                          // D396
      if (!std::isnan(r.shape_error)) f.set_attr("/fit", "shape_error", r.shape_error); // D417
      f.set_attr("/fit", "chi2", r.chi2);
      f.set_attr("/fit", "dof", r.dof);
      f.set_attr("/fit", "chi2_p", r.chi2_p);
      h5::RowMatrix r2(static_cast<Eigen::Index>(r.components.size()), 10);
      for (std::size_t i = 0; i < r.components.size(); ++i) {
        const auto& c = r.components[i];
        r2.row(static_cast<Eigen::Index>(i)) << c.case_id, c.component, c.points, c.r2, c.rms,
            c.chi2, c.runs, c.runs_expected, c.runs_p, c.lag1;
      }
      f.write_matrix("/fit/r2", r2);
      f.set_attr("/fit/r2", "columns",
                 "case, component (Voigt 0..5), points, R^2, rms (Pa), chi^2 (1), runs, "
                 "expected runs, runs-test p, lag-1 autocorrelation");
      h5::RowMatrix reg(static_cast<Eigen::Index>(r.regression.size()), 5);
      std::ostringstream labels;
      for (std::size_t i = 0; i < r.regression.size(); ++i) {
        const auto& l = r.regression[i];
        reg.row(static_cast<Eigen::Index>(i)) << l.case_id, l.component, l.a, l.b, l.r2;
        labels << l.linear_label << ',' << l.damage_label << '\n';
      }
      f.write_matrix("/fit/regression", reg);
      f.set_attr("/fit/regression", "columns", "case, component, a (Pa), b (Pa), R^2");
      f.write_string("/fit/regression_labels", labels.str());
    }
    h5::write_provenance(f, command);
  }
  out.commit();
}

Card read_card(const std::string& path) {
  h5::File f(path, h5::File::Mode::read);
  if (!f.exists("/model")) fail(path, "/model", "", "not a pnc material card: group is missing");
  const auto variant = f.attr_string("/model", "variant");
  if (!variant) fail(path, "/model@variant", "", "required attribute is missing");
  const auto version = f.attr_double("/model", "card_version");
  if (!version || (*version != 1 && *version != kCardVersion))
    fail(path, "/model@card_version", version ? std::to_string(*version) : "",
         "this pnc reads card versions 1 and " + std::to_string(kCardVersion));
  Card c;
  c.params.model = parse_model(*variant, path + ": field '/model@variant'");
  const auto& names = constant_names(c.params.model);
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string ds = "/constants/" + names[i];
    c.params.k[i] = f.read_scalar(ds);
    const auto units = f.attr_string(ds, "units");
    if (units && *units != constant_unit(names[i]))
      fail(path, ds + "@units", *units, "must be " + constant_unit(names[i]) + " (SI)");
    c.std_error.push_back(f.attr_double(ds, "std_error").value_or(kNaN));
    c.fitted.push_back(f.attr_string(ds, "fitted").value_or("no") == "yes");
    c.status.push_back(f.attr_string(ds, "status").value_or(c.fitted.back() ? "fitted" : "held"));
    c.note.push_back(f.attr_string(ds, "note").value_or(""));
  }
  if (f.exists("/platelet_rotation")) {
    const auto R = f.read_matrix("/platelet_rotation");
    if (R.rows() != 3 || R.cols() != 3)
      fail(path, "/platelet_rotation", std::to_string(R.rows()) + "x" + std::to_string(R.cols()),
           "must be a 3x3 matrix");
    c.params.R = R;
  }
  validate(c.params, path);
  if (*version == 1) {
    c.verdict.level = VerdictLevel::usable_with_warnings;
    c.verdict.reasons = {"warning: card version 1 was written before cards carried a verdict; "
                         "refit it to have one"};
  } else {
    const auto level = f.attr_string("/verdict", "level");
    if (!level) fail(path, "/verdict@level", "", "required attribute is missing (card version 2)");
    c.verdict.level = parse_verdict(*level, path + ": field '/verdict@level'");
    std::istringstream reasons(f.attr_string("/verdict", "reasons").value_or(""));
    for (std::string line; std::getline(reasons, line);)
      if (!line.empty()) c.verdict.reasons.push_back(line);
  }
  if (f.exists("/fit")) {
    FitRecord& r = c.fit;
    r.present = true;
    r.data_source = f.attr_string("/fit", "data_source").value_or("");
    r.data_hash = f.attr_string("/fit", "data_hash").value_or("");
    r.stress_definition = f.attr_string("/fit", "stress_definition").value_or("");
    r.termination = f.attr_string("/fit", "termination").value_or("");
    r.message = f.attr_string("/fit", "message").value_or("");
    r.loss = f.attr_string("/fit", "loss").value_or("");
    r.converged = f.attr_string("/fit", "converged").value_or("no") == "yes";
    const auto count = [&](const char* name) {
      return to_int(f.attr_double("/fit", name).value_or(0), path, std::string("/fit@") + name);
    };
    r.iterations = count("iterations");
    r.residuals = count("residuals");
    r.free_parameters = count("free_parameters");
    r.initial_cost = f.attr_double("/fit", "initial_cost").value_or(kNaN);
    r.final_cost = f.attr_double("/fit", "final_cost").value_or(kNaN);
    r.seconds = f.attr_double("/fit", "seconds").value_or(kNaN);
    r.warnings = f.attr_string("/fit", "warnings").value_or("");
    r.error_model = f.attr_string("/fit", "error_model").value_or("");
    r.alpha_choice = f.attr_string("/fit", "alpha_choice").value_or("");
    r.strain_max = f.attr_double("/fit", "strain_max").value_or(0.0); // absent: every row
    if (!(r.strain_max >= 0 && r.strain_max <= 10))
      fail(path, "/fit@strain_max", std::to_string(r.strain_max), "must be in [0, 10]");
    r.rows_beyond_strain_max = count("rows_beyond_strain_max");
    r.stretch_max = f.attr_double("/fit", "stretch_max").value_or(0.0); // absent: none (D12m)
    if (!(r.stretch_max >= 0 && r.stretch_max <= 10))
      fail(path, "/fit@stretch_max", std::to_string(r.stretch_max), "must be in [0, 10]");
    const std::string iso = f.attr_string("/fit", "isotropic").value_or("no"); // D396
    if (iso != "yes" && iso != "no") fail(path, "/fit@isotropic", iso, "must be \"yes\" or \"no\"");
    r.isotropic = iso == "yes";
    r.shape_error = f.attr_double("/fit", "shape_error") // absent: not tested (D417)
                        .value_or(std::numeric_limits<double>::quiet_NaN());
    if (!(std::isnan(r.shape_error) || r.shape_error >= 0)) // +inf: a curve of zero stress
      fail(path, "/fit@shape_error", std::to_string(r.shape_error),
           "must be a share of the stress, >= 0");
    r.chi2 = f.attr_double("/fit", "chi2").value_or(kNaN);
    r.chi2_p = f.attr_double("/fit", "chi2_p").value_or(kNaN);
    r.dof = count("dof");
    if (f.exists("/fit/r2")) {
      const auto m = read_table(f, "/fit/r2", 5); // version 1: 5 columns, version 2: 10
      for (Eigen::Index i = 0; i < m.rows(); ++i) {
        const auto cell = [&](Eigen::Index j) {
          return to_int(m(i, j), path, "/fit/r2 (row " + std::to_string(i) + ")");
        };
        ComponentFit cf{cell(0), cell(1), cell(2), m(i, 3), m(i, 4)};
        if (m.cols() >= 10) {
          cf.chi2 = m(i, 5);
          cf.runs = cell(6);
          cf.runs_expected = m(i, 7);
          cf.runs_p = m(i, 8);
          cf.lag1 = m(i, 9);
        }
        r.components.push_back(cf);
      }
    }
    if (f.exists("/fit/regression")) {
      const auto m = read_table(f, "/fit/regression", 5);
      std::istringstream labels(
          f.exists("/fit/regression_labels") ? f.read_string("/fit/regression_labels") : "");
      for (Eigen::Index i = 0; i < m.rows(); ++i) {
        std::string line, lin, dam;
        std::getline(labels, line);
        const auto comma = line.find(',');
        lin = line.substr(0, comma);
        dam = comma == std::string::npos ? "" : line.substr(comma + 1);
        const std::string row = "/fit/regression (row " + std::to_string(i) + ")";
        r.regression.push_back({to_int(m(i, 0), path, row), to_int(m(i, 1), path, row), lin, dam,
                                m(i, 2), m(i, 3), m(i, 4)});
      }
    }
    if (f.exists("/fit/solver_report")) r.solver_report = f.read_string("/fit/solver_report");
  }
  c.software = f.attr_string("/", "software").value_or("");
  c.created = f.attr_string("/provenance", "created").value_or("");
  c.command = f.attr_string("/provenance", "command").value_or("");
  return c;
}

} // namespace pnc::damage
