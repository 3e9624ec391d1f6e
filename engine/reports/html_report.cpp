// The report page builder and the atomic file writer (see html_report.h).
#include "engine/reports/html_report.h"

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "core/output_files.h"
#include "engine/reports/svg_plot.h"

namespace gearmc {
namespace {

constexpr const char* kStyle = R"(body { font-family: Helvetica, Arial, sans-serif; color: #222;
  max-width: 980px; margin: 2em auto; padding: 0 1em; line-height: 1.45; }
h1 { font-size: 1.6em; border-bottom: 2px solid #0072B2; padding-bottom: 0.2em; }
h2 { font-size: 1.3em; margin-top: 1.6em; }
table { border-collapse: collapse; margin: 1em 0; }
.table-caption { font-weight: bold; margin-top: 1em; padding-bottom: 0.3em; }
.table-caption + .table-scroll table { margin-top: 0; }
th, td { border: 1px solid #ccc; padding: 0.3em 0.7em; text-align: right; }
th { background: #f0f0f0; }
th:first-child, td:first-child { text-align: left; }
table.text-last td:last-child, table.text-last th:last-child { text-align: left; }
tr.highlight td { background: #fff4d6; }
figure { margin: 1.2em 0; break-inside: avoid; }
figure svg { max-width: 100%; height: auto; }
.figure-row { display: flex; flex-wrap: wrap; gap: 0 1.5em; }
.figure-row figure { flex: 1 1 420px; min-width: 0; }
table { break-inside: avoid; }
.table-scroll { overflow-x: auto; }
h2, h3, h4, .table-caption, .pre-caption { break-after: avoid; }
figure.sheet { margin: 1.5em 0; }
.verdict { border: 2px solid #0072B2; background: #eef5fb; padding: 0.5em 1em; margin: 1em 0; }
.verdict.good { border-color: #009E73; background: #eaf7f2; }
.verdict.bad { border-color: #C00000; background: #fcecec; }
.verdict .headline { font-weight: bold; font-size: 1.1em; }
.verdict ul { margin: 0.3em 0 0.2em; padding-left: 1.3em; }
@media print { @page { size: A4 portrait; margin: 12mm; }
  body { max-width: none; margin: 0; font-size: 9.5pt; }
  nav.contents { display: none; }
  figure.sheet { break-before: page; break-inside: avoid; }
  .table-scroll { overflow: visible; }
  .figure-row figure { flex-basis: 45%; }
  pre { white-space: pre-wrap; } }
figcaption { font-size: 0.9em; color: #444; margin-top: 0.3em; }
pre { background: #f6f6f6; border: 1px solid #ddd; padding: 0.8em; overflow-x: auto;
  font-size: 0.85em; }
.pre-caption { font-weight: bold; margin-bottom: 0.3em; }
nav.contents { background: #f6f6f6; border: 1px solid #ddd; padding: 0.5em 1em; font-size: 0.92em; }
nav.contents ol { margin: 0.2em 0; padding-left: 1.4em; }
@media (min-width: 700px) { nav.contents > ol { columns: 2; column-gap: 2em; } }
nav.contents li { break-inside: avoid; }
)";

// An id from a heading's text: ASCII letters and digits lower-cased, every other run of
// characters one '-'; "section" when nothing is left.
std::string slug(std::string_view text) {
  std::string id;
  bool dash = false;
  for (const char c : text) {
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    if (alnum) {
      if (dash && !id.empty()) id += '-';
      id += static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
      dash = false;
    } else {
      dash = true;
    }
  }
  return id.empty() ? "section" : id;
}

}  // namespace

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

HtmlReport& HtmlReport::contents(std::string_view title) {
  contents_at_ = body_.size();
  contents_title_ = title;
  anchors_.clear();
  return *this;
}

HtmlReport& HtmlReport::heading(std::string_view text, int level) {
  level = std::clamp(level, 2, 4);
  const std::string tag = "h" + std::to_string(level);
  if (contents_at_ == std::string::npos) {
    body_ += '<' + tag + '>' + escape_xml(text) + "</" + tag + ">\n";
    return *this;
  }
  const std::string base = slug(text);
  std::string id = base;
  for (int repeat = 2;; ++repeat) {
    const bool taken =
        std::any_of(anchors_.begin(), anchors_.end(), [&](const Anchor& a) { return a.id == id; });
    if (!taken) break;
    id = base + '-' + std::to_string(repeat);
  }
  anchors_.push_back({level, id, std::string(text)});
  body_ += '<' + tag + " id=\"" + id + "\">" + escape_xml(text) + "</" + tag + ">\n";
  return *this;
}

HtmlReport& HtmlReport::paragraph(std::string_view text) {
  body_ += "<p>" + escape_xml(text) + "</p>\n";
  return *this;
}

HtmlReport& HtmlReport::link_paragraph(std::string_view text, std::string_view href,
                                       std::string_view link_text) {
  body_ += "<p>" + escape_xml(text) + "<a href=\"" + escape_xml(href) + "\">" +
           escape_xml(link_text) + "</a></p>\n";
  return *this;
}

HtmlReport& HtmlReport::table(const HtmlTable& table) {
  // The caption above a scrolling box: a table wider than a narrow window scrolls by itself,
  // not the page, and its caption wraps at the window's width.
  if (!table.caption.empty()) {
    body_ += "<div class=\"table-caption\">" + escape_xml(table.caption) + "</div>\n";
  }
  body_ += table.last_column_text ? "<div class=\"table-scroll\">\n<table class=\"text-last\">\n"
                                  : "<div class=\"table-scroll\">\n<table>\n";
  if (!table.header.empty()) {
    body_ += "<thead><tr>";
    for (const std::string& h : table.header) body_ += "<th>" + escape_xml(h) + "</th>";
    body_ += "</tr></thead>\n";
  }
  body_ += "<tbody>\n";
  for (const HtmlTable::Row& row : table.rows) {
    body_ += row.highlight ? "<tr class=\"highlight\">" : "<tr>";
    for (const std::string& cell : row.cells) body_ += "<td>" + escape_xml(cell) + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</tbody>\n</table>\n</div>\n";
  return *this;
}

HtmlReport& HtmlReport::figure(std::string_view svg, std::string_view caption) {
  return figure_with_class(svg, caption, "");
}

HtmlReport& HtmlReport::figure_with_class(std::string_view svg, std::string_view caption,
                                          std::string_view css_class) {
  body_ += css_class.empty() ? std::string("<figure>\n")
                             : "<figure class=\"" + std::string(css_class) + "\">\n";
  body_ += svg;
  if (!caption.empty()) body_ += "<figcaption>" + escape_xml(caption) + "</figcaption>\n";
  body_ += "</figure>\n";
  return *this;
}

HtmlReport& HtmlReport::figure_row(
    const std::vector<std::pair<std::string, std::string>>& figures) {
  body_ += "<div class=\"figure-row\">\n";
  for (const auto& [svg, caption] : figures) figure(svg, caption);
  body_ += "</div>\n";
  return *this;
}

HtmlReport& HtmlReport::sheet(std::string_view svg, std::string_view caption) {
  return figure_with_class(svg, caption, "sheet");
}

HtmlReport& HtmlReport::verdict(std::string_view headline, const std::vector<std::string>& lines,
                                Tone tone) {
  const char* tone_class = tone == Tone::kGood ? " good" : tone == Tone::kBad ? " bad" : "";
  body_ += std::string("<div class=\"verdict") + tone_class + "\">\n<div class=\"headline\">" +
           escape_xml(headline) + "</div>\n";
  if (!lines.empty()) {
    body_ += "<ul>\n";
    for (const std::string& line : lines) body_ += "<li>" + escape_xml(line) + "</li>\n";
    body_ += "</ul>\n";
  }
  body_ += "</div>\n";
  return *this;
}

HtmlReport& HtmlReport::preformatted(std::string_view text, std::string_view caption) {
  if (!caption.empty()) body_ += "<div class=\"pre-caption\">" + escape_xml(caption) + "</div>\n";
  body_ += "<pre>" + escape_xml(text) + "</pre>\n";
  return *this;
}

std::string HtmlReport::html() const {
  std::string body = body_;
  if (contents_at_ != std::string::npos) {
    std::string nav = "<nav class=\"contents\">\n<div class=\"pre-caption\">" +
                      escape_xml(contents_title_) + "</div>\n<ol>\n";
    bool open_item = false, open_sub = false;
    for (const Anchor& a : anchors_) {
      if (a.level > 3) continue;
      const std::string link = "<a href=\"#" + a.id + "\">" + escape_xml(a.text) + "</a>";
      if (a.level == 3 && open_item) {
        if (!open_sub) nav += "\n<ol>\n";
        open_sub = true;
        nav += "<li>" + link + "</li>\n";
        continue;
      }
      if (open_sub) nav += "</ol>\n";
      if (open_item) nav += "</li>\n";
      open_sub = false;
      nav += "<li>" + link;  // a level-3 heading before any level 2 is listed at the top level
      open_item = true;
    }
    if (open_sub) nav += "</ol>\n";
    if (open_item) nav += "</li>\n";
    nav += "</ol>\n</nav>\n";
    body.insert(contents_at_, nav);
  }
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
         escape_xml(title_) + "</title>\n<style>\n" + kStyle + "</style>\n</head>\n<body>\n<h1>" +
         escape_xml(title_) + "</h1>\n" + body + "</body>\n</html>\n";
}

void HtmlReport::write(const std::filesystem::path& file) const {
  write_file_atomically(file, html());
}

}  // namespace gearmc
