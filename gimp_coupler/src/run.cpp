// The driver of `pnc gimp run` (run.hpp).
#include "pnc/gimp_coupler/run.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/plot.hpp"
#include "pnc/core/progress.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/version.hpp"
#include "pnc/gimp_coupler/fracture.hpp"
#include "pnc/gimp_coupler/input.hpp"
#include "pnc/gimp_coupler/output.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace pnc::gimp {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// Draws energy.png from history.csv through the one plot runner (pnc/core/plot.hpp, D337);
/// returns a warning ("" on success): a missing interpreter, matplotlib or script never fails
/// the run. `extra`: further arguments of the script (plot_G.py: --gc, --stop;
/// plot_energy.py: --per-thickness).
std::string plot_energy(const std::string& csv, const std::string& png, const std::string& title,
                        const char* script_name = "plot_energy.py",
                        const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args = {csv, png, title};
  args.insert(args.end(), extra.begin(), extra.end());
  try {
    return run_plot(script_name, args).warning;
  } catch (const InputError& e) { // the script is not installed: the run is written anyway
    return std::string(script_name) + ": " + e.what();
  }
}

/// One `pnc gimp run` of dimension D: the solver from the input, its history, frames and
/// checkpoints (output.hpp), the step loop, summary.json and the plots.
template <int D> struct GimpRun {
  explicit GimpRun(const RunOptions& opt);
  RunSummary run();

  /// Resumes from the checkpoint or starts at t = 0 (the history columns).
  void start();
  /// 3-D (D42): the straight fronts of `initial` (the flags of t = 0) or of now.
  void find_fronts(const std::vector<int>& initial);
  /// One history row at the current step (step dt).
  void record(double row_dt);
  void record_tips(std::vector<double>& row) const;   ///< 2-D: J, G_I, G_II, length, tip
  void record_fronts(std::vector<double>& row) const; ///< 3-D: J, G_I, G_II, depth, length
  /// One VTU frame and the .pvd.
  void frame();
  /// The steps until the end, max_steps, stop_after_steps or a stop request.
  void loop();
  /// D40 (2-D) / D43 (3-D): J and growth every fracture_every steps.
  void grow();
  bool stop_requested() const { return o.stop != nullptr && o.stop->requested(); }
  /// The numbers of a finished run and the plots.
  void fill_summary();
  /// Why the run ended and why each crack stopped growing (RunSummary::end_reason, cracks).
  void fill_outcomes();
  void write_summary_json() const;
  nlohmann::json cracks_json() const; ///< the "cracks" block of summary.json

  const RunOptions& o;
  const Clock::time_point wall0 = Clock::now();
  Solver<D> s;
  RunConfig rc;
  std::string ckpt, pvd, hist_csv;
  CheckpointExtra x;
  // Crack tips at the start ((crack, end), "<crack>_start|end"): fixed history columns.
  std::vector<std::pair<std::pair<std::size_t, int>, std::string>> tip_ids;
  // 3-D (D42): the straight fronts at the start ((crack, edge), "<crack>_front<edge>"): fixed
  // history columns. With growth (D43) a front may stop being one; the flags of t = 0 are
  // kept in the checkpoint (as the 2-D tips of t = 0, in CheckpointExtra::initial_tips).
  std::vector<std::pair<std::pair<std::size_t, std::size_t>, std::string>> front_ids;
  bool any_growth = false;
  RunSummary sum;
  long step0 = 0;
  double t_begin = 0.0, dt = 0.0, eps_t = 0.0;
  Clock::time_point run0;
  bool last_framed = true;
};

template <int D> GimpRun<D>::GimpRun(const RunOptions& opt) : o(opt) {
  rc = load_input<D>(o.input, s);
  if (o.threads > 0) s.threads = rc.threads = o.threads;
  make_output_directory(o.out_dir);
  make_output_directory((fs::path(o.out_dir) / "frames").string());
  ckpt = (fs::path(o.out_dir) / "checkpoint.h5").string();
  pvd = (fs::path(o.out_dir) / "particles.pvd").string();
  hist_csv = (fs::path(o.out_dir) / "history.csv").string();
  x.input = rc.expanded_input; // --resume compares it (D339)
  x.input_source = o.input;
  x.input_hash = file_fnv1a64(o.input);
  for (const auto& c : s.cracks)
    any_growth = any_growth || c.growth.Gc > 0.0;
  sum.dimension = D;
}

template <int D> void GimpRun<D>::find_fronts(const std::vector<int>& initial) {
  std::size_t n = 0;
  for (const auto& c : s.cracks)
    n += c.front.size();
  const bool use_initial = initial.size() == n;
  std::size_t i = 0;
  for (std::size_t c = 0; c < s.cracks.size(); ++c)
    for (std::size_t e = 0; e < s.cracks[c].front.size(); ++e, ++i)
      if (use_initial ? initial[i] == 1 : s.cracks[c].front[e] == 1)
        front_ids.push_back({{c, e}, s.cracks[c].name + "_front" + std::to_string(e)});
}

template <int D> void GimpRun<D>::start() {
  if (o.resume && fs::exists(ckpt)) {
    s.initialize(true);
    read_checkpoint<D>(ckpt, s, x);
    s.initialize(false);
    // initialize() recomputes KE/SE from the particles; keep the works from the checkpoint.
    sum.resumed = true;
    if constexpr (D == 3) find_fronts(x.initial_tips);
    if constexpr (D == 2)
      for (std::size_t c = 0; c < s.cracks.size(); ++c)
        for (int e = 0; e < 2; ++e)
          if (x.initial_tips.size() > 2 * c + static_cast<std::size_t>(e) &&
              x.initial_tips[2 * c + static_cast<std::size_t>(e)])
            tip_ids.push_back({{c, e}, s.cracks[c].name + (e == 0 ? "_start" : "_end")});
  } else {
    if (o.resume && o.progress)
      std::cerr << "pnc gimp: --resume: no checkpoint in " << o.out_dir << ", starting at t = 0\n";
    s.initialize(true);
    x.initial_tips.clear();
    if constexpr (D == 3) { // the front flags of t = 0, crack by crack, edge by edge
      for (const auto& c : s.cracks)
        for (int f : c.front)
          x.initial_tips.push_back(f == 1 ? 1 : 0);
      find_fronts(x.initial_tips);
    }
    if constexpr (D == 2)
      for (std::size_t c = 0; c < s.cracks.size(); ++c)
        for (int e = 0; e < 2; ++e) {
          const bool is_tip = s.cracks[c].tip[static_cast<std::size_t>(e)] == 1;
          x.initial_tips.push_back(is_tip ? 1 : 0);
          if (is_tip) tip_ids.push_back({{c, e}, s.cracks[c].name + (e == 0 ? "_start" : "_end")});
        }
    // D335: the unit ends every column name (docs/formats.md); 2-D energies and reactions
    // are per metre of thickness (J/m, N/m), 3-D ones in J and N
    const std::string E = D == 2 ? "_J_per_m" : "_J", F = D == 2 ? "_N_per_m" : "_N";
    x.history.columns = {"step",
                         "time_s",
                         "dt_s",
                         "kinetic" + E,
                         "strain" + E,
                         "external_work" + E,
                         "boundary_work" + E,
                         "balance" + E};
    static const char* ax[] = {"x", "y", "z"};
    for (const auto& bc : s.bcs)
      for (int a = 0; a < D; ++a)
        x.history.columns.push_back("reaction_" + bc.name + "_" + ax[a] + F);
    x.history.columns.push_back("damping_work" + E);
    if constexpr (D == 2)
      for (const auto& t : tip_ids)
        for (const char* q : {"J_", "GI_", "GII_", "length_", "tipx_", "tipy_"})
          x.history.columns.push_back(q + t.second +
                                      (q[0] == 'J' || q[0] == 'G' ? "_J_per_m2" : "_m"));
    if constexpr (D == 3)
      for (const auto& t : front_ids)
        for (const char* q : {"J_", "GI_", "GII_", "length_", "frontlength_"})
          x.history.columns.push_back(q + t.second +
                                      (q[0] == 'J' || q[0] == 'G' ? "_J_per_m2" : "_m"));
  }
}

template <int D> void GimpRun<D>::record(double row_dt) {
  std::vector<double> row = {static_cast<double>(s.steps),
                             s.time,
                             row_dt,
                             s.energy.kinetic,
                             s.energy.strain,
                             s.energy.external_work,
                             s.energy.boundary_work,
                             s.energy.balance()};
  for (const auto& bc : s.bcs)
    for (int a = 0; a < D; ++a)
      row.push_back(bc.reaction[a]);
  row.push_back(s.energy.damping_work);
  if constexpr (D == 2) record_tips(row);
  if constexpr (D == 3) record_fronts(row);
  x.history.rows.push_back(row);
}

template <int D> void GimpRun<D>::record_tips(std::vector<double>& row) const {
  const auto tips = tip_ids.empty() ? std::vector<TipResult>{} : crack_tips(s);
  for (const auto& t : tip_ids) {
    const TipResult* r = nullptr;
    for (const auto& q : tips)
      if (q.crack == t.first.first && q.end == t.first.second) r = &q;
    const double nan = std::nan("");
    if (r) {
      row.insert(row.end(), {r->J, r->GI, r->GII, r->length, r->tip[0], r->tip[1]});
    } else { // the tip has left the material (crack through)
      const Crack& c = s.cracks[t.first.first];
      const Eigen::Vector2d q = t.first.second == 0 ? c.points.front() : c.points.back();
      double L = 0.0;
      for (std::size_t k = 0; k + 1 < c.points.size(); ++k)
        L += (c.points[k + 1] - c.points[k]).norm();
      row.insert(row.end(), {nan, nan, nan, L, q[0], q[1]});
    }
  }
}

template <int D> void GimpRun<D>::record_fronts(std::vector<double>& row) const {
  const auto fronts = front_ids.empty() ? std::vector<FrontResult>{} : crack_fronts(s);
  for (const auto& t : front_ids) {
    const FrontResult* r = nullptr;
    for (const auto& q : fronts)
      if (q.crack == t.first.first && q.edge == t.first.second) r = &q;
    if (r) {
      row.insert(row.end(), {r->J, r->GI, r->GII, r->depth, r->length});
    } else { // the front has left the material (crack through, D43): NaN, the length
      const Crack& c = s.cracks[t.first.first];
      const std::size_t m = c.corners.size(), e = t.first.second;
      const Eigen::Vector3d mid = 0.5 * (c.corners[e] + c.corners[(e + 1) % m]);
      const Eigen::Vector3d e1 = edge_outward(c, e);
      double depth = 0.0;
      for (const auto& q : c.corners)
        depth = std::max(depth, (mid - q).dot(e1));
      const double nan = std::nan("");
      row.insert(row.end(), {nan, nan, nan, depth, nan});
    }
  }
}

template <int D> void GimpRun<D>::frame() {
  const std::string name = fmt::format("frames/particles_{:06d}.vtu", x.frame_files.size());
  write_vtu<D>((fs::path(o.out_dir) / name).string(), s, rc.vtu_binary, rc.material_names);
  x.frame_files.push_back(name);
  x.frame_times.push_back(s.time);
  write_pvd(pvd, x.frame_files, x.frame_times);
}

template <int D> void GimpRun<D>::loop() {
  step0 = s.steps;
  t_begin = s.time;
  run0 = Clock::now();
  dt = 0.0;
  eps_t = 1e-12 * rc.t_end;
  ProgressOptions po; // a line every 2 s; the time simulated before a resume is not in the rate
  po.every_s = 2.0;
  po.enabled = o.progress;
  Progress bar("pnc gimp", rc.t_end, "s simulated", po); // D344, D345
  bar.skip(std::min(t_begin, rc.t_end));
  last_framed = true;
  while (s.time < rc.t_end - eps_t && (rc.max_steps == 0 || s.steps < rc.max_steps) &&
         (o.stop_after_steps == 0 || s.steps < o.stop_after_steps) && !stop_requested()) {
    dt = rc.dt > 0 ? rc.dt : s.stable_dt();
    dt = std::min(dt, rc.t_end - s.time);
    if (x.next_output_time > s.time + eps_t) dt = std::min(dt, x.next_output_time - s.time);
    s.step(dt);
    last_framed = false;
    grow();
    if (s.steps % rc.history_every == 0) record(dt);
    if (s.time >= x.next_output_time - eps_t) {
      if (s.steps % rc.history_every != 0) record(dt);
      frame();
      last_framed = true;
      x.next_output_time += rc.output_interval > 0 ? rc.output_interval : rc.t_end;
      if (x.frame_files.size() % static_cast<std::size_t>(rc.checkpoint_every) == 0) {
        x.history.write_csv(hist_csv);
        write_checkpoint<D>(ckpt, s, x);
      }
    }
    bar.set(s.time >= rc.t_end - eps_t ? rc.t_end : std::min(s.time, rc.t_end),
            fmt::format("step {} t = {:.6g} s dt = {:.3g} s", s.steps, s.time, dt));
  }
}

template <int D> void GimpRun<D>::grow() {
  if constexpr (D == 2) { // D40: J and growth every fracture_every steps
    if (!tip_ids.empty() && s.steps % rc.fracture_every == 0) {
      const auto tips = crack_tips(s);
      const int g = grow_cracks(s, tips);
      sum.crack_increments += g;
      if (g > 0 && o.progress)
        for (const auto& c : s.cracks)
          std::cerr << fmt::format("pnc gimp: step {} t = {:.6g} s: crack '{}' has {} "
                                   "increments, tip at ({:.6g}, {:.6g}) m\n",
                                   s.steps, s.time, c.name, c.increments, c.points.back()[0],
                                   c.points.back()[1]);
    }
  }
  if constexpr (D == 3) { // D43: growth of the straight fronts every fracture_every steps
    if (any_growth && !front_ids.empty() && s.steps % rc.fracture_every == 0) {
      const int g = grow_cracks(s, crack_fronts(s));
      sum.crack_increments += g;
      if (g > 0 && o.progress)
        for (const auto& c : s.cracks)
          std::cerr << fmt::format("pnc gimp: step {} t = {:.6g} s: crack '{}' has {} "
                                   "increments\n",
                                   s.steps, s.time, c.name, c.increments);
    }
  }
}

template <int D> RunSummary GimpRun<D>::run() {
  start();
  if (!sum.resumed) {
    record(0.0);
    frame();
    x.next_output_time = rc.output_interval > 0 ? rc.output_interval : rc.t_end;
    write_checkpoint<D>(ckpt, s, x);
  }
  loop();
  // Stopped by --max-steps or a stop request before the end: leave frames and history as an
  // uninterrupted run would have them (the checkpoint carries the rest); --resume continues.
  const bool unfinished =
      s.time < rc.t_end - eps_t && (rc.max_steps == 0 || s.steps < rc.max_steps);
  const bool stopped = unfinished && stop_requested();
  const bool interrupted =
      unfinished && (stopped || (o.stop_after_steps > 0 && s.steps >= o.stop_after_steps));
  if (!last_framed && !interrupted) {
    if (x.history.rows.empty() || x.history.rows.back()[0] != static_cast<double>(s.steps))
      record(dt);
    frame();
  }
  x.history.write_csv(hist_csv);
  write_checkpoint<D>(ckpt, s, x);
  sum.history_csv = hist_csv;
  sum.checkpoint = ckpt;
  if (stopped) { // the checkpoint is the whole state: no plots, no summary.json
    sum.stopped = true;
    sum.stop_signal = o.stop->signal();
    sum.steps = s.steps;
    sum.steps_this_run = s.steps - step0;
    sum.time = s.time;
    return sum;
  }
  fill_summary();
  write_summary_json();
  return sum;
}

template <int D> void GimpRun<D>::fill_summary() {
  const double run_s = std::chrono::duration<double>(Clock::now() - run0).count();
  sum.particles = s.particles.size();
  sum.steps = s.steps;
  sum.steps_this_run = s.steps - step0;
  sum.time = s.time;
  sum.dt_last = dt;
  sum.energy = s.energy;
  for (const auto& r : x.history.rows)
    sum.max_abs_balance = std::max(sum.max_abs_balance, std::abs(r[7]));
  sum.threads = s.threads;
  sum.frames = static_cast<int>(x.frame_files.size());
  sum.pvd = pvd;
  sum.particle_steps_per_second = run_s > 0 ? static_cast<double>(sum.steps_this_run) *
                                                  static_cast<double>(sum.particles) / run_s
                                            : 0.0;
  for (const auto& bc : s.bcs) {
    sum.reaction_names.push_back(bc.name);
    sum.reactions.emplace_back(bc.reaction.data(), bc.reaction.data() + D);
  }
  fill_outcomes();
  if (o.plot) {
    // the plotting phase is announced: no silent seconds after the last step's ETA 0 s (D344)
    Phase phase("pnc gimp", "plotting energy.png (and G.png for cracks)", o.progress);
    const std::string png = (fs::path(o.out_dir) / "energy.png").string();
    sum.plot_warning = plot_energy(
        hist_csv, png, fs::path(o.input).filename().string(), "plot_energy.py",
        D == 2 ? std::vector<std::string>{"--per-thickness"} : std::vector<std::string>{});
    if (sum.plot_warning.empty()) sum.plot_png = png;
    if (!tip_ids.empty() || !front_ids.empty()) {
      const std::string gpng = (fs::path(o.out_dir) / "G.png").string();
      std::vector<std::string> marks; // the critical G line and the stop marker (D272)
      for (const auto& c : sum.cracks)
        if (c.Gc > 0) {
          marks.insert(marks.end(), {"--gc", c.name, fmt::format("{:.17g}", c.Gc)});
          marks.insert(marks.end(), {"--stop", c.name, c.stop_reason});
        }
      const std::string w =
          plot_energy(hist_csv, gpng, fs::path(o.input).filename().string(), "plot_G.py", marks);
      if (w.empty())
        sum.plot_G_png = gpng;
      else
        sum.plot_warning += (sum.plot_warning.empty() ? "" : "; ") + w;
    }
    phase.done("plotting done");
  }
  sum.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
}

template <int D> void GimpRun<D>::fill_outcomes() {
  if (s.time >= rc.t_end - eps_t)
    sum.end_reason = "end time reached";
  else if (rc.max_steps > 0 && s.steps >= rc.max_steps)
    sum.end_reason = fmt::format("input max_steps ({}) reached", rc.max_steps);
  else
    sum.end_reason = fmt::format("--max-steps ({}) reached", o.stop_after_steps);
  // the largest J (and mixed-mode ratio) of each crack's tips or fronts now
  std::vector<double> J(s.cracks.size(), std::nan("")), mix(s.cracks.size(), std::nan(""));
  auto take = [&](std::size_t c, double j, double gi, double gii) {
    const CrackGrowth& g = s.cracks[c].growth;
    if (!std::isfinite(j)) return;
    J[c] = std::isfinite(J[c]) ? std::max(J[c], j) : j;
    if (g.Gc > 0 && g.GIIc > 0) {
      const double m = gi / g.Gc + gii / g.GIIc;
      mix[c] = std::isfinite(mix[c]) ? std::max(mix[c], m) : m;
    }
  };
  if constexpr (D == 2) {
    for (const auto& t : crack_tips(s))
      take(t.crack, t.J, t.GI, t.GII);
  } else {
    for (const auto& f : crack_fronts(s))
      take(f.crack, f.J, f.GI, f.GII);
  }
  for (std::size_t c = 0; c < s.cracks.size(); ++c) {
    const Crack& k = s.cracks[c];
    CrackOutcome out{k.name, k.growth.Gc, k.growth.GIIc, k.growth.max_increments, k.increments, ""};
    if (k.growth.Gc <= 0)
      out.stop_reason = "no growth law (Gc = 0)";
    else if (k.increments >= k.growth.max_increments)
      out.stop_reason = fmt::format("max_increments ({}) reached", k.growth.max_increments);
    else if (!std::isfinite(J[c]))
      out.stop_reason = "no tip left inside the material";
    else if (k.growth.GIIc > 0 ? mix[c] >= 1 : J[c] >= k.growth.Gc)
      out.stop_reason = "still growing: the criterion is met at the end of the run";
    else if (k.growth.GIIc > 0)
      out.stop_reason = fmt::format("G_I/Gc + G_II/GIIc = {:.3g} < 1 at the end", mix[c]);
    else
      out.stop_reason = fmt::format("J = {:.4g} < Gc = {:.4g} J/m² at the end", J[c], k.growth.Gc);
    sum.cracks.push_back(out);
  }
}

template <int D> void GimpRun<D>::write_summary_json() const {
  nlohmann::json j;
  j["software"] = version_string();
  j["input"] = o.input;
  j["dimension"] = D;
  j["particles"] = sum.particles;
  j["steps"] = sum.steps;
  j["time_s"] = sum.time;
  j["energy_J"] = {{"initial", s.energy.initial},
                   {"kinetic", s.energy.kinetic},
                   {"strain", s.energy.strain},
                   {"external_work", s.energy.external_work},
                   {"boundary_work", s.energy.boundary_work},
                   {"balance", s.energy.balance()},
                   {"max_abs_balance", sum.max_abs_balance}};
  j["frames"] = sum.frames;
  j["energy_J"]["damping_work"] = s.energy.damping_work;
  j["cracks"] = cracks_json();
  write_text_atomically((fs::path(o.out_dir) / "summary.json").string(), j.dump(2) + "\n");
}

template <int D> nlohmann::json GimpRun<D>::cracks_json() const {
  nlohmann::json cj = nlohmann::json::array();
  if constexpr (D == 2) {
    const auto tips = crack_tips(s);
    for (std::size_t c = 0; c < s.cracks.size(); ++c) {
      nlohmann::json one;
      one["name"] = s.cracks[c].name;
      one["increments"] = s.cracks[c].increments;
      nlohmann::json pts = nlohmann::json::array();
      for (const auto& q : s.cracks[c].points)
        pts.push_back({q[0], q[1]});
      one["points_m"] = pts;
      nlohmann::json tj = nlohmann::json::array();
      for (const auto& t : tips)
        if (t.crack == c)
          tj.push_back({{"end", t.end == 0 ? "start" : "end"},
                        {"J_J_per_m2", t.J},
                        {"GI_J_per_m2", t.GI},
                        {"GII_J_per_m2", t.GII},
                        {"tip_m", {t.tip[0], t.tip[1]}}});
      one["tips"] = tj;
      cj.push_back(one);
    }
  }
  if constexpr (D == 3) { // D42
    const auto fronts = crack_fronts(s);
    for (std::size_t c = 0; c < s.cracks.size(); ++c) {
      nlohmann::json one;
      one["name"] = s.cracks[c].name;
      one["increments"] = s.cracks[c].increments;
      nlohmann::json pts = nlohmann::json::array();
      for (const auto& q : s.cracks[c].corners)
        pts.push_back({q[0], q[1], q[2]});
      one["corners_m"] = pts;
      nlohmann::json fj = nlohmann::json::array();
      for (const auto& r : fronts)
        if (r.crack == c)
          fj.push_back({{"edge", r.edge},
                        {"J_J_per_m2", r.J},
                        {"GI_J_per_m2", r.GI},
                        {"GII_J_per_m2", r.GII},
                        {"front_length_m", r.length},
                        {"mid_m", {r.mid[0], r.mid[1], r.mid[2]}}});
      one["fronts"] = fj;
      cj.push_back(one);
    }
  }
  return cj;
}

} // namespace

RunSummary run(const RunOptions& o) {
  if (o.out_dir.empty()) fail("<command line>", "--out", "", "an output folder is required");
  refuse_existing_run(o.out_dir, o.resume, {"checkpoint.h5", "history.csv", "summary.json"});
  const int d = input_dimension(o.input);
  return d == 2 ? GimpRun<2>(o).run() : GimpRun<3>(o).run();
}

} // namespace pnc::gimp
