// A small builder for the self-contained report.html pages (docs/formats.md: `run` and `diagnose`
// outputs): a title, an optional table of contents, headings, paragraphs, tables with optional
// highlighted rows, inline SVG figures with captions and preformatted blocks (e.g. the scenario
// YAML). The page needs nothing
// from outside: no external CSS, JS, fonts or images; a little inline CSS for readability. All
// text is HTML-escaped; only the SVG of a figure is inserted as is (it must come from
// svg_plot.h, which escapes its own text). Files are written atomically (docs/formats.md: "nothing
// is half-written"): to FILE.tmp, then renamed to FILE.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gearmc {

struct HtmlTable {
  struct Row {
    std::vector<std::string> cells;
    bool highlight = false;  // drawn with a tinted background (e.g. P1's reference values)
  };
  std::string caption;  // empty: none
  std::vector<std::string> header;
  std::vector<Row> rows;
  bool last_column_text = false;  // the last column is prose: left-aligned like the first
};

class HtmlReport {
 public:
  // `title` goes into <title> and the page's <h1>.
  explicit HtmlReport(std::string title);

  // A table of contents at this place: html() fills it with a link to every heading of level 2
  // and 3 added after this call (level 3 nested under its level 2); every heading after it gets an
  // id made from its text ("Gap before and after" → "gap-before-and-after", "-2", "-3" … for a
  // repeated text). Without this call headings carry no id.
  HtmlReport& contents(std::string_view title = "Contents");
  HtmlReport& heading(std::string_view text, int level = 2);  // level 2..4
  HtmlReport& paragraph(std::string_view text);
  // A paragraph of `text` followed by a link to `href` (a relative path or URL) reading
  // `link_text`; all escaped.
  HtmlReport& link_paragraph(std::string_view text, std::string_view href,
                             std::string_view link_text);
  // In a box that scrolls sideways when the table is wider than the window.
  HtmlReport& table(const HtmlTable& table);
  // `svg` from svg_plot.h, inlined verbatim; `caption` escaped.
  HtmlReport& figure(std::string_view svg, std::string_view caption);
  // Figures side by side (e.g. left and right flanks), wrapping onto new lines on a narrow
  // window; each (svg, caption).
  HtmlReport& figure_row(const std::vector<std::pair<std::string, std::string>>& figures);
  // A figure across the page's full width that prints on a page of its own (an inspection sheet).
  HtmlReport& sheet(std::string_view svg, std::string_view caption);
  // The verdict box that opens a report: a bold headline and the lines under it (each escaped),
  // framed in the tone's colour (neutral blue, good green, bad red).
  enum class Tone { kNeutral, kGood, kBad };
  HtmlReport& verdict(std::string_view headline, const std::vector<std::string>& lines,
                      Tone tone = Tone::kNeutral);
  // A <pre> block, e.g. the scenario file; `caption` (optional) above it.
  HtmlReport& preformatted(std::string_view text, std::string_view caption = "");

  // The whole page: <!DOCTYPE html>, UTF-8, inline CSS, the blocks in the order added.
  std::string html() const;
  // write_file_atomically(file, html()).
  void write(const std::filesystem::path& file) const;

 private:
  // A <figure> (with `css_class` when not empty) holding `svg` and the escaped caption.
  HtmlReport& figure_with_class(std::string_view svg, std::string_view caption,
                                std::string_view css_class);
  struct Anchor {
    int level;
    std::string id, text;
  };
  std::string title_;
  std::string body_;
  // The table of contents: where in body_ it goes (npos: none), its title, its entries.
  std::size_t contents_at_ = std::string::npos;
  std::string contents_title_;
  std::vector<Anchor> anchors_;
};

}  // namespace gearmc
