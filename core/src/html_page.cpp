#include "pnc/core/html_page.hpp"

#include "pnc/core/atomic_file.hpp"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace pnc::html {

namespace {

namespace fs = std::filesystem;

// Inline CSS of every page: readable system fonts, aligned number columns, figures at the
// page width, the verdict colour-coded; print-friendly (no background images, no fonts
// fetched).
constexpr const char* kStyle = R"css(
:root { --fg: #1d2430; --muted: #5b6472; --line: #d5dae2; --band: #f4f6f9; }
* { box-sizing: border-box; }
body { margin: 0; background: #fff; color: var(--fg);
  font: 16px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif; }
main { max-width: 1180px; margin: 0 auto; padding: 20px 32px 48px; }
h1 { font-size: 1.65em; margin: .3em 0 .7em; padding-bottom: .3em;
  border-bottom: 3px solid var(--line); }
h2 { font-size: 1.3em; margin: 1.7em 0 .5em; padding-bottom: .2em;
  border-bottom: 1px solid var(--line); }
h3 { font-size: 1.1em; margin: 1.3em 0 .4em; }
h4, h5 { font-size: 1em; margin: 1.1em 0 .3em; }
p { margin: .5em 0 .8em; }
table { border-collapse: collapse; margin: .5em 0 1.1em; font-size: .92em; }
caption { caption-side: top; text-align: left; color: var(--muted); padding-bottom: 4px; }
th, td { border: 1px solid var(--line); padding: 4px 10px; text-align: left;
  vertical-align: top; }
th { background: var(--band); font-weight: 600; }
td.num, th.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
table.facts th { min-width: 12em; }
table.side { display: inline-table; vertical-align: top; margin-right: 20px; max-width: 100%; }
code, pre { font-family: "DejaVu Sans Mono", Menlo, Consolas, monospace; font-size: .88em; }
code { background: var(--band); padding: 0 3px; border-radius: 3px; }
pre { background: var(--band); border: 1px solid var(--line); padding: 10px 12px;
  overflow-x: auto; line-height: 1.35; }
ul { padding-left: 1.4em; }
li { margin: .2em 0; }
.tone-good { color: #14532d; } .tone-warning { color: #7a4a00; } .tone-bad { color: #9b1c1c; }
.box { border-left: 8px solid; border-radius: 4px; padding: 10px 18px; margin: 1em 0; }
.box.tone-good { background: #e8f5ec; border-color: #1e7b3a; }
.box.tone-warning { background: #fff5df; border-color: #c27c0e; }
.box.tone-bad { background: #fdecec; border-color: #c0262d; }
.box.tone-neutral { background: var(--band); border-color: var(--line); }
.verdict .level { font-size: 1.35em; font-weight: 700; }
.verdict ul { margin: .4em 0 0; }
figure { margin: 1em 0 1.4em; }
figure img { display: block; max-width: 100%; height: auto; border: 1px solid var(--line); }
figcaption { color: var(--muted); font-size: .92em; margin-top: 4px; }
.missing { color: var(--muted); font-style: italic; }
)css";

const char* tone_class(Tone t) {
  switch (t) {
  case Tone::good:
    return "tone-good";
  case Tone::warning:
    return "tone-warning";
  case Tone::bad:
    return "tone-bad";
  default:
    return "tone-neutral";
  }
}

bool read_png(const std::string& path, std::string& bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream ss;
  ss << in.rdbuf();
  bytes = ss.str();
  return bytes.size() > 8 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

std::string figure_html(const std::string& path, const std::string& caption) {
  std::string bytes;
  if (!read_png(path, bytes))
    return "<p class=\"missing\">Figure not available: " + escape(path) +
           " is missing or not a PNG.</p>\n";
  return "<figure><img alt=\"" + escape(caption) + "\" src=\"data:image/png;base64," +
         base64(bytes) + "\">" +
         (caption.empty() ? std::string()
                          : "<figcaption>" + inline_text(caption) + "</figcaption>") +
         "</figure>\n";
}

bool looks_numeric(const std::string& s) {
  std::size_t i = 0;
  while (i < s.size() && s[i] == ' ')
    ++i;
  if (i < s.size() && (s[i] == '-' || s[i] == '+')) ++i;
  if (i < s.size() && s[i] == '.') ++i;
  return i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]));
}

std::string table_html(const Table& t) {
  auto num = [&](std::size_t c) { return c < t.numeric.size() && t.numeric[c]; };
  std::string s = t.side_by_side ? "<table class=\"side\">" : "<table>";
  if (!t.caption.empty()) s += "<caption>" + inline_text(t.caption) + "</caption>";
  if (!t.header.empty()) {
    s += "<thead><tr>";
    for (std::size_t c = 0; c < t.header.size(); ++c)
      s += std::string(num(c) ? "<th class=\"num\">" : "<th>") + inline_text(t.header[c]) + "</th>";
    s += "</tr></thead>";
  }
  s += "<tbody>\n";
  for (const auto& row : t.rows) {
    s += "<tr>";
    for (std::size_t c = 0; c < row.size(); ++c)
      s += std::string(num(c) ? "<td class=\"num\">" : "<td>") + inline_text(row[c]) + "</td>";
    s += "</tr>\n";
  }
  return s + "</tbody></table>\n";
}

std::string md_cell(const std::string& s) {
  std::string o;
  for (char ch : s) {
    if (ch == '|') o += '\\';
    o += ch == '\n' ? ' ' : ch;
  }
  return o;
}

std::string table_md(const Table& t) {
  std::string s = t.caption.empty() ? "" : t.caption + "\n\n";
  const std::size_t n =
      !t.header.empty() ? t.header.size() : (t.rows.empty() ? 0 : t.rows[0].size());
  if (n == 0) return s;
  s += "|";
  for (std::size_t c = 0; c < n; ++c)
    s += " " + md_cell(c < t.header.size() ? t.header[c] : "") + " |";
  s += "\n|";
  for (std::size_t c = 0; c < n; ++c)
    s += c < t.numeric.size() && t.numeric[c] ? "---:|" : "---|";
  s += "\n";
  for (const auto& row : t.rows) {
    s += "|";
    for (std::size_t c = 0; c < n; ++c)
      s += " " + md_cell(c < row.size() ? row[c] : "") + " |";
    s += "\n";
  }
  return s + "\n";
}

// Splits a Markdown table row into cells ("\|" is a literal bar).
std::vector<std::string> split_row(const std::string& line) {
  std::vector<std::string> cells;
  std::string cur;
  std::size_t i = line.find('|') + 1;
  for (; i < line.size(); ++i) {
    if (line[i] == '\\' && i + 1 < line.size() && line[i + 1] == '|') {
      cur += '|';
      ++i;
    } else if (line[i] == '|') {
      cells.push_back(cur);
      cur.clear();
    } else {
      cur += line[i];
    }
  }
  auto trim = [](std::string& c) {
    const auto b = c.find_first_not_of(' '), e = c.find_last_not_of(' ');
    c = b == std::string::npos ? "" : c.substr(b, e - b + 1);
  };
  for (auto& c : cells)
    trim(c);
  return cells;
}

bool is_table_rule(const std::string& line) {
  if (line.empty() || line[0] != '|') return false;
  for (char c : line)
    if (c != '|' && c != '-' && c != ':' && c != ' ') return false;
  return line.find('-') != std::string::npos;
}

bool is_item(const std::string& line) {
  return line.size() > 2 && (line[0] == '-' || line[0] == '*') && line[1] == ' ';
}

// "![alt](path)" alone on a line: alt and path, else false.
bool image_line(const std::string& line, std::string& alt, std::string& path) {
  if (line.rfind("![", 0) != 0 || line.back() != ')') return false;
  const auto mid = line.find("](");
  if (mid == std::string::npos) return false;
  alt = line.substr(2, mid - 2);
  path = line.substr(mid + 2, line.size() - mid - 3);
  return !path.empty();
}

} // namespace

std::string escape(std::string_view text) {
  std::string o;
  o.reserve(text.size());
  for (char c : text) {
    switch (c) {
    case '&':
      o += "&amp;";
      break;
    case '<':
      o += "&lt;";
      break;
    case '>':
      o += "&gt;";
      break;
    case '"':
      o += "&quot;";
      break;
    case '\'':
      o += "&#39;";
      break;
    default:
      o += c;
    }
  }
  return o;
}

std::string base64(std::string_view bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string o;
  o.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    o += k[(v >> 18) & 63];
    o += k[(v >> 12) & 63];
    o += k[(v >> 6) & 63];
    o += k[v & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (two ? static_cast<unsigned char>(bytes[i + 1]) << 8 : 0u);
    o += k[(v >> 18) & 63];
    o += k[(v >> 12) & 63];
    o += two ? k[(v >> 6) & 63] : '=';
    o += '=';
  }
  return o;
}

std::string inline_text(std::string_view text) {
  std::string o;
  bool code = false, bold = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '`' && (code || text.find('`', i + 1) != std::string_view::npos)) {
      o += code ? "</code>" : "<code>";
      code = !code;
    } else if (!code && c == '*' && i + 1 < text.size() && text[i + 1] == '*' &&
               (bold || text.find("**", i + 2) != std::string_view::npos)) {
      o += bold ? "</strong>" : "<strong>";
      bold = !bold;
      ++i;
    } else {
      o += escape(std::string_view(&text[i], 1));
    }
  }
  return o;
}

std::string markdown_to_html(const std::string& md, const std::string& base_dir,
                             int heading_shift) {
  std::vector<std::string> lines;
  {
    std::istringstream in(md);
    std::string l;
    while (std::getline(in, l))
      lines.push_back(l);
  }
  std::string o, para;
  auto flush = [&] {
    if (!para.empty()) o += "<p>" + inline_text(para) + "</p>\n";
    para.clear();
  };
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    std::string alt, path;
    if (l.rfind("```", 0) == 0) { // fenced block, verbatim
      flush();
      std::string body;
      for (++i; i < lines.size() && lines[i].rfind("```", 0) != 0; ++i)
        body += lines[i] + "\n";
      o += "<pre>" + escape(body) + "</pre>\n";
    } else if (l.rfind('#', 0) == 0 && l.find_first_not_of('#') != std::string::npos &&
               l[l.find_first_not_of('#')] == ' ') {
      flush();
      const int level = std::min(6, static_cast<int>(l.find_first_not_of('#')) + heading_shift);
      const std::string h = std::to_string(level);
      o += "<h" + h + ">" + inline_text(l.substr(l.find_first_not_of('#') + 1)) + "</h" + h + ">\n";
    } else if (!l.empty() && l[0] == '|' && i + 1 < lines.size() && is_table_rule(lines[i + 1])) {
      flush();
      Table t;
      t.header = split_row(l);
      for (i += 2; i < lines.size() && !lines[i].empty() && lines[i][0] == '|'; ++i)
        t.rows.push_back(split_row(lines[i]));
      --i;
      t.numeric.assign(t.header.size(), false);
      for (std::size_t c = 0; c < t.header.size(); ++c) {
        bool all = !t.rows.empty();
        for (const auto& r : t.rows)
          all = all && c < r.size() && (r[c].empty() || looks_numeric(r[c]));
        t.numeric[c] = all;
      }
      o += table_html(t);
    } else if (is_item(l)) {
      flush();
      o += "<ul>\n";
      while (i < lines.size() && is_item(lines[i])) {
        std::string item = lines[i].substr(2);
        while (i + 1 < lines.size() && lines[i + 1].rfind("  ", 0) == 0 &&
               lines[i + 1].find_first_not_of(' ') != std::string::npos) {
          ++i;
          item += " " + lines[i].substr(lines[i].find_first_not_of(' '));
        }
        o += "<li>" + inline_text(item) + "</li>\n";
        ++i;
      }
      --i;
      o += "</ul>\n";
    } else if (image_line(l, alt, path)) {
      flush();
      o += figure_html((fs::path(base_dir) / path).string(), alt);
    } else if (l.find_first_not_of(' ') == std::string::npos) {
      flush();
    } else {
      para += (para.empty() ? "" : " ") + l;
    }
  }
  flush();
  return o;
}

// ------------------------------------------------------------------ Page

Page::Page(std::string title) : title_(std::move(title)) {}

Page& Page::section(const std::string& heading) {
  blocks_.push_back({Kind::section, Tone::neutral, heading, "", "", {}, {}});
  return *this;
}
Page& Page::subsection(const std::string& heading) {
  blocks_.push_back({Kind::subsection, Tone::neutral, heading, "", "", {}, {}});
  return *this;
}
Page& Page::paragraph(const std::string& text, Tone tone) {
  blocks_.push_back({Kind::paragraph, tone, text, "", "", {}, {}});
  return *this;
}
Page& Page::facts(const std::vector<std::pair<std::string, std::string>>& rows) {
  Block b{Kind::facts, Tone::neutral, "", "", "", {}, {}};
  for (const auto& [k, v] : rows)
    b.table.rows.push_back({k, v});
  blocks_.push_back(std::move(b));
  return *this;
}
Page& Page::table(const Table& t) {
  blocks_.push_back({Kind::table, Tone::neutral, "", "", "", t, {}});
  return *this;
}
Page& Page::list(const std::vector<std::string>& items, Tone tone) {
  Block b{Kind::list, tone, "", "", "", {}, {}};
  for (const auto& it : items)
    b.items.emplace_back(tone, it);
  blocks_.push_back(std::move(b));
  return *this;
}
Page& Page::warnings(const std::vector<std::string>& items) {
  section("Warnings");
  return items.empty() ? paragraph("None.") : list(items, Tone::warning);
}
Page& Page::verdict(const std::string& level, Tone tone,
                    const std::vector<std::pair<Tone, std::string>>& reasons) {
  blocks_.push_back({Kind::verdict, tone, level, "", "", {}, reasons});
  return *this;
}
Page& Page::figure(const std::string& png_path, const std::string& caption,
                   const std::string& md_link) {
  blocks_.push_back({Kind::figure, Tone::neutral, caption, png_path, md_link, {}, {}});
  return *this;
}
Page& Page::preformatted(const std::string& text) {
  blocks_.push_back({Kind::pre, Tone::neutral, text, "", "", {}, {}});
  return *this;
}
Page& Page::markdown(const std::string& md, const std::string& base_dir) {
  blocks_.push_back({Kind::md, Tone::neutral, md, base_dir, "", {}, {}});
  return *this;
}

std::string Page::html() const {
  std::string o = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                  "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
                  "<title>" +
                  escape(title_) + "</title>\n<style>" + kStyle +
                  "</style>\n</head>\n<body>\n<main>\n" + "<h1>" + inline_text(title_) + "</h1>\n";
  for (const Block& b : blocks_) {
    switch (b.kind) {
    case Kind::section:
      o += "<h2>" + inline_text(b.text) + "</h2>\n";
      break;
    case Kind::subsection:
      o += "<h3>" + inline_text(b.text) + "</h3>\n";
      break;
    case Kind::paragraph:
      o += b.tone == Tone::neutral ? "<p>" + inline_text(b.text) + "</p>\n"
                                   : "<p class=\"box " + std::string(tone_class(b.tone)) + "\">" +
                                         inline_text(b.text) + "</p>\n";
      break;
    case Kind::facts: {
      o += "<table class=\"facts\"><tbody>\n";
      for (const auto& r : b.table.rows)
        o += "<tr><th>" + inline_text(r[0]) + "</th><td>" + inline_text(r[1]) + "</td></tr>\n";
      o += "</tbody></table>\n";
      break;
    }
    case Kind::table:
      o += table_html(b.table);
      break;
    case Kind::list:
    case Kind::verdict: {
      if (b.kind == Kind::verdict)
        o += "<div class=\"box verdict " + std::string(tone_class(b.tone)) +
             "\"><div class=\"level\">" + inline_text(b.text) + "</div>\n";
      if (!b.items.empty()) o += "<ul>\n";
      for (const auto& [tone, text] : b.items)
        o += "<li class=\"" + std::string(tone_class(tone)) + "\">" + inline_text(text) + "</li>\n";
      if (!b.items.empty()) o += "</ul>\n";
      if (b.kind == Kind::verdict) o += "</div>\n";
      break;
    }
    case Kind::figure:
      o += figure_html(b.extra, b.text);
      break;
    case Kind::pre:
      o += "<pre>" + escape(b.text) + "</pre>\n";
      break;
    case Kind::md:
      o += markdown_to_html(b.text, b.extra, 0);
      break;
    }
  }
  return o + "</main>\n</body>\n</html>\n";
}

std::string Page::markdown() const {
  std::string o = "# " + title_ + "\n\n";
  for (const Block& b : blocks_) {
    switch (b.kind) {
    case Kind::section:
      o += "## " + b.text + "\n\n";
      break;
    case Kind::subsection:
      o += "### " + b.text + "\n\n";
      break;
    case Kind::paragraph:
      o += b.text + "\n\n";
      break;
    case Kind::facts: {
      Table t;
      t.header = {"", ""};
      t.rows = b.table.rows;
      o += table_md(t);
      break;
    }
    case Kind::table:
      o += table_md(b.table);
      break;
    case Kind::list:
    case Kind::verdict:
      if (b.kind == Kind::verdict) o += "## " + b.text + "\n\n";
      for (const auto& item : b.items)
        o += "- " + item.second + "\n";
      if (!b.items.empty()) o += "\n";
      break;
    case Kind::figure:
      o += "![" + b.text + "](" + b.extra2 + ")\n\n";
      break;
    case Kind::pre:
      o += "```\n" + b.text + (b.text.empty() || b.text.back() == '\n' ? "" : "\n") + "```\n\n";
      break;
    case Kind::md:
      o += b.text + (b.text.empty() || b.text.back() == '\n' ? "\n" : "\n\n");
      break;
    }
  }
  return o;
}

void Page::write(const std::string& html_path, const std::string& md_path) const {
  write_text_atomically(html_path, html());
  if (!md_path.empty()) write_text_atomically(md_path, markdown());
}

std::string Page::write_report(const std::string& dir) const {
  const std::string html_path = (std::filesystem::path(dir) / "report.html").string();
  write(html_path, (std::filesystem::path(dir) / "report.md").string());
  return html_path;
}

} // namespace pnc::html
