// All-or-nothing output files (see output_files.h).
#include "engine/report/output_files.h"

#include "engine/scenario/input_error.h"

namespace gearmc {

namespace fs = std::filesystem;

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

}  // namespace gearmc
