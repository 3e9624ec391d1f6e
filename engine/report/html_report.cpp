// The report page builder and the atomic file writer (see html_report.h).
#include "engine/report/html_report.h"

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "engine/io/output_files.h"
#include "engine/report/svg_plot.h"

namespace gearmc {
namespace {

constexpr const char* kStyle = R"(body { font-family: Helvetica, Arial, sans-serif; color: #222;
  max-width: 980px; margin: 2em auto; padding: 0 1em; line-height: 1.45; }
h1 { font-size: 1.6em; border-bottom: 2px solid #0072B2; padding-bottom: 0.2em; }
h2 { font-size: 1.3em; margin-top: 1.6em; }
table { border-collapse: collapse; margin: 1em 0; }
caption { caption-side: top; text-align: left; font-weight: bold; padding-bottom: 0.3em; }
th, td { border: 1px solid #ccc; padding: 0.3em 0.7em; text-align: right; }
th { background: #f0f0f0; }
th:first-child, td:first-child { text-align: left; }
tr.highlight td { background: #fff4d6; }
figure { margin: 1.2em 0; break-inside: avoid; }
figure svg { max-width: 100%; height: auto; }
.figure-row { display: flex; flex-wrap: wrap; gap: 0 1.5em; }
.figure-row figure { flex: 1 1 420px; min-width: 0; }
table { break-inside: avoid; }
h2, h3, h4, caption, .pre-caption { break-after: avoid; }
@media print { body { max-width: none; margin: 0; font-size: 10pt; }
  pre { white-space: pre-wrap; } }
figcaption { font-size: 0.9em; color: #444; margin-top: 0.3em; }
pre { background: #f6f6f6; border: 1px solid #ddd; padding: 0.8em; overflow-x: auto;
  font-size: 0.85em; }
.pre-caption { font-weight: bold; margin-bottom: 0.3em; }
)";

}  // namespace

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

HtmlReport& HtmlReport::heading(std::string_view text, int level) {
  const std::string tag = "h" + std::to_string(std::clamp(level, 2, 4));
  body_ += '<' + tag + '>' + escape_xml(text) + "</" + tag + ">\n";
  return *this;
}

HtmlReport& HtmlReport::paragraph(std::string_view text) {
  body_ += "<p>" + escape_xml(text) + "</p>\n";
  return *this;
}

HtmlReport& HtmlReport::table(const HtmlTable& table) {
  body_ += "<table>\n";
  if (!table.caption.empty()) body_ += "<caption>" + escape_xml(table.caption) + "</caption>\n";
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
  body_ += "</tbody>\n</table>\n";
  return *this;
}

HtmlReport& HtmlReport::figure(std::string_view svg, std::string_view caption) {
  body_ += "<figure>\n";
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

HtmlReport& HtmlReport::preformatted(std::string_view text, std::string_view caption) {
  if (!caption.empty()) body_ += "<div class=\"pre-caption\">" + escape_xml(caption) + "</div>\n";
  body_ += "<pre>" + escape_xml(text) + "</pre>\n";
  return *this;
}

std::string HtmlReport::html() const {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
         escape_xml(title_) + "</title>\n<style>\n" + kStyle + "</style>\n</head>\n<body>\n<h1>" +
         escape_xml(title_) + "</h1>\n" + body_ + "</body>\n</html>\n";
}

void HtmlReport::write(const std::filesystem::path& file) const {
  write_file_atomically(file, html());
}

}  // namespace gearmc
