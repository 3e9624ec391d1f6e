// A small parser of the DMIS statement syntax (ANSI/DMIS 105.2 Part 1, 5.3) for the tests of the
// program `gearmc export-plan` writes: independent of the writer and of the results reader. It
// splits the text into statements (`$$` starts a comment, a line ending in `$` continues on the
// next), tokenizes each one — words, numbers, quoted strings, labels TYPE(name) of the types
// F, FA, S, D, DA, DAT, and the delimiters = / , — and parses the form
//   [LABEL =] MAJOR [/ param {, param}]
// against a vocabulary of the statements gearmc writes, with their parameter lists (a fixed word,
// one of a set of words, a number, a string, a label of a given type, per position; exact
// counts). Anything else is a parse error naming the line. The semantic checks (features defined
// before they are measured, MEAS closed by ENDMES, …) are the tests' own.
#pragma once

#include <cctype>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace gearmc::testing_support {

struct DmisToken {
  enum Kind { kWord, kNumber, kString, kLabel, kEquals, kSlash, kComma } kind;
  std::string text;        // word (upper case), string contents, label name
  std::string label_type;  // F, FA, S, D, DA, DAT
  double number = 0.0;
};

inline DmisToken dmis_token(DmisToken::Kind kind, std::string text) {
  DmisToken t{kind, std::move(text), "", 0.0};
  return t;
}

struct DmisStatement {
  int line = 0;
  std::string defines_type, defines_name;  // the label before '=' (empty: none)
  std::string major;
  std::vector<DmisToken> params;
  const DmisToken& param(std::size_t k) const { return params.at(k); }
};

class DmisParseError : public std::runtime_error {
 public:
  DmisParseError(int line, const std::string& what)
      : std::runtime_error("line " + std::to_string(line) + ": " + what) {}
};

// The statements' texts with their first lines: comments removed, continuations joined.
inline std::vector<std::pair<int, std::string>> dmis_statement_texts(const std::string& text) {
  std::vector<std::pair<int, std::string>> out;
  std::string current;
  int line_no = 0, start = 0;
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(at, end - at);
    at = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (const auto c = line.find("$$"); c != std::string::npos) line.erase(c);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    if (current.empty()) start = line_no;
    if (!line.empty() && line.back() == '$') {
      line.pop_back();
      current += line;
      continue;
    }
    current += line;
    if (current.find_first_not_of(" \t") != std::string::npos) out.emplace_back(start, current);
    current.clear();
  }
  if (!current.empty()) throw DmisParseError(start, "continuation at the end of the file");
  return out;
}

inline std::vector<DmisToken> dmis_tokens(const std::string& s, int line) {
  static const std::vector<std::string> kLabelTypes = {"F", "FA", "S", "D", "DA", "DAT"};
  std::vector<DmisToken> out;
  std::size_t i = 0;
  while (i < s.size()) {
    const char c = s[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '=' || c == '/' || c == ',') {
      const DmisToken::Kind kind = c == '='   ? DmisToken::kEquals
                                   : c == '/' ? DmisToken::kSlash
                                              : DmisToken::kComma;
      out.push_back(dmis_token(kind, std::string(1, c)));
      ++i;
    } else if (c == '\'') {
      const std::size_t close = s.find('\'', i + 1);
      if (close == std::string::npos) throw DmisParseError(line, "unterminated string");
      out.push_back(dmis_token(DmisToken::kString, s.substr(i + 1, close - i - 1)));
      i = close + 1;
    } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.') {
      // [+-] digits [. digits] [e [+-] digits], or [+-] . digits
      std::size_t j = i;
      if (s[j] == '-' || s[j] == '+') ++j;
      const std::size_t digits = j;
      while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
      if (j < s.size() && s[j] == '.') {
        ++j;
        while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
      }
      if (j == digits || (j == digits + 1 && s[digits] == '.')) {
        throw DmisParseError(line, "malformed number at column " + std::to_string(i + 1));
      }
      if (j < s.size() && (s[j] == 'e' || s[j] == 'E')) {
        std::size_t k = j + 1;
        if (k < s.size() && (s[k] == '-' || s[k] == '+')) ++k;
        const std::size_t exp = k;
        while (k < s.size() && std::isdigit(static_cast<unsigned char>(s[k]))) ++k;
        if (k == exp) throw DmisParseError(line, "malformed exponent");
        j = k;
      }
      DmisToken t = dmis_token(DmisToken::kNumber, s.substr(i, j - i));
      t.number = std::strtod(t.text.c_str(), nullptr);
      out.push_back(t);
      i = j;
    } else if (std::isalpha(static_cast<unsigned char>(c))) {
      std::size_t j = i;
      while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '_')) ++j;
      std::string word = s.substr(i, j - i);
      for (char& ch : word) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
      std::size_t k = j;
      while (k < s.size() && s[k] == ' ') ++k;
      bool is_label = false;
      for (const std::string& type : kLabelTypes) is_label = is_label || type == word;
      if (is_label && k < s.size() && s[k] == '(') {
        const std::size_t close = s.find(')', k);
        if (close == std::string::npos) throw DmisParseError(line, "unclosed label " + word);
        std::string name = s.substr(k + 1, close - k - 1);
        if (name.empty() ||
            name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                   "abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos) {
          throw DmisParseError(line, "bad label name '" + name + "'");
        }
        DmisToken t = dmis_token(DmisToken::kLabel, name);
        t.label_type = word;
        out.push_back(t);
        i = close + 1;
      } else {
        out.push_back(dmis_token(DmisToken::kWord, word));
        i = j;
      }
    } else {
      throw DmisParseError(line, std::string("unexpected character '") + c + "'");
    }
  }
  return out;
}

// One parameter slot of a statement form: "N" a number, "S" a string, "L:F" a label of type F,
// "WORD" that word, "A|B" one of the words.
inline bool dmis_slot_matches(const std::string& slot, const DmisToken& t) {
  if (slot == "N") return t.kind == DmisToken::kNumber;
  if (slot == "S") return t.kind == DmisToken::kString;
  if (slot.rfind("L:", 0) == 0)
    return t.kind == DmisToken::kLabel && t.label_type == slot.substr(2);
  if (t.kind != DmisToken::kWord) return false;
  std::size_t from = 0;
  while (true) {
    const std::size_t bar = slot.find('|', from);
    if (slot.substr(from, bar - from) == t.text) return true;
    if (bar == std::string::npos) return false;
    from = bar + 1;
  }
}

struct DmisForm {
  std::string label;               // the label type it defines ("" = none)
  std::vector<std::string> slots;  // its parameters, exactly
};

// The vocabulary of gearmc's program: per major word its forms.
inline const std::map<std::string, std::vector<DmisForm>>& dmis_vocabulary() {
  static const std::vector<std::string> six = {"N", "N", "N", "N", "N", "N"};
  const auto with = [](std::vector<std::string> head, const std::vector<std::string>& tail) {
    head.insert(head.end(), tail.begin(), tail.end());
    return head;
  };
  static const std::map<std::string, std::vector<DmisForm>> v = {
      {"DMISMN", {{"", {"S", "N"}}}},
      {"UNITS", {{"", {"MM", "ANGDEC"}}}},
      {"SNSDEF", {{"S", {"PROBE", "INDEX", "POL", "N", "N", "N", "N", "N", "N", "N"}}}},
      {"SNSLCT", {{"", {"L:S"}}}},
      {"SNSET", {{"", {"APPRCH|RETRCT|SEARCH", "N"}}}},
      {"MODE", {{"", {"MAN"}}, {"", {"AUTO", "PROG", "MAN"}}}},
      {"TEXT", {{"", {"OPER", "S"}}}},
      {"FEAT",
       {{"F", with({"POINT", "CART"}, six)},
        {"F", with({"PLANE", "CART"}, six)},
        {"F", with(with({"CYLNDR", "INNER|OUTER", "CART"}, six), {"N", "N"})}}},
      {"MEAS", {{"", {"POINT|PLANE|CYLNDR", "L:F", "N"}}}},
      {"PTMEAS", {{"", with({"CART"}, six)}}},
      {"ENDMES", {{"", {}}}},
      {"CONST", {{"", {"POINT", "L:F", "MIDPT", "L:FA", "L:FA"}}}},
      {"DATDEF", {{"", {"L:FA", "L:DAT"}}}},
      {"DATSET", {{"D", {"L:DA", "ZDIR", "XORIG", "YORIG", "L:DA", "ZORIG", "L:DA", "XDIR"}}}},
      {"ROTATE", {{"D", {"ZAXIS", "N"}}}},
      {"GOTO", {{"", {"N", "N", "N"}}}},
      {"OUTPUT", {{"", {"L:F"}}, {"", {"L:FA"}}}},
      {"ENDFIL", {{"", {}}}},
  };
  return v;
}

// The whole program parsed; throws DmisParseError at the first statement that is not one of the
// vocabulary's forms.
inline std::vector<DmisStatement> parse_dmis_program(const std::string& text) {
  std::vector<DmisStatement> out;
  for (const auto& [line, s] : dmis_statement_texts(text)) {
    const std::vector<DmisToken> t = dmis_tokens(s, line);
    DmisStatement st;
    st.line = line;
    std::size_t i = 0;
    if (t.size() >= 2 && t[0].kind == DmisToken::kLabel && t[1].kind == DmisToken::kEquals) {
      st.defines_type = t[0].label_type;
      st.defines_name = t[0].text;
      i = 2;
    }
    if (i >= t.size() || t[i].kind != DmisToken::kWord) {
      throw DmisParseError(line, "no major word in '" + s + "'");
    }
    st.major = t[i++].text;
    if (i < t.size()) {
      if (t[i].kind != DmisToken::kSlash) throw DmisParseError(line, "no '/' after " + st.major);
      ++i;
      while (true) {
        if (i >= t.size() || t[i].kind == DmisToken::kComma || t[i].kind == DmisToken::kSlash ||
            t[i].kind == DmisToken::kEquals) {
          throw DmisParseError(line, "missing parameter in '" + s + "'");
        }
        st.params.push_back(t[i++]);
        if (i == t.size()) break;
        if (t[i].kind != DmisToken::kComma) throw DmisParseError(line, "no ',' in '" + s + "'");
        ++i;
      }
    }
    const auto forms = dmis_vocabulary().find(st.major);
    if (forms == dmis_vocabulary().end()) {
      throw DmisParseError(line, "statement " + st.major + " is not in the vocabulary");
    }
    bool matched = false;
    for (const DmisForm& f : forms->second) {
      if (f.label != st.defines_type || f.slots.size() != st.params.size()) continue;
      bool all = true;
      for (std::size_t k = 0; k < f.slots.size() && all; ++k) {
        all = dmis_slot_matches(f.slots[k], st.params[k]);
      }
      matched = matched || all;
    }
    if (!matched) throw DmisParseError(line, "'" + s + "' matches no form of " + st.major);
    out.push_back(std::move(st));
  }
  return out;
}

}  // namespace gearmc::testing_support
