#pragma once
// pnc/core/html_page.hpp: the one writer of pnc's run reports (report.html and its plain-text
// twin report.md; docs/formats.md "Run reports").
//
// A Page is a list of blocks (sections, paragraphs, fact tables, tables, lists, a verdict box,
// figures, preformatted text, Markdown) rendered two ways: html() is a self-contained page
// (inline CSS, figures embedded as base64 PNG, no script, no network, no external file) and
// markdown() the same content as Markdown, figures as links relative to the Markdown file.
// Text in blocks is plain text with two inline Markdown marks understood in HTML: `code` and
// **bold**; everything else is escaped. Units belong in the text (the page adds none).
//
// Any pnc command (or a solver linking pnc_core) builds its report with it:
//   pnc::html::Page p("pnc fit: card.h5");
//   p.facts({{"command", cmd}, {"wall time", "1.2 s"}});
//   p.verdict("usable with warnings", pnc::html::Tone::warning, {...});
//   p.figure("card_plots/fit.png", "Data and fitted curves", "card_plots/fit.png");
//   p.write("card_report.html", "card_report.md");
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pnc::html {

/// HTML-escapes & < > " ' (text and attribute values alike).
std::string escape(std::string_view text);
/// Standard base64 (RFC 4648, with padding) of arbitrary bytes.
std::string base64(std::string_view bytes);
/// Escapes `text` and renders its inline marks: `code` and **bold**.
std::string inline_text(std::string_view text);
/// A Markdown subset as HTML: ATX headings (#..####), paragraphs, "- " lists, pipe tables
/// (the second line |---|), ``` fences, inline `code` and **bold**, and images
/// ![alt](relative/path.png), embedded from `base_dir`/path as base64 (a missing or non-PNG
/// file becomes a visible note, never an external reference). Headings are shifted down by
/// `heading_shift` levels (1: "#" becomes <h2>).
std::string markdown_to_html(const std::string& md, const std::string& base_dir,
                             int heading_shift = 1);

/// Colour of a block: neutral, good (green), warning (amber), bad (red).
enum class Tone { neutral, good, warning, bad };

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  /// per column: true = a number column (right-aligned, tabular figures); missing = false
  std::vector<bool> numeric;
  std::string caption; ///< optional, above the table
  /// HTML: consecutive side-by-side tables flow next to each other while the page is wide
  bool side_by_side = false;
};

class Page {
public:
  /// `title`: the <title> and the <h1> of the page.
  explicit Page(std::string title);

  Page& section(const std::string& heading);    ///< <h2>, "## " in Markdown
  Page& subsection(const std::string& heading); ///< <h3>, "### " in Markdown
  Page& paragraph(const std::string& text, Tone tone = Tone::neutral);
  /// Two-column table of label and value (what was run, key numbers).
  Page& facts(const std::vector<std::pair<std::string, std::string>>& rows);
  Page& table(const Table& t);
  Page& list(const std::vector<std::string>& items, Tone tone = Tone::neutral);
  /// The verdict in words, coloured by `tone`, with one reason per item (each coloured); a
  /// "## " heading in Markdown.
  Page& verdict(const std::string& level, Tone tone,
                const std::vector<std::pair<Tone, std::string>>& reasons);
  /// A PNG read from `png_path` when the page is rendered and embedded as base64; in Markdown
  /// a link to `md_link` (relative to the Markdown file). A missing file renders as a note.
  Page& figure(const std::string& png_path, const std::string& caption, const std::string& md_link);
  Page& preformatted(const std::string& text);
  /// Markdown (the subset of markdown_to_html) kept verbatim in report.md; in HTML its
  /// headings keep their level ("## " is <h2>) and images are resolved against `base_dir`.
  Page& markdown(const std::string& md, const std::string& base_dir);
  /// The "Warnings" section of a run report: "None." when `items` is empty, else one amber
  /// item each.
  Page& warnings(const std::vector<std::string>& items);

  std::string html() const;
  std::string markdown() const;
  /// Writes html() to `html_path` and, unless empty, markdown() to `md_path`, each atomically
  /// (pnc/core/atomic_file.hpp). Throws pnc::InputError naming the path.
  void write(const std::string& html_path, const std::string& md_path = "") const;
  /// The run report of an output folder: writes `dir`/report.html and `dir`/report.md (as
  /// write()) and returns the HTML path.
  std::string write_report(const std::string& dir) const;

private:
  enum class Kind { section, subsection, paragraph, facts, table, list, verdict, figure, pre, md };
  struct Block {
    Kind kind;
    Tone tone = Tone::neutral;
    std::string text, extra, extra2; ///< meaning by kind (caption, paths, base dir)
    Table table;
    std::vector<std::pair<Tone, std::string>> items;
  };
  std::string title_;
  std::vector<Block> blocks_;
};

} // namespace pnc::html
