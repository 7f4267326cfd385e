// pnc characterize end to end on a tiny recipe (seconds): outputs, JSON, resume without
// recomputation, and a bad recipe's error line.
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/version.hpp"
#include "pnc/damage/data.hpp"

#include "characterize_support.hpp"
#include "common/page_check.hpp"
#include "common/run_command.hpp"
#include "common/temp_dir.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>

namespace fs = std::filesystem;

namespace {
using pnc::test::tiny_recipe;
using Proc = pnc::test::CommandResult;
using pnc::test::run_pnc;
Proc run(const std::string& args) {
  return run_pnc(args);
}
using pnc::test::slurp;
const char* tiny = tiny_recipe;
/// report.html of a run drawn with its figures: self-contained, the verdict and every
/// constant of the JSON summary `j`, both figures (the fit, the MD stresses) embedded; the
/// progress line counts them.
void expect_report_page(const std::string& out, const nlohmann::json& j, const std::string& err) {
  const std::string html = slurp(out + "/report.html");
  ASSERT_FALSE(html.empty());
  EXPECT_EQ(pnc::test::self_contained_problems(html), std::vector<std::string>{});
  EXPECT_NE(html.find("Verdict: " + j["verdict"]["level"].get<std::string>()), std::string::npos);
  for (const auto& [name, c] : j["constants"].items())
    EXPECT_NE(html.find("<td>" + name + "</td>"), std::string::npos) << name;
  EXPECT_NE(html.find("What to do next"), std::string::npos);
  EXPECT_NE(html.find("<h2>Statistics</h2>"), std::string::npos); // report.md's details
  std::size_t images = 0;
  for (auto at = html.find("src=\"data:image/png;base64,iVBORw0KGgo"); at != std::string::npos;
       at = html.find("src=\"data:image/png;base64,iVBORw0KGgo", at + 1))
    ++images;
  EXPECT_EQ(images, 2u) << "plots/fit.png and plots/stress.png";
  EXPECT_TRUE(fs::exists(fs::path(out) / "plots/stress.png"));
  EXPECT_NE(err.find("plotting 2 figures ..."), std::string::npos) << err;
  const std::string md = slurp(out + "/report.md");
  EXPECT_NE(md.find("](plots/stress.png)"), std::string::npos);
  EXPECT_NE(md.find("## Verdict: "), std::string::npos);
}
/// The MD figure's content, from the job list the plot script drew it from
/// (plots/figures.json, app/figures.hpp): per case the stress as measured next to the stress
/// minus the reference hold, all six components (a shear case's normal stresses too), an
/// error bar on every averaged point; the subtracted panel is the data that was fitted.
void expect_md_figure(const std::string& out, const pnc::damage::StressStrainData& data) {
  const auto jobs = nlohmann::json::parse(slurp(out + "/plots/figures.json"), nullptr, false);
  ASSERT_FALSE(jobs.is_discarded());
  const nlohmann::json* fig = nullptr;
  for (const auto& f : jobs["figures"])
    if (f["png"].get<std::string>().find("stress.png") != std::string::npos) fig = &f;
  ASSERT_NE(fig, nullptr) << jobs.dump();
  const auto& panels = (*fig)["panels"];
  ASSERT_EQ(panels.size(), 2 * data.cases.size()) << "two panels per case";
  const char* comp[6] = {"11", "22", "33", "23", "13", "12"};
  for (std::size_t c = 0; c < data.cases.size(); ++c) {
    const auto& cc = data.cases[c];
    const auto& raw = panels[2 * c];
    const auto& rel = panels[2 * c + 1];
    const std::string id = std::to_string(cc.id);
    EXPECT_EQ(raw["title"].get<std::string>().rfind("case " + id + " (", 0), 0u) << raw["title"];
    EXPECT_NE(raw["title"].get<std::string>().find("as measured"), std::string::npos);
    EXPECT_EQ(rel["title"], "case " + id + ": minus the reference (fitted)");
    ASSERT_EQ(raw["series"].size(), 6u);
    ASSERT_EQ(rel["series"].size(), 6u);
    const auto k = static_cast<std::size_t>(cc.strain.rows());
    for (int j = 0; j < 6; ++j) {
      const auto& a = raw["series"][static_cast<std::size_t>(j)];
      const auto& b = rel["series"][static_cast<std::size_t>(j)];
      EXPECT_EQ(a["label"], std::string("σ") + comp[j]);
      // raw: the reference hold at zero strain, then the k points; subtracted: the k points
      ASSERT_EQ(a["y"].size(), k + 1) << "case " << id << " σ" << comp[j];
      ASSERT_EQ(b["y"].size(), k) << "case " << id << " σ" << comp[j];
      EXPECT_EQ(a["x"][0].get<double>(), 0.0);
      for (const auto* s : {&a, &b}) {
        ASSERT_TRUE(s->contains("yerr")) << "case " << id << " σ" << comp[j];
        ASSERT_EQ((*s)["yerr"].size(), (*s)["y"].size());
        for (const auto& e : (*s)["yerr"])
          EXPECT_GT(e.get<double>(), 0.0) << "case " << id << " σ" << comp[j];
      }
      for (std::size_t i = 0; i < k; ++i) {
        const auto r = static_cast<Eigen::Index>(i);
        // MPa as plotted; JSON keeps 17 digits: the fitted data divided by 1e6, exactly
        EXPECT_EQ(b["y"][i].get<double>(), cc.stress(r, j) / 1e6);
        EXPECT_EQ(b["yerr"][i].get<double>(), cc.stress_stderr(r, j) / 1e6);
        // one replica: raw = subtracted + reference, to the rounding of the two sums
        // (|values| <~ 1e3 MPa: 1e-9 MPa is far above it, far below any stress)
        EXPECT_NEAR(a["y"][i + 1].get<double>() - a["y"][0].get<double>(), b["y"][i].get<double>(),
                    1e-9);
        EXPECT_EQ(a["x"][i + 1].get<double>(), b["x"][i].get<double>());
      }
    }
  }
}

/// What the plot script drew from that job list, read back from the matplotlib artists
/// (`plot_figures.py --describe`, D343): every panel of the MD figure is an axes with its title,
/// six component lines with their points and one error-bar set per line, a bar on every point.
void expect_md_figure_drawn(const std::string& out) {
  const std::string desc = out + "/plots/describe.json";
  const Proc p = pnc::test::run_command(
      std::string("'" PNC_PYTHON "' '" PNC_SOURCE_DIR "/scripts/plot_figures.py' --describe '") +
      desc + "' '" + out + "/plots/figures.json' 2>&1");
  ASSERT_EQ(p.code, 0) << p.out;
  const auto jobs = nlohmann::json::parse(slurp(out + "/plots/figures.json"));
  const auto drawn = nlohmann::json::parse(slurp(desc), nullptr, false);
  ASSERT_FALSE(drawn.is_discarded());
  ASSERT_EQ(drawn["figures"].size(), jobs["figures"].size());
  for (std::size_t f = 0; f < jobs["figures"].size(); ++f) {
    const auto& job = jobs["figures"][f];
    if (job["png"].get<std::string>().find("stress.png") == std::string::npos) continue;
    const auto& axes = drawn["figures"][f]["axes"];
    ASSERT_EQ(axes.size(), job["panels"].size()) << "one axes per panel (no residuals here)";
    for (std::size_t a = 0; a < axes.size(); ++a) {
      const auto& panel = job["panels"][a];
      EXPECT_EQ(axes[a]["title"], panel["title"]);
      ASSERT_EQ(axes[a]["lines"].size(), 6u) << panel["title"];
      ASSERT_EQ(axes[a]["error_bars"].size(), 6u) << panel["title"];
      for (std::size_t j = 0; j < 6; ++j) {
        const auto n = panel["series"][j]["y"].size();
        EXPECT_EQ(axes[a]["lines"][j]["label"], panel["series"][j]["label"]);
        EXPECT_EQ(axes[a]["lines"][j]["points"].get<std::size_t>(), n) << panel["title"];
        EXPECT_EQ(axes[a]["error_bars"][j].get<std::size_t>(), n) << panel["title"];
      }
    }
  }
}
} // namespace

TEST(RveCharacterizeCli, TinyRecipeEndToEndAndResume) {
  const auto d = pnc::test::fresh_dir("test_rve_char");
  std::ofstream(d / "tiny.json") << tiny;
  const std::string out = (d / "out").string();
  const Proc r = run("characterize " + (d / "tiny.json").string() + " --out " + out +
                     " --json --no-plots 2>" + (d / "err.txt").string());
  // exit 0, 3 (fit did not converge) or 4 (card "not usable": 3 noisy points a case): every
  // one leaves the outputs, and the exit code is 4 exactly when the verdict says so
  ASSERT_TRUE(r.code == 0 || r.code == 3 || r.code == 4) << r.code << " " << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["command"], "characterize");
  EXPECT_EQ(r.code == 4, j["verdict"]["level"] == "not usable") << j["verdict"].dump();
  const std::string report = slurp((fs::path(out) / "report.md").string());
  EXPECT_NE(report.find("## Verdict: "), std::string::npos);
  // the phase check: in the report (words and numbers), the JSON and phase/phase.h5; a
  // relaxing RVE has its shear and damage constants held as not identified, and says why
  EXPECT_TRUE(fs::exists(fs::path(out) / "phase/phase.h5"));
  EXPECT_NE(report.find("## Phase check: "), std::string::npos) << report;
  EXPECT_NE(report.find("G_hold"), std::string::npos);
  const auto& pc = j["phase_check"];
  ASSERT_TRUE(pc.is_object()) << j.dump();
  EXPECT_TRUE(pc["G_t0_Pa"].is_number());
  EXPECT_GT(pc["G_t0_Pa"].get<double>(), 0.0); // a variance times V/kT
  EXPECT_TRUE(pc["G_hold_stderr_Pa"].is_number());
  EXPECT_TRUE(pc["K_Pa"].is_number());
  EXPECT_DOUBLE_EQ(pc["hold_time_s"].get<double>(), 200 * 1e-15);
  const bool solid = pc["solid"].get<bool>();
  EXPECT_EQ(pc["phase"], solid ? "solid on the hold time scale" : "relaxes within a hold");
  EXPECT_NE(report.find(pc["phase"].get<std::string>()), std::string::npos);
  if (!solid) {
    for (const char* n : {"C44", "B1", "B2", "B4", "alpha"})
      EXPECT_EQ(j["constants"][n]["status"], "not identified") << n;
    EXPECT_NE(j["verdict"].dump().find("not defined by these data"), std::string::npos);
  }
  for (const char* f : {"cases.h5", "card.h5", "report.md", "recipe.json", "build/rve.data",
                        "build/build.h5", "equilibrate/final.h5", "phase/phase.h5",
                        "cases/case_2/checkpoint.h5", "cases/case_6/checkpoint.h5"})
    EXPECT_TRUE(fs::exists(fs::path(out) / f)) << f;
  EXPECT_GT(j["equilibrated"]["density_kg_per_m3"].get<double>(), 500.0); // SI (D284)
  EXPECT_GE(j["equilibrated"]["void_fraction"].get<double>(), 0.0);
  // cases.h5: SI, labelled, relative to the zero-strain hold (row 0 dropped): 3 rows per case
  const auto data = pnc::damage::read_stress_strain_h5((fs::path(out) / "cases.h5").string());
  ASSERT_EQ(data.cases.size(), 2u);
  EXPECT_EQ(data.cases[0].id, 2);
  EXPECT_EQ(data.cases[0].strain.rows(), 3);
  EXPECT_DOUBLE_EQ(data.cases[0].strain(2, 1), 0.03);
  EXPECT_DOUBLE_EQ(data.cases[1].strain(0, 5), 0.01);
  EXPECT_EQ(data.cases[0].stress_stderr.rows(), 3);
  // the total stress by default (D134); errors from checked blocks of one structure (D132)
  EXPECT_NE(data.stress_definition.find("virial + kinetic"), std::string::npos);
  EXPECT_NE(data.stress_definition.find("block standard errors"), std::string::npos);
  EXPECT_NE(data.stress_definition.find("zero-strain hold"), std::string::npos);
  {
    // the file names its columns and says what made it (the card's provenance convention)
    pnc::h5::File f((fs::path(out) / "cases.h5").string(), pnc::h5::File::Mode::read);
    EXPECT_EQ(f.attr_string("/case_2/strain", "columns").value_or(""), "e11,e22,e33,g23,g13,g12");
    EXPECT_EQ(f.attr_string("/case_2/stress", "columns").value_or(""), "s11,s22,s33,s23,s13,s12");
    EXPECT_EQ(f.attr_string("/replicas/replica_1/case_2/raw_strain", "columns").value_or(""),
              "e11,e22,e33,g23,g13,g12");
    const std::string cmd = f.attr_string("/provenance", "command").value_or("");
    EXPECT_NE(cmd.find("characterize"), std::string::npos) << cmd;
    EXPECT_NE(cmd.find("tiny.json"), std::string::npos) << cmd;
    EXPECT_EQ(f.read_string("/provenance/software"), pnc::version_string());
    // every HDF5 file of the run folder (build, equilibration, case checkpoints, cases, card)
    // carries the same provenance block (docs/formats.md "Conventions")
    int n_h5 = 0;
    for (const auto& e : fs::recursive_directory_iterator(out)) {
      if (e.path().extension() != ".h5") continue;
      ++n_h5;
      pnc::h5::File h(e.path().string(), pnc::h5::File::Mode::read);
      const std::string where = e.path().string();
      ASSERT_TRUE(h.exists("/provenance/software")) << where;
      EXPECT_EQ(h.read_string("/provenance/software"), pnc::version_string()) << where;
      EXPECT_EQ(h.attr_string("/", "software").value_or(""), pnc::version_string()) << where;
      EXPECT_FALSE(h.attr_string("/provenance", "created").value_or("").empty()) << where;
      EXPECT_FALSE(h.attr_string("/provenance", "command").value_or("").empty()) << where;
    }
    EXPECT_GE(n_h5, 4) << "build.h5, a case checkpoint, cases.h5 and card.h5 at least";
    // counts are integers (readable as numbers too)
    pnc::h5::File b((fs::path(out) / "build/build.h5").string(), pnc::h5::File::Mode::read);
    EXPECT_TRUE(b.is_integer("/result/atoms"));
    EXPECT_EQ(b.read_vector("/result/type").size(),
              static_cast<std::size_t>(b.read_integer("/result/atoms")));
  }
  // resume of a finished run recomputes nothing (case checkpoints untouched)
  const auto t2 = fs::last_write_time(fs::path(out) / "cases/case_2/checkpoint.h5");
  // (with the figures this time: the report page of a one-replica run, D131 error bars)
  const Proc again = run("characterize " + (d / "tiny.json").string() + " --out " + out +
                         " --resume 2>" + (d / "err2.txt").string());
  EXPECT_EQ(again.code, r.code); // the same data, the same fit and verdict
  EXPECT_EQ(fs::last_write_time(fs::path(out) / "cases/case_2/checkpoint.h5"), t2);
  expect_report_page(out, j, slurp((d / "err2.txt").string()));
  expect_md_figure(out, data);
  expect_md_figure_drawn(out);
  // the page in a real browser (here, not in the slower two-replica test): both figures decode, no
  // console error, not blank
  const auto page = pnc::test::render_in_chromium(out + "/report.html", d.string());
  ASSERT_EQ(page.error, "");
  EXPECT_EQ(page.images, (std::vector<std::string>{"ok", "ok"}));
  EXPECT_EQ(page.console, std::vector<std::string>{});
  EXPECT_GT(page.ink, 0.02); // text, tables and figures (a blank page is below 1 %)
  // without --resume an existing run is refused, naming --out
  const Proc refuse = run("characterize " + (d / "tiny.json").string() + " --out " + out + " 2>&1");
  EXPECT_EQ(refuse.code, 1);
  EXPECT_NE(refuse.out.find("--resume"), std::string::npos) << refuse.out;
  fs::remove_all(d);
}

// Two independent replicas (decision D130): own build and equilibration each, every case on
// every replica, between-replica errors in cases.h5, and --resume after the run does nothing.
TEST(RveCharacterizeCli, TwoReplicasGiveBetweenReplicaErrorsAndResumeDoesNothing) {
  const auto d = pnc::test::fresh_dir("test_rve_char_replicas");
  auto recipe = nlohmann::json::parse(tiny);
  recipe["run"]["replicas"] = 2;
  recipe["name"] = "tiny-replicas";
  // the machinery is under test, not the physics: shorter equilibration and reference hold
  recipe["equilibrate"]["hot_steps"] = 500;
  recipe["equilibrate"]["npt_steps"] = 500;
  recipe["deform"]["reference_holds"] = 1;
  std::ofstream(d / "tiny2.json") << recipe.dump();
  const std::string out = (d / "out").string();
  const Proc r = run("characterize " + (d / "tiny2.json").string() + " --out " + out +
                     " --json --no-plots 2>" + (d / "err.txt").string());
  ASSERT_TRUE(r.code == 0 || r.code == 3 || r.code == 4)
      << r.code << " " << r.out << slurp((d / "err.txt").string());
  const auto js = nlohmann::json::parse(r.out);
  EXPECT_EQ(js["statistics"]["error_method"], "replicas");
  EXPECT_EQ(js["statistics"]["cases"][0]["replica_slopes_Pa"].size(), 2u);
  // two replicas are too few for the bootstrap check of the error bars (D431): it says so
  EXPECT_EQ(js["statistics"]["bootstrap"]["applicable"], false);
  EXPECT_NE(js["statistics"]["bootstrap"]["why_not"].get<std::string>().find("this run: 2"),
            std::string::npos);
  std::vector<fs::path> ckpts;
  for (const char* rep : {"replica_1", "replica_2"}) {
    for (const char* f : {"build/rve.data", "build/build.h5", "equilibrate/final.h5"})
      EXPECT_TRUE(fs::exists(fs::path(out) / rep / f)) << rep << "/" << f;
    for (const char* c : {"cases/case_2/checkpoint.h5", "cases/case_6/checkpoint.h5"}) {
      ckpts.push_back(fs::path(out) / rep / c);
      EXPECT_TRUE(fs::exists(ckpts.back())) << ckpts.back();
    }
  }
  EXPECT_FALSE(fs::exists(fs::path(out) / "cases")); // no single-replica layout next to it
  // independent structures: the two builds differ
  EXPECT_NE(slurp(out + "/replica_1/build/rve.data"), slurp(out + "/replica_2/build/rve.data"));
  const std::string h5 = (fs::path(out) / "cases.h5").string();
  const auto data = pnc::damage::read_stress_strain_h5(h5);
  ASSERT_EQ(data.cases.size(), 2u);
  EXPECT_NE(data.stress_definition.find("between-replica"), std::string::npos);
  {
    pnc::h5::File f(h5, pnc::h5::File::Mode::read);
    EXPECT_EQ(f.attr_string("/", "error_method").value_or(""), "replicas");
    // the point error is sd/sqrt(2) of the two replicas' fit rows, never below the variance
    // pooled over the rows of the curve (D130), recomputed here
    for (const int id : {2, 6}) {
      const std::string c = "/case_" + std::to_string(id);
      const auto a = f.read_matrix("/replicas/replica_1" + c + "/stress");
      const auto b = f.read_matrix("/replicas/replica_2" + c + "/stress");
      const auto m = f.read_matrix(c + "/stress");
      const auto se = f.read_matrix(c + "/stress_stderr");
      ASSERT_EQ(a.rows(), 3);
      for (Eigen::Index j = 0; j < 6; ++j) {
        // variance of two values: (a - b)^2 / 2
        double pooled = 0;
        for (Eigen::Index k = 0; k < a.rows(); ++k)
          pooled += 0.5 * std::pow(a(k, j) - b(k, j), 2) / static_cast<double>(a.rows());
        for (Eigen::Index k = 0; k < a.rows(); ++k) {
          EXPECT_NEAR(m(k, j), 0.5 * (a(k, j) + b(k, j)), 1e-6 * (1 + std::fabs(m(k, j))));
          const double v = std::max(0.5 * std::pow(a(k, j) - b(k, j), 2), pooled);
          EXPECT_NEAR(se(k, j), std::sqrt(v / 2), 1e-6 * (1 + se(k, j)));
        }
      }
    }
  }
  EXPECT_NE(slurp((fs::path(out) / "report.md").string()).find("between-replica standard errors"),
            std::string::npos);
  EXPECT_NE(slurp((fs::path(out) / "report.md").string())
                .find("Between-replica errors of the fitted constants"),
            std::string::npos);
  EXPECT_NE(slurp((fs::path(out) / "report.md").string())
                .find("bootstrap of the joint fit\n\nNot run: needs >= 8 replicas"),
            std::string::npos);
  // every replica's own fit (replica_fits.csv): two rows; the card's standard error of a fitted
  // constant is at least t x sd/sqrt(2) of the two (D130, t = 1.84 for 1 degree of freedom)
  {
    std::istringstream csv(slurp((fs::path(out) / "replica_fits.csv").string()));
    std::string header, row;
    std::getline(csv, header);
    EXPECT_EQ(header.rfind("replica,C11_Pa,", 0), 0u) << header;
    std::vector<std::vector<std::string>> rows;
    while (std::getline(csv, row)) {
      std::vector<std::string> f;
      std::stringstream ss(row);
      for (std::string x; std::getline(ss, x, ',');)
        f.push_back(x);
      rows.push_back(f);
    }
    ASSERT_EQ(rows.size(), 2u);
    std::vector<std::string> names;
    std::stringstream hs(header);
    for (std::string x; std::getline(hs, x, ',');)
      names.push_back(x);
    int checked = 0;
    for (std::size_t i = 1; i < names.size(); ++i) {
      const std::string n = names[i].substr(0, names[i].rfind('_'));
      if (!js["constants"].contains(n) || !js["constants"][n]["fitted"].get<bool>()) continue;
      if (rows[0].size() <= i || rows[1].size() <= i || rows[0][i].empty() || rows[1][i].empty())
        continue;
      const double a = std::stod(rows[0][i]), b = std::stod(rows[1][i]);
      const double between = 1.8373 * std::fabs(a - b) / 2; // sd of two / sqrt(2) = |a - b| / 2
      EXPECT_GE(js["constants"][n]["std_error"].get<double>(), between * (1 - 1e-4)) << n;
      ++checked;
    }
    EXPECT_GT(checked, 0);
  }
  // --resume after the finished run recomputes nothing
  std::vector<fs::file_time_type> times;
  for (const auto& p : ckpts)
    times.push_back(fs::last_write_time(p));
  const auto tb = fs::last_write_time(fs::path(out) / "replica_2/build/rve.data");
  const Proc again = run("characterize " + (d / "tiny2.json").string() + " --out " + out +
                         " --resume 2>" + (d / "err2.txt").string());
  EXPECT_EQ(again.code, r.code);
  expect_report_page(out, js, slurp((d / "err2.txt").string()));
  for (std::size_t i = 0; i < ckpts.size(); ++i)
    EXPECT_EQ(fs::last_write_time(ckpts[i]), times[i]) << ckpts[i];
  EXPECT_EQ(fs::last_write_time(fs::path(out) / "replica_2/build/rve.data"), tb);
  const std::string err2 = slurp((d / "err2.txt").string());
  EXPECT_EQ(err2.find("finished in"), std::string::npos) << err2; // no case ran again
  fs::remove_all(d);
}

TEST(RveCharacterizeCli, BadRecipeAndRecipeShow) {
  const auto d = pnc::test::fresh_dir("test_rve_char_bad");
  std::ofstream(d / "bad.json") << R"({"deform": {"steps": 0}})";
  const Proc r =
      run("characterize " + (d / "bad.json").string() + " --out " + (d / "o").string() + " 2>&1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("deform.steps"), std::string::npos) << r.out;
  const Proc show = run("recipe show paper");
  EXPECT_EQ(show.code, 0);
  const auto j = nlohmann::json::parse(show.out);
  EXPECT_EQ(j["build"]["chains"], 75);
  fs::remove_all(d);
}

// --refit (D400): a finished run fitted again with a changed fit section runs no MD, rewrites
// the card and the summary with the new fit, and stores the new recipe; a change outside "fit"
// is refused naming the key, and so is a run whose MD units are not all done.
TEST(RveCharacterizeCli, RefitFitsAFinishedRunAgainAndChangesNothingElse) {
  const auto d = pnc::test::fresh_dir("test_rve_char_refit");
  std::ofstream(d / "tiny.json") << tiny;
  const std::string out = (d / "out").string();
  const std::string base = "characterize " + (d / "tiny.json").string();
  const Proc first = run(base + " --out " + out + " --json --no-plots 2>/dev/null");
  ASSERT_TRUE(first.code == 0 || first.code == 3 || first.code == 4) << first.code;
  const auto j1 = nlohmann::json::parse(first.out);
  EXPECT_EQ(j1["fit"]["isotropic"], false);
  const fs::path ckpt = fs::path(out) / "cases/case_2/checkpoint.h5";
  const fs::path final_h5 = fs::path(out) / "equilibrate/final.h5";
  ASSERT_TRUE(fs::exists(ckpt));
  ASSERT_TRUE(fs::exists(final_h5));
  const auto t_ckpt = fs::last_write_time(ckpt), t_final = fs::last_write_time(final_h5);

  // a change outside the fit section: refused, naming the key and its stored value
  auto other = nlohmann::json::parse(tiny);
  other["deform"]["steps"] = 4;
  std::ofstream(d / "other.json") << other.dump();
  const Proc bad = run("characterize " + (d / "other.json").string() + " --out " + out +
                       " --refit --no-plots 2>&1");
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.out.find("field 'deform.steps': value '4'"), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("(3, stored in"), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("--refit continues a run only with the same input (the fit section "
                         "may change)"),
            std::string::npos)
      << bad.out;

  // the fit section changed (the isotropic pure-polymer fit, D396): only the fit unit runs
  auto iso = nlohmann::json::parse(tiny);
  iso["fit"]["isotropic"] = true;
  std::ofstream(d / "iso.json") << iso.dump();
  const Proc again = run("characterize " + (d / "iso.json").string() + " --out " + out +
                         " --refit --json --no-plots 2>" + (d / "err.txt").string());
  const std::string err = slurp((d / "err.txt").string());
  ASSERT_TRUE(again.code == 0 || again.code == 3 || again.code == 4) << again.code << err;
  const auto j2 = nlohmann::json::parse(again.out);
  EXPECT_EQ(j2["fit"]["isotropic"], true);
  EXPECT_EQ(fs::last_write_time(ckpt), t_ckpt);
  EXPECT_EQ(fs::last_write_time(final_h5), t_final);
  EXPECT_EQ(err.find("finished in"), std::string::npos) << err; // no case ran again
  const auto stored = nlohmann::json::parse(slurp(out + "/recipe.json"));
  EXPECT_EQ(stored["fit"]["isotropic"], true);
  EXPECT_EQ(nlohmann::json::parse(slurp(out + "/summary.json"))["fit"]["isotropic"], true);

  // an MD unit not done: refused, naming it and --resume
  fs::remove(fs::path(out) / "state/replica_1/case_6.json");
  const Proc open = run("characterize " + (d / "tiny.json").string() + " --out " + out +
                        " --refit --no-plots 2>&1");
  EXPECT_EQ(open.code, 1);
  EXPECT_NE(open.out.find("value 'replica_1/case_6'"), std::string::npos) << open.out;
  // the MD units: the equilibration, the phase check and the two cases
  EXPECT_NE(open.out.find("1 of its 4 MD unit(s) are not done"), std::string::npos) << open.out;
  EXPECT_NE(open.out.find("finish the run with --resume first"), std::string::npos) << open.out;
  fs::remove_all(d);
}
