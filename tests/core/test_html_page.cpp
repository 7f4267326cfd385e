// pnc/core/html_page.hpp: escaping, base64 (RFC 4648 test vectors), the Markdown subset, and a
// page that embeds its figure and references nothing outside itself.
#include "pnc/core/html_page.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace pnc::html;

TEST(HtmlPage, EscapesEverySpecialCharacter) {
  EXPECT_EQ(escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
  EXPECT_EQ(escape("plain 1.5 GPa"), "plain 1.5 GPa");
  // inline marks: `code` and **bold**; an unpaired mark stays text
  EXPECT_EQ(inline_text("run `pnc fit` **now** <x>"),
            "run <code>pnc fit</code> <strong>now</strong> &lt;x&gt;");
  EXPECT_EQ(inline_text("R^2 < 0.9 ** and ` alone"), "R^2 &lt; 0.9 ** and ` alone");
  EXPECT_EQ(inline_text("`<b>`"), "<code>&lt;b&gt;</code>");
}

TEST(HtmlPage, Base64MatchesTheRfc4648Vectors) {
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foob"), "Zm9vYg==");
  EXPECT_EQ(base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64(std::string("\xff\x00\x80", 3)), "/wCA");
}

TEST(HtmlPage, MarkdownSubsetBecomesHtml) {
  const std::string md = "# Title\n\nSome *text* with `code`.\nSecond line.\n\n"
                         "- one\n- two\n  continued\n\n"
                         "| a | b |\n|---|---|\n| x | 1.5 |\n| y\\|z | -2 |\n\n"
                         "```\n<raw> & text\n```\n";
  const std::string h = markdown_to_html(md, ".", 1);
  EXPECT_NE(h.find("<h2>Title</h2>"), std::string::npos) << h;
  EXPECT_NE(h.find("<p>Some *text* with <code>code</code>. Second line.</p>"), std::string::npos)
      << h;
  EXPECT_NE(h.find("<li>one</li>\n<li>two continued</li>"), std::string::npos) << h;
  EXPECT_NE(h.find("<td>y|z</td><td class=\"num\">-2</td>"), std::string::npos) << h;
  EXPECT_NE(h.find("<pre>&lt;raw&gt; &amp; text\n</pre>"), std::string::npos) << h;
}

TEST(HtmlPage, PageEmbedsItsFigureAndWritesTheMarkdownTwin) {
  const fs::path d = pnc::test::fresh_dir("html_page");
  fs::create_directories(d / "plots");
  const std::string png("\x89PNG\r\n\x1a\nfake-but-signed", 23);
  std::ofstream(d / "plots/fig.png", std::ios::binary) << png;
  Page page("run <1>");
  page.verdict("Verdict: usable with warnings", Tone::warning, {{Tone::warning, "warning: w"}});
  page.section("Numbers");
  page.table({{"name", "value"}, {{"C11", "1.5"}}, {false, true}, "GPa", false});
  page.figure((d / "plots/fig.png").string(), "the fit", "plots/fig.png");
  page.figure((d / "plots/missing.png").string(), "absent", "plots/missing.png");
  page.markdown("## Details\n\n![inline](plots/fig.png)\n", d.string());
  const std::string html = page.html();
  EXPECT_NE(html.find("<title>run &lt;1&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("box verdict tone-warning"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"num\">1.5</td>"), std::string::npos);
  const std::string img = "src=\"data:image/png;base64," + base64(png) + "\"";
  EXPECT_NE(html.find(img), std::string::npos);
  EXPECT_NE(html.find(img, html.find(img) + 1), std::string::npos) << "the Markdown image too";
  EXPECT_NE(html.find("Figure not available"), std::string::npos);
  EXPECT_EQ(html.find("http"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("src=\"plots"), std::string::npos);
  page.write((d / "report.html").string(), (d / "report.md").string());
  std::ifstream in(d / "report.md");
  const std::string md((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(md.rfind("# run <1>\n\n## Verdict: usable with warnings\n\n- warning: w\n", 0), 0u)
      << md;
  EXPECT_NE(md.find("| C11 | 1.5 |"), std::string::npos) << md;
  EXPECT_NE(md.find("![the fit](plots/fig.png)"), std::string::npos);
  EXPECT_TRUE(fs::exists(d / "report.html"));
  fs::remove_all(d);
}
