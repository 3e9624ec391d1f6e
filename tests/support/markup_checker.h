// A minimal well-formedness checker for the SVG and HTML that the reports write (balanced tags,
// quoted unique attributes, known entities only), with the start tags it saw, for the tests of
// engine/reports (report_test.cpp, inspection_charts_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <cctype>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace gearmc::testing_markup {

// --- A minimal well-formedness checker --------------------------------------------------------

struct Element {
  std::string name;
  std::map<std::string, std::string> attributes;
  std::string text;  // the raw text directly after the start tag, up to the next tag
};

// Parses `doc`; returns "" when well-formed (one root element, balanced tags, quoted unique
// attributes, '&' only in &amp; &lt; &gt; &quot; &#39; &#NNN;), else a description of the first
// problem. With `html`, skips <!DOCTYPE> and accepts the void elements meta/br/hr/img/link.
// Collects every start tag into `elements` in document order.
inline std::string check_markup(const std::string& doc, bool html, std::vector<Element>* elements) {
  const std::set<std::string> voids = {"meta", "br", "hr", "img", "link", "input"};
  std::vector<std::string> open;
  int roots = 0;
  std::size_t i = 0;
  auto entity_ok = [&](std::size_t at) {
    for (const char* e : {"&amp;", "&lt;", "&gt;", "&quot;", "&#39;"}) {
      if (doc.compare(at, std::string(e).size(), e) == 0) return true;
    }
    std::size_t k = at + 1;
    if (k < doc.size() && doc[k] == '#') {
      ++k;
      const std::size_t digits = k;
      while (k < doc.size() && std::isdigit(static_cast<unsigned char>(doc[k]))) ++k;
      return k > digits && k < doc.size() && doc[k] == ';';
    }
    return false;
  };
  while (i < doc.size()) {
    if (doc[i] != '<') {
      if (doc[i] == '&' && !entity_ok(i)) return "bad entity at " + std::to_string(i);
      if (open.empty() && !std::isspace(static_cast<unsigned char>(doc[i]))) {
        return "text outside the root at " + std::to_string(i);
      }
      if (elements && !elements->empty() && !open.empty()) elements->back().text += doc[i];
      ++i;
      continue;
    }
    if (doc.compare(i, 4, "<!--") == 0) {
      const std::size_t end = doc.find("-->", i);
      if (end == std::string::npos) return "unclosed comment";
      i = end + 3;
      continue;
    }
    if (html && doc.compare(i, 9, "<!DOCTYPE") == 0) {
      i = doc.find('>', i) + 1;
      continue;
    }
    const bool closing = i + 1 < doc.size() && doc[i + 1] == '/';
    std::size_t k = i + (closing ? 2 : 1);
    const std::size_t name_start = k;
    while (k < doc.size() &&
           (std::isalnum(static_cast<unsigned char>(doc[k])) || doc[k] == '-' || doc[k] == ':')) {
      ++k;
    }
    const std::string name = doc.substr(name_start, k - name_start);
    if (name.empty()) return "empty tag name at " + std::to_string(i);
    if (closing) {
      if (k >= doc.size() || doc[k] != '>') return "bad end tag </" + name;
      if (open.empty() || open.back() != name) {
        return "</" + name + "> does not close <" + (open.empty() ? "" : open.back()) + ">";
      }
      open.pop_back();
      i = k + 1;
      continue;
    }
    Element element{name, {}, {}};
    bool self_closing = false;
    for (;;) {
      while (k < doc.size() && std::isspace(static_cast<unsigned char>(doc[k]))) ++k;
      if (k >= doc.size()) return "unterminated tag <" + name;
      if (doc[k] == '>') {
        ++k;
        break;
      }
      if (doc.compare(k, 2, "/>") == 0) {
        self_closing = true;
        k += 2;
        break;
      }
      const std::size_t attribute_start = k;
      while (k < doc.size() && doc[k] != '=' && !std::isspace(static_cast<unsigned char>(doc[k])) &&
             doc[k] != '>') {
        ++k;
      }
      const std::string attribute = doc.substr(attribute_start, k - attribute_start);
      if (k >= doc.size() || doc[k] != '=' || k + 1 >= doc.size() || doc[k + 1] != '"') {
        return "attribute " + attribute + " of <" + name + "> is not name=\"value\"";
      }
      const std::size_t value_end = doc.find('"', k + 2);
      if (value_end == std::string::npos) return "unterminated attribute value";
      const std::string value = doc.substr(k + 2, value_end - k - 2);
      if (value.find('<') != std::string::npos) return "'<' in an attribute value";
      for (std::size_t a = value.find('&'); a != std::string::npos; a = value.find('&', a + 1)) {
        if (!entity_ok(k + 2 + a)) return "bad entity in an attribute value";
      }
      if (!element.attributes.emplace(attribute, value).second) {
        return "duplicate attribute " + attribute;
      }
      k = value_end + 1;
    }
    if (open.empty()) ++roots;
    if (elements) elements->push_back(element);
    if (!self_closing && !(html && voids.count(name))) open.push_back(name);
    i = k;
  }
  if (!open.empty()) return "<" + open.back() + "> is never closed";
  if (roots != 1) return "expected one root element, found " + std::to_string(roots);
  return "";
}

inline std::vector<Element> parse_ok(const std::string& doc, bool html = false) {
  std::vector<Element> elements;
  const std::string problem = check_markup(doc, html, &elements);
  EXPECT_EQ(problem, "") << doc.substr(0, 2000);
  return elements;
}

inline std::size_t count_text(const std::string& haystack, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t at = haystack.find(needle); at != std::string::npos;
       at = haystack.find(needle, at + 1)) {
    ++n;
  }
  return n;
}

}  // namespace gearmc::testing_markup
