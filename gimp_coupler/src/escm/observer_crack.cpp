// The crack observer of Cases II/III (observers.hpp; docs/escm.md "Cases II and III",
// D80-D84): J and growth of the continuum crack every crack.every coupled steps, the atomistic
// separation across the same line, crack.csv and the "crack" block of summary.json.
#include "observers.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/gimp_coupler/fracture.hpp"

#include <fmt/format.h>

#include <iostream>
#include <sstream>

namespace pnc::gimp::escm {

namespace {

using json = nlohmann::json;

/// One row of crack.csv and the quantities the summary needs (Cases II/III).
struct CrackRecord {
  double time = 0.0;
  TipResult tip;
  int increments = 0;
  AtomisticCrack md;
};

std::string crack_csv_header() {
  return "time_s,tip_x_m,crack_length_m,increments,J_J_per_m2,GI_J_per_m2,GII_J_per_m2,"
         "opening_m,sliding_m,md_bonds,md_broken_bonds,md_separated_columns,md_crack_length_m,"
         "md_entry_opening_m,md_entry_sliding_m,md_max_opening_m,md_max_abs_sliding_m,"
         "md_slipped_columns\n";
}

std::string crack_csv_row(const CrackRecord& c) {
  std::ostringstream o;
  o.precision(10);
  const double A = units::m_per_A;
  o << c.time << ',' << c.tip.tip[0] << ',' << c.tip.length << ',' << c.increments << ',' << c.tip.J
    << ',' << c.tip.GI << ',' << c.tip.GII << ',' << c.tip.opening << ',' << c.tip.sliding << ','
    << c.md.bonds << ',' << c.md.broken << ',' << c.md.separated_columns << ',' << c.md.length_A * A
    << ',' << c.md.entry_opening_A * A << ',' << c.md.entry_sliding_A * A << ','
    << c.md.max_opening_A * A << ',' << c.md.max_abs_sliding_A * A << ',' << c.md.slipped_columns
    << '\n';
  return o.str();
}

json crack_json(const CrackRecord& c) {
  const double A = units::m_per_A;
  return {{"time_s", c.time},
          {"tip_x_m", c.tip.tip[0]},
          {"crack_length_m", c.tip.length},
          {"increments", c.increments},
          {"J_J_per_m2", c.tip.J},
          {"GI_J_per_m2", c.tip.GI},
          {"GII_J_per_m2", c.tip.GII},
          {"opening_m", c.tip.opening},
          {"sliding_m", c.tip.sliding},
          {"md_bonds", c.md.bonds},
          {"md_broken_bonds", c.md.broken},
          {"md_separated_columns", c.md.separated_columns},
          {"md_columns", c.md.columns},
          {"md_crack_length_m", c.md.length_A * A},
          {"md_entry_opening_m", c.md.entry_opening_A * A},
          {"md_entry_sliding_m", c.md.entry_sliding_A * A},
          {"md_max_opening_m", c.md.max_opening_A * A},
          {"md_max_abs_sliding_m", c.md.max_abs_sliding_A * A},
          {"md_slipped_columns", c.md.slipped_columns}};
}

/// The "crack" block of summary.json: the continuum tip at the end, when it reached the stop
/// before the block (D81), when the first bond across the line broke and when the first column
/// separated (D82), the last record and the per-frame records.
json crack_summary(const std::vector<CrackRecord>& log, const json& frames, const CoupleInput& p,
                   double h, int max_increments) {
  const int bx0 = (p.ncx - p.nbx) / 2;
  json cj;
  cj["initial_tip_x_m"] = (p.crack_cells + 0.5) * h;
  cj["stop_tip_x_m"] = (bx0 - 0.5) * h;
  cj["block_x_m"] = bx0 * h;
  cj["max_increments"] = max_increments;
  cj["evaluations"] = log.size();
  json none; // null when it did not happen
  cj["time_tip_reached_stop_s"] = none;
  cj["time_first_broken_bond_s"] = none;
  cj["time_first_separated_column_s"] = none;
  cj["time_first_slipped_column_s"] = none;
  for (const CrackRecord& c : log) {
    if (cj["time_tip_reached_stop_s"].is_null() && c.increments >= max_increments)
      cj["time_tip_reached_stop_s"] = c.time;
    if (cj["time_first_broken_bond_s"].is_null() && c.md.broken > 0)
      cj["time_first_broken_bond_s"] = c.time;
    if (cj["time_first_separated_column_s"].is_null() && c.md.separated_columns > 0)
      cj["time_first_separated_column_s"] = c.time;
    if (cj["time_first_slipped_column_s"].is_null() && c.md.slipped_columns > 0)
      cj["time_first_slipped_column_s"] = c.time;
  }
  if (!log.empty()) cj["last"] = crack_json(log.back());
  cj["frames"] = frames;
  return cj;
}

std::vector<double> crack_row(const CrackRecord& c) {
  return {c.time,
          c.tip.tip[0],
          c.tip.tip[1],
          c.tip.e1[0],
          c.tip.e1[1],
          c.tip.J,
          c.tip.GI,
          c.tip.GII,
          c.tip.opening,
          c.tip.sliding,
          c.tip.length,
          static_cast<double>(c.tip.particles),
          static_cast<double>(c.tip.crack),
          static_cast<double>(c.tip.end),
          static_cast<double>(c.increments),
          static_cast<double>(c.md.bonds),
          static_cast<double>(c.md.broken),
          static_cast<double>(c.md.columns),
          static_cast<double>(c.md.separated_columns),
          c.md.length_A,
          c.md.entry_opening_A,
          c.md.entry_sliding_A,
          c.md.max_opening_A,
          c.md.max_abs_sliding_A};
}

CrackRecord crack_record(const double* d) {
  CrackRecord c;
  c.time = d[0];
  c.tip.tip = Eigen::Vector2d(d[1], d[2]);
  c.tip.e1 = Eigen::Vector2d(d[3], d[4]);
  c.tip.J = d[5];
  c.tip.GI = d[6];
  c.tip.GII = d[7];
  c.tip.opening = d[8];
  c.tip.sliding = d[9];
  c.tip.length = d[10];
  c.tip.particles = static_cast<int>(d[11]);
  c.tip.crack = static_cast<std::size_t>(d[12]);
  c.tip.end = static_cast<int>(d[13]);
  c.increments = static_cast<int>(d[14]);
  c.md.bonds = static_cast<int>(d[15]);
  c.md.broken = static_cast<int>(d[16]);
  c.md.columns = static_cast<int>(d[17]);
  c.md.separated_columns = static_cast<int>(d[18]);
  c.md.length_A = d[19];
  c.md.entry_opening_A = d[20];
  c.md.entry_sliding_A = d[21];
  c.md.max_opening_A = d[22];
  c.md.max_abs_sliding_A = d[23];
  return c;
}

/// Records the crack at every J evaluation (CoupledRun::last_tip) and at every frame: crack.csv,
/// the per-frame records and the "crack" block of summary.json.
class CrackRecorder final : public Observer {
public:
  CrackRecorder(const CoupledRun& run, std::unique_ptr<BondMonitor> bonds, bool progress)
      : bonds_(std::move(bonds)), progress_(progress) {
    max_increments_ = run.solver().cracks[0].growth.max_increments;
    csv_ << crack_csv_header();
  }

  void on_step(const CoupledRun& run, long done) override {
    if (done % run.input().crack_every != 0) return;
    CrackRecord rec;
    rec.time = run.solver().time;
    rec.tip = run.last_tip();
    rec.increments = run.solver().cracks[0].increments;
    rec.md = bonds_->measure(run.atoms_x());
    csv_ << crack_csv_row(rec);
    log_.push_back(rec);
  }

  void on_frame(const CoupledRun& run, long index) override {
    CrackRecord rec = log_.empty() ? CrackRecord{} : log_.back();
    rec.time = run.solver().time;
    rec.md = bonds_->measure(run.atoms_x());
    frame_log_.push_back(crack_json(rec));
    if (progress_)
      std::cerr << fmt::format(
          "frame {}  t = {:.2f} ps  continuum tip x = {:.2f} A ({}/{} increments)  MD: "
          "{}/{} bonds broken, separated {:.1f} A, {} columns slipped\n",
          std::to_string(index).c_str(), rec.time / 1e-12, rec.tip.tip[0] / units::m_per_A,
          rec.increments, max_increments_, rec.md.broken, rec.md.bonds, rec.md.length_A,
          rec.md.slipped_columns);
  }

  void save(CoupledCheckpoint& ck) const override {
    ck.texts["crack_csv"] = csv_.str();
    ck.texts["frame_log"] = frame_log_.dump();
    CheckpointTable cl(static_cast<Eigen::Index>(log_.size()), kCrackLogColumns);
    for (std::size_t i = 0; i < log_.size(); ++i) {
      const auto row = crack_row(log_[i]);
      for (int j = 0; j < kCrackLogColumns; ++j)
        cl(static_cast<Eigen::Index>(i), j) = row[static_cast<std::size_t>(j)];
    }
    ck.tables["crack_log"] = cl;
  }

  void restore(const CoupledCheckpoint& ck, const std::string& ckpt_file) override {
    const CheckpointTable cl = checkpoint_table(ck, ckpt_file, "crack_log", -1, kCrackLogColumns);
    log_.clear();
    for (Eigen::Index i = 0; i < cl.rows(); ++i)
      log_.push_back(crack_record(cl.row(i).data()));
    if (ck.texts.count("crack_csv")) {
      csv_.str("");
      csv_ << checkpoint_text(ck, "crack_csv");
    }
    frame_log_ =
        ck.texts.count("frame_log") ? json::parse(checkpoint_text(ck, "frame_log")) : json::array();
  }

  void write(const CoupledRun& run, CoupleSummary& r) const override {
    r.crack_csv = run.out_dir() + "/crack.csv";
    pnc::write_text_atomically(r.crack_csv, csv_.str());
  }

  void summarize(const CoupledRun& run, json& sj) const override {
    const CoupleInput& p = run.input();
    const double wsep = run.separation_work();
    sj["crack"] = crack_summary(log_, frame_log_, p, run.cell_size(), max_increments_);
    sj["crack"]["Gc_J_per_m2"] = run.Gc();
    sj["crack"]["interface_fraction"] = p.crack_f;
    sj["crack"]["separation_work_bulk_J_per_m2"] = wsep;
    sj["crack"]["separation_work_interface_J_per_m2"] = p.crack_f * wsep;
    sj["crack_csv"] = run.out_dir() + "/crack.csv";
  }

private:
  std::unique_ptr<BondMonitor> bonds_;
  bool progress_ = false;
  int max_increments_ = 0;
  std::vector<CrackRecord> log_;
  std::ostringstream csv_;
  json frame_log_ = json::array();
};

} // namespace

std::unique_ptr<Observer> make_crack_record(const CoupledRun& run,
                                            std::unique_ptr<BondMonitor> bonds, bool progress) {
  return std::make_unique<CrackRecorder>(run, std::move(bonds), progress);
}

} // namespace pnc::gimp::escm
