// Whole text files for tests: read one (empty when it cannot be opened) or write one.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace gearmc::testing_support {

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

}  // namespace gearmc::testing_support
