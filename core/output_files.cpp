// All-or-nothing output files (see output_files.h).
#include "core/output_files.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "core/input_error.h"

namespace gearmc {

namespace fs = std::filesystem;

void prepare_output_folder(const fs::path& dir, bool* created) {
  *created = false;
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  if (fs::exists(status) && !fs::is_directory(status)) {
    throw InputError({dir.string(), 0, 0}, dir.string() + ": is not a folder (output folder)");
  }
  if (!fs::exists(status)) {
    *created = fs::create_directories(dir, ec);
    if (ec) {
      throw InputError({dir.string(), 0, 0},
                       dir.string() + ": cannot create the output folder: " + ec.message());
    }
  }
  const fs::path probe = dir / (".gearmc-write-test-" + std::to_string(::getpid()));
  std::ofstream f(probe, std::ios::binary);
  const int error = errno;
  if (!f) {
    if (*created) remove_if_empty(dir);
    throw InputError({dir.string(), 0, 0},
                     dir.string() + ": cannot write in the output folder: " + std::strerror(error));
  }
  f.close();
  fs::remove(probe, ec);
}

void check_output_file(const fs::path& file, const std::string& option) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) {
    throw InputError({}, option, file.string(), "a file name, not a folder");
  }
  const fs::path parent = file.has_parent_path() ? file.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec)) {
    throw InputError({}, option, file.string(),
                     "a file in an existing folder (" + parent.string() + " is not a folder)");
  }
  // Prove it by opening the file for writing (without truncating it), and remove it again if
  // this check created it; permission bits alone say nothing for root or read-only mounts.
  const bool existed = fs::exists(file, ec);
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int error = errno;
    throw InputError({}, option, file.string(),
                     "a file that can be written (" + std::string(std::strerror(error)) + ")");
  }
  ::close(fd);
  if (!existed) fs::remove(file, ec);
}

void remove_if_empty(const fs::path& dir) {
  std::error_code ignored;
  if (fs::is_directory(dir, ignored) && fs::is_empty(dir, ignored)) fs::remove(dir, ignored);
}

OutputFiles::OutputFiles(fs::path dir) : dir_(std::move(dir)) {}

OutputFiles::~OutputFiles() {
  std::error_code ignored;
  for (const auto& name : pending_) fs::remove(partial(name), ignored);
}

std::ofstream OutputFiles::open(const std::string& name) {
  pending_.push_back(name);
  std::ofstream f(partial(name), std::ios::binary);
  if (!f) throw InputError({dir_.string(), 0, 0}, dir_.string() + ": cannot write " + name);
  return f;
}

void OutputFiles::write(const std::string& name, const std::string& content) {
  std::ofstream f = open(name);
  f << content;
  f.close();
  if (!f) throw InputError({dir_.string(), 0, 0}, dir_.string() + ": cannot write " + name);
}

void OutputFiles::commit() {
  for (const auto& name : pending_) fs::rename(partial(name), dir_ / name);
  pending_.clear();
}

void write_file_atomically(const std::filesystem::path& file, std::string_view content) {
  std::filesystem::path temporary = file;
  temporary += ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (out) {
      out.write(content.data(), static_cast<std::streamsize>(content.size()));
      out.close();  // close() reports the last write's failure (e.g. a full disk) via failbit
    }
    if (out.fail()) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw std::runtime_error("cannot write " + file.string());
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, file, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error("cannot write " + file.string() + ": " + error.message());
  }
}

}  // namespace gearmc
