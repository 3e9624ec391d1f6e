// The version of this gearmc build: CMake's project(VERSION) and the git commit the build was
// made from (written at build time by core/version.cmake; "unknown" outside a git
// checkout, with "-dirty" when the work tree had uncommitted changes).
// Public API (docs/api.md): a stable part of the C++ interface, installed with its includes.
#pragma once

#include <string>

namespace gearmc {

std::string gearmc_version();   // e.g. "0.1.0"
std::string gearmc_git_hash();  // e.g. "163c6ed2a1b4" or "163c6ed2a1b4-dirty" or "unknown"
// "gearmc 0.1.0 (git 163c6ed2a1b4)"
std::string gearmc_version_line();

}  // namespace gearmc
