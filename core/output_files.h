// A set of output files of one command written all-or-nothing (docs/formats.md: nothing is
// half-written): each file is written as "<name>.partial" in the output folder and all are
// renamed to their names together by commit(); if the object is destroyed before commit()
// (an exception), the partial files are removed. A single file is written atomically with
// write_file_atomically (temporary name, then rename). In core: every command and module that
// writes an output uses these, none writes its own.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace gearmc {

// Checks, before any work, that `dir` can hold a command's outputs: creates it (and its parents)
// when missing — `*created` says whether this call made it, so the caller can remove it again
// if the command fails — and proves it writable by creating and removing a probe file. Throws
// InputError naming the folder and the system's reason (e.g. "Permission denied").
void prepare_output_folder(const std::filesystem::path& dir, bool* created);

// Checks, before any work, that `file` can be written: its folder exists and is writable, and
// `file` is not a folder and can be opened for writing (tried, and removed again if it did not
// exist). `option` names the command-line option (e.g. "--out") in the message.
void check_output_file(const std::filesystem::path& file, const std::string& option);

// Removes `dir` if it is empty (a folder a failed or interrupted command created); errors are
// ignored.
void remove_if_empty(const std::filesystem::path& dir);

// Writes `content` to `file` atomically: to "<file>.tmp" in the same directory, flushed and
// closed, then renamed over `file` (std::filesystem::rename, atomic on POSIX within one file
// system). On failure removes the temporary file and throws std::runtime_error naming the file;
// an existing `file` is left untouched. The directory must exist.
void write_file_atomically(const std::filesystem::path& file, std::string_view content);

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
