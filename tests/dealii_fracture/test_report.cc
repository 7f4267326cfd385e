// tests/dealii_fracture/test_report.cc: the demo's run report (report.html + report.md,
// examples/dealii_fracture/demo_report.h) of a run made by ctest dealii_fracture.demo_short.
//   test_dealii_report [gtest options] --dir DEMO_OUTPUT_DIR
// The page must stand alone (no network, no external file), carry the peak force that the
// demo's force_displacement.csv holds (read here independently), embed the annotated figure,
// and render in headless Chromium (tests/common/page_check.hpp). No deal.II in this program.
#include "common/page_check.hpp"
#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {
namespace fs = std::filesystem;
std::string g_dir;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> f;
  std::stringstream ss(line);
  for (std::string x; std::getline(ss, x, ',');)
    f.push_back(x);
  return f;
}

// The row of the largest |force| of force_displacement.csv (SI, D317): force and displacement.
struct Peak {
  double force = 0, u = 0;
  std::string unit; // the column's unit suffix: N_per_m (2-D) or N (3-D)
};
Peak csv_peak(const std::string& path) {
  std::ifstream f(path);
  std::string line;
  std::getline(f, line);
  const auto head = split(line);
  int fk = -1, uk = -1;
  Peak p;
  for (std::size_t i = 0; i < head.size(); ++i) {
    if (head[i].rfind("force_", 0) == 0) {
      fk = static_cast<int>(i);
      p.unit = head[i].substr(6);
    }
    if (head[i] == "displacement_m") uk = static_cast<int>(i);
  }
  if (fk < 0 || uk < 0) throw std::runtime_error(path + ": no force_* or displacement_m column");
  while (std::getline(f, line)) {
    const auto r = split(line);
    const double F = std::stod(r.at(fk));
    if (std::abs(F) > std::abs(p.force)) {
      p.force = F;
      p.u = std::stod(r.at(uk));
    }
  }
  return p;
}

// The number after `label` in the page's fact table: <th>label</th><td>NUMBER ...
double fact_number(const std::string& html, const std::string& label, std::string& rest) {
  const std::string key = "<th>" + label + "</th><td>";
  const auto at = html.find(key);
  if (at == std::string::npos) return NAN;
  const char* s = html.c_str() + at + key.size();
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  rest = std::string(end, std::min<std::size_t>(std::strlen(end), 40));
  return end == s ? NAN : v;
}

class DemoReport : public ::testing::Test {
protected:
  std::string p(const std::string& name) const { return (fs::path(g_dir) / name).string(); }
};

TEST_F(DemoReport, PageStandsAloneWithThePeakOfTheCsv) {
  ASSERT_TRUE(fs::exists(p("report.html"))) << "the demo writes report.html in " << g_dir;
  ASSERT_TRUE(fs::exists(p("report.md"))) << "and its twin report.md";
  const std::string html = pnc::test::slurp(p("report.html"));
  EXPECT_EQ(pnc::test::self_contained_problems(html), std::vector<std::string>{});
  // the peak force and its displacement, as the CSV has them (SI, 10 digits); the page shows
  // the demo's units (D307): 1 N/m = 1e-3 N/mm (2-D), N (3-D), 1 m = 1e3 mm. It prints 6
  // significant digits, so they agree to half a unit in the 6th digit: relative 5e-6
  const Peak peak = csv_peak(p("force_displacement.csv"));
  ASSERT_GT(std::abs(peak.force), 0.0) << "the short demo loads the specimen";
  ASSERT_TRUE(peak.unit == "N_per_m" || peak.unit == "N") << peak.unit;
  const double F_page = peak.unit == "N_per_m" ? 1e-3 * peak.force : peak.force;
  const double u_page = 1e3 * peak.u;
  std::string rest;
  const double F = fact_number(html, "peak force", rest);
  ASSERT_FALSE(std::isnan(F)) << "a 'peak force' row with a number";
  EXPECT_NEAR(F, F_page, 5e-6 * std::abs(F_page));
  EXPECT_EQ(rest.rfind(peak.unit == "N_per_m" ? " N/mm at u = " : " N at u = ", 0), 0u) << rest;
  const auto u_at = html.find("at u = ", html.find("<th>peak force</th>"));
  ASSERT_NE(u_at, std::string::npos);
  EXPECT_NEAR(std::strtod(html.c_str() + u_at + 7, nullptr), u_page, 5e-6 * std::abs(u_page));
  // what was run, the verdict, the warnings and the advice are there
  for (const char* s : {"What was run", "What to do next", "Key numbers", "Warnings",
                        "dissipated energy", "Newton iterations", "wall time", "short.prm"})
    EXPECT_NE(html.find(s), std::string::npos) << s;
  EXPECT_TRUE(html.find("Completed") != std::string::npos ||
              html.find("Stopped early") != std::string::npos)
      << "a verdict in words";
  // the force-displacement figure (and the damage map) embedded; linked in the Markdown twin
  EXPECT_NE(html.find("src=\"data:image/png;base64,iVBORw0KGgo"), std::string::npos);
  const std::string md = pnc::test::slurp(p("report.md"));
  EXPECT_NE(md.find("](force_displacement.png)"), std::string::npos);
}

TEST_F(DemoReport, RendersInHeadlessChromium) {
  const fs::path work = pnc::test::fresh_dir("dealii_report");
  const auto r = pnc::test::render_in_chromium(p("report.html"), work.string());
  ASSERT_EQ(r.error, "");
  EXPECT_EQ(r.images, (std::vector<std::string>{"ok", "ok"}))
      << "both embedded figures (force-displacement, damage map) decode";
  EXPECT_EQ(r.console, std::vector<std::string>{});
  // not a blank page: text, tables and two figures leave ink (an empty or unstyled white
  // page is below 1 % of the 1200 x 3000 screenshot; the fit page with one figure ~6 %)
  EXPECT_GT(r.ink, 0.02);
  fs::remove_all(work);
}
} // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--dir") g_dir = argv[i + 1];
  if (g_dir.empty()) {
    std::cerr << "test_dealii_report: --dir DEMO_OUTPUT_DIR is required\n";
    return 2;
  }
  return RUN_ALL_TESTS();
}
