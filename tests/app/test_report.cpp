// The run report of `pnc fit` (<card>_report.html and its twin <card>_report.md next to the
// card): self-contained, with the verdict, every constant and the figure, written even when
// matplotlib is missing (a warning, the exit code unchanged), and rendered by a real headless
// browser (chromium) with every image decoded and no console error.
#include "common/page_check.hpp"
#include "common/temp_dir.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace fs = std::filesystem;
using pnc::test::slurp;

namespace {

class Report : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = pnc::test::fresh_dir(
        "report_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_); // kept for a look when a test fails
  }
  std::string p(const std::string& n) const { return (dir_ / n).string(); }
  /// `pnc ARGS` in the test directory (ARGS quoted by the caller), stderr to err.txt.
  pnc::test::CommandResult pnc(const std::string& args, const std::string& env = "") const {
    return pnc::test::run_command("cd '" + dir_.string() + "' && " + env + " '" PNC_EXE "' " +
                                  args + " 2>'" + p("err.txt") + "'");
  }
  fs::path dir_;
};

std::string escaped(const std::string& s) {
  std::string o;
  for (char c : s)
    o += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
  return o;
}

/// The number in the table cell that follows the cell `<td>name</td>`, or NaN.
double cell_after(const std::string& html, const std::string& name, int skip = 0) {
  auto at = html.find("<td>" + name + "</td>");
  if (at == std::string::npos) return std::nan("");
  for (int i = 0; i <= skip; ++i) {
    at = html.find("<td class=\"num\">", at + 1);
    if (at == std::string::npos) return std::nan("");
  }
  return std::strtod(html.c_str() + at + 16, nullptr);
}

} // namespace

TEST_F(Report, FitPageIsSelfContainedWithVerdictEveryConstantAndTheFigure) {
  // a data file name with HTML specials: the page must show it escaped, never as markup
  ASSERT_EQ(pnc("synth --model pnc --points 60 --noise-mpa 2 --seed 4 --out 'a<b&c.h5'").code, 0);
  const auto f = pnc("fit --data 'a<b&c.h5' --model pnc --out card.h5 --json");
  ASSERT_TRUE(f.code == 0 || f.code == 4) << slurp(p("err.txt"));
  const auto j = nlohmann::json::parse(f.out);
  EXPECT_EQ(j["report"], "card_report.html");
  const std::string html = slurp(p("card_report.html")), md = slurp(p("card_report.md"));
  ASSERT_FALSE(html.empty());
  ASSERT_FALSE(md.empty());
  EXPECT_EQ(pnc::test::self_contained_problems(html), std::vector<std::string>{});
  EXPECT_EQ(html.find("a<b&c"), std::string::npos) << "unescaped file name";
  EXPECT_NE(html.find("a&lt;b&amp;c.h5"), std::string::npos);
  // the verdict in words and each reason
  const std::string level = j["verdict"]["level"];
  EXPECT_NE(html.find("Verdict: " + level), std::string::npos);
  EXPECT_NE(md.find("## Verdict: " + level), std::string::npos);
  for (const auto& reason : j["verdict"]["reasons"])
    EXPECT_NE(html.find(escaped(reason.get<std::string>())), std::string::npos) << reason;
  EXPECT_NE(html.find("What to do next"), std::string::npos);
  // every constant with its value (5 significant digits) and standard error (2 digits), in
  // the display units of the page: GPa, alpha dimensionless
  ASSERT_EQ(j["constants"].size(), 22u);
  for (const auto& [name, c] : j["constants"].items()) {
    const double scale = name == "alpha" ? 1.0 : 1e-9;
    const double v = c["value"].get<double>() * scale;
    EXPECT_NEAR(cell_after(html, name), v, 5e-5 * std::fabs(v) + 1e-12) << name;
    if (c["std_error"].is_number()) {
      const double se = c["std_error"].get<double>() * scale;
      EXPECT_NEAR(cell_after(html, name, 1), se, 0.05 * se) << name;
    }
  }
  // both readings of the moduli and the fit quality per curve
  EXPECT_NE(html.find("compliance inversion"), std::string::npos);
  EXPECT_NE(html.find("E2 (printed formula)"), std::string::npos);
  EXPECT_NE(html.find("R²"), std::string::npos);
  // the figure: one PNG embedded (base64 of the PNG signature is iVBORw0KGgo), linked in .md
  const std::string img = "src=\"data:image/png;base64,iVBORw0KGgo";
  EXPECT_NE(html.find(img), std::string::npos);
  EXPECT_EQ(html.find(img, html.find(img) + 1), std::string::npos) << "one figure: all cases";
  EXPECT_NE(md.find("](card_plots/fit.png)"), std::string::npos);
  EXPECT_TRUE(fs::exists(p("card_plots/fit.png")));
  EXPECT_NE(slurp(p("err.txt")).find("plotting 1 figure ..."), std::string::npos);
}

TEST_F(Report, MissingMatplotlibIsAWarningAndTheExitCodeStays) {
  ASSERT_EQ(pnc("synth --model pp --points 40 --out d.h5").code, 0);
  const auto plain = pnc("fit --data d.h5 --model pp --out plain.h5 --no-plots");
  // a Python whose matplotlib import fails as on a machine without python3-matplotlib
  fs::create_directories(dir_ / "nompl/matplotlib");
  std::ofstream(dir_ / "nompl/matplotlib/__init__.py")
      << "raise ModuleNotFoundError(\"No module named 'matplotlib'\")\n";
  const auto f =
      pnc("fit --data d.h5 --model pp --out card.h5 --json", "PYTHONPATH='" + p("nompl") + "'");
  EXPECT_EQ(f.code, plain.code) << slurp(p("err.txt"));
  const std::string err = slurp(p("err.txt"));
  EXPECT_NE(err.find("warning: figures not drawn"), std::string::npos) << err;
  EXPECT_NE(err.find("matplotlib"), std::string::npos) << err;
  const auto j = nlohmann::json::parse(f.out);
  EXPECT_TRUE(j["plots"].empty());
  EXPECT_NE(j["plot_warning"].get<std::string>().find("matplotlib"), std::string::npos);
  EXPECT_TRUE(fs::exists(p("card.h5")));
  const std::string html = slurp(p("card_report.html"));
  EXPECT_NE(html.find("Figures not drawn"), std::string::npos);
  EXPECT_EQ(html.find("data:image/png"), std::string::npos);
  EXPECT_EQ(pnc::test::self_contained_problems(html), std::vector<std::string>{});
}

TEST_F(Report, FitPageRendersInHeadlessChromium) {
  ASSERT_EQ(pnc("synth --model pp --points 60 --max-extension 0.3 --out d.h5").code, 0);
  ASSERT_EQ(pnc("fit --data d.h5 --model pp --out card.h5").code, 0) << slurp(p("err.txt"));
  const auto r = pnc::test::render_in_chromium(p("card_report.html"), dir_.string());
  ASSERT_EQ(r.error, "");
  EXPECT_EQ(r.images, std::vector<std::string>{"ok"}) << "the embedded figure decodes";
  EXPECT_EQ(r.console, std::vector<std::string>{});
  // not a blank page: text, tables and the figure leave ink (measured about 6 % of the
  // 1200 x 3000 screenshot; an empty or unstyled white page is below 1 %)
  EXPECT_GT(r.ink, 0.02);
}

// The material driver's page (8 steps of uniaxial strain on the tabulated pnc card) in a real
// browser: it loads with no console message, its one figure (r.png, embedded) decodes, and the
// screenshot is not blank. The screenshot is left in the test's working directory:
// drive_report_screenshot.png.
TEST_F(Report, MaterialDrivePageRendersInHeadlessChromium) {
  ASSERT_EQ(pnc("card tables --model pnc --out t.h5").code, 0);
  std::ofstream(p("p.toml")) << "[[segment]]\nsteps = 8\ne11 = 0.1\n";
  ASSERT_EQ(pnc("material drive t.h5 --path p.toml --out r.csv").code, 0) << slurp(p("err.txt"));
  const auto r = pnc::test::render_in_chromium(p("r_report.html"), dir_.string());
  ASSERT_EQ(r.error, "");
  EXPECT_EQ(r.images, std::vector<std::string>{"ok"}) << "the embedded r.png decodes";
  EXPECT_EQ(r.console, std::vector<std::string>{});
  // not a blank page: the tables and the 2 x 2 panel figure leave ink (an empty or unstyled
  // white page is below 1 % of the 1200 x 3000 screenshot)
  EXPECT_GT(r.ink, 0.02);
  // the screenshot for a human, in the test's working directory (the build tree)
  fs::copy_file(dir_ / "screenshot.png", "drive_report_screenshot.png",
                fs::copy_options::overwrite_existing);
}

TEST_F(Report, MaterialDriveWritesItsPageAndFlagsAReferenceMismatchInRed) {
  ASSERT_EQ(pnc("card tables --model pnc --out t.h5").code, 0);
  std::ofstream(p("p.toml")) << "[[segment]]\nsteps = 8\ne11 = 0.1\n";
  const auto d = pnc("material drive t.h5 --path p.toml --out r.csv --json");
  ASSERT_EQ(d.code, 0) << slurp(p("err.txt"));
  const auto j = nlohmann::json::parse(d.out);
  EXPECT_EQ(j["report"], "r_report.html");
  const std::string html = slurp(p("r_report.html"));
  EXPECT_EQ(pnc::test::self_contained_problems(html), std::vector<std::string>{});
  EXPECT_NE(html.find("box verdict tone-good\"><div class=\"level\">Completed: 8 of 8 steps"),
            std::string::npos);
  EXPECT_NE(html.find("src=\"data:image/png;base64,iVBORw0KGgo"), std::string::npos);
  // the end stress in MPa, 6 significant digits, as the JSON summary has it in Pa
  const double s11 = j["final"]["stress_Pa"][0].get<double>() / 1e6;
  EXPECT_NEAR(cell_after(html, "σ11 / ε11", 1), s11, 1e-5 * s11);
  EXPECT_NE(slurp(p("r_report.md")).find("](r.png)"), std::string::npos);
  // a reference whose s11 is 1 % + 1 kPa off in every row (steps 0..8: 9 values beyond the
  // default tolerance 1 Pa + 1e-6 |reference|): exit 5 and a red box naming the mismatch
  std::ifstream in(p("r.csv"));
  std::ofstream ref(p("ref.csv"));
  std::string line, header;
  std::getline(in, header);
  while (header.rfind('#', 0) == 0)
    std::getline(in, header);
  ref << header << "\n";
  const auto col = [&] {
    std::size_t c = 0, at = 0;
    for (; header.compare(at, 7, "s11_Pa,") != 0; ++c)
      at = header.find(',', at) + 1;
    return c;
  }();
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::size_t at = 0;
    for (auto e = line.find(',');; e = line.find(',', at)) {
      cells.push_back(line.substr(at, e == std::string::npos ? e : e - at));
      if (e == std::string::npos) break;
      at = e + 1;
    }
    cells[col] = std::to_string(std::stod(cells[col]) * 1.01 + 1e3);
    for (std::size_t c = 0; c < cells.size(); ++c)
      ref << (c ? "," : "") << cells[c];
    ref << "\n";
  }
  ref.close();
  const auto bad = pnc("material drive t.h5 --path p.toml --out r2.csv --reference ref.csv");
  EXPECT_EQ(bad.code, 5) << slurp(p("err.txt"));
  const std::string red = slurp(p("r2_report.html"));
  EXPECT_NE(red.find("box verdict tone-bad\"><div class=\"level\">Outside the reference "
                     "tolerances: 9 value(s)"),
            std::string::npos)
      << red.substr(0, 3000);
  EXPECT_NE(red.find("<td>s11_Pa</td>"), std::string::npos);
}
