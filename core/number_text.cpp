// Shortest round-trip number text (see number_text.h).
#include "core/number_text.h"

#include <charconv>
#include <sstream>

namespace gearmc {

std::string shortest_text(double value) {
  char buffer[64];  // the longest shortest form of a double is 24 characters
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string short_text(double value, int digits) {
  std::ostringstream s;
  s.precision(digits);
  s << value;
  return s.str();
}

}  // namespace gearmc
