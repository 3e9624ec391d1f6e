// The lines of an input text, one at a time, for the line-based readers (readings CSV, point
// tables): ends are "\n", "\r\n" or a lone "\r" (old Mac exports), a UTF-8 byte order mark
// (Windows exports) is skipped, and a line longer than the reader's limit is an InputError at
// its line and the first column past the limit (a binary file, or a file without line ends).
#pragma once

#include <cstddef>
#include <string>

#include "core/input_error.h"

namespace gearmc {

// One line without its end, and its 1-based number.
struct TextLine {
  std::string text;
  int number = 0;
};

class TextLines {
 public:
  // `text` and `source` must outlive the reader; `kind` names the expected file in the
  // too-long message ("a readings CSV").
  TextLines(const std::string& text, const std::string& source, std::size_t max_line_bytes,
            const char* kind)
      : text_(text), source_(source), max_line_bytes_(max_line_bytes), kind_(kind) {
    if (text_.rfind("\xEF\xBB\xBF", 0) == 0) pos_ = 3;
  }

  // The next line into `line` (its number counts on); false at the end of the text.
  bool next(TextLine* line) {
    if (pos_ >= text_.size()) return false;
    ++line->number;
    std::size_t end = text_.find_first_of("\r\n", pos_);
    if (end == std::string::npos) end = text_.size();
    if (end - pos_ > max_line_bytes_) {
      throw InputError({source_, line->number, static_cast<int>(max_line_bytes_) + 1},
                       "a line of at most " + std::to_string(max_line_bytes_) +
                           " bytes, but this line is longer (is it " + kind_ + "?)");
    }
    line->text.assign(text_, pos_, end - pos_);
    pos_ = end + (end + 1 < text_.size() && text_[end] == '\r' && text_[end + 1] == '\n' ? 2 : 1);
    return true;
  }

 private:
  const std::string& text_;
  const std::string& source_;
  std::size_t max_line_bytes_;
  const char* kind_;
  std::size_t pos_ = 0;
};

}  // namespace gearmc
