// A set of output files of one command written all-or-nothing (interface.md: nothing is
// half-written): each file is written as "<name>.partial" in the output folder and all are
// renamed to their names together by commit(); if the object is destroyed before commit()
// (an exception), the partial files are removed. Used by `run` and `diagnose`.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace gearmc {

class OutputFiles {
 public:
  // `dir` must exist.
  explicit OutputFiles(std::filesystem::path dir);
  ~OutputFiles();
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

  // A stream on "<name>.partial" (for files written piece by piece, e.g. points.csv). Throws
  // InputError naming the folder when the file cannot be created.
  std::ofstream open(const std::string& name);
  // Writes the whole `content` as "<name>.partial"; throws InputError when it cannot.
  void write(const std::string& name, const std::string& content);
  // Renames every partial file to its name.
  void commit();
  // Where `name` will be after commit().
  std::filesystem::path path(const std::string& name) const { return dir_ / name; }

 private:
  std::filesystem::path partial(const std::string& name) const {
    return dir_ / (name + ".partial");
  }
  std::filesystem::path dir_;
  std::vector<std::string> pending_;
};

}  // namespace gearmc
