// Reading a user's input file safely and making its bytes fit for messages. A scenario or
// readings file is read only if it is a regular file (stat before open: a FIFO would block,
// /dev/zero would never end, a directory is no text) no larger than a stated cap; YAML text
// must be UTF-8 (it ends up in JSON outputs and reports). Every failure is an InputError that
// names the file (and line:column for a bad byte).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "core/input_error.h"

namespace gearmc {

// Largest scenario file read: 64 MiB. The largest real scenario is a few kB; a file this big
// is a wrong file, and yaml-cpp keeps about 50 bytes of nodes per input byte.
inline constexpr std::uintmax_t kMaxScenarioBytes = 64ull << 20;
// Largest readings file read: 1 GiB (about 10 million points of about 100 bytes each, 1 000
// gears of P1's 10 x 5 x 24 x 2 grid four times over).
inline constexpr std::uintmax_t kMaxReadingsBytes = 1ull << 30;
// Longest line of a readings CSV: a row of 16 shortest-round-trip numbers is under 400 bytes.
inline constexpr std::size_t kMaxReadingsLineBytes = 4096;

// Why `path` cannot be read as an input file of at most `max_bytes` bytes ("it is a FIFO (named
// pipe), expected a regular file", "No such file or directory", "it has 5000 bytes, more than
// the 64 MiB a scenario file may have"), or nullopt when it is a regular file within the cap.
// Only regular files are inputs: a FIFO would block, /dev/zero would never end.
std::optional<std::string> unreadable_input_reason(const std::string& path, const std::string& what,
                                                   std::uintmax_t max_bytes);

// The whole file as bytes. `what` names the file's role in messages ("scenario file").
// Throws InputError: missing or unreadable, not a regular file (directory, FIFO, device),
// larger than `max_bytes`, or a read error.
std::string read_input_file(const std::string& path, const std::string& what,
                            std::uintmax_t max_bytes);

// The byte offset of the first byte that is not part of well-formed UTF-8 (RFC 3629: no
// overlong forms, no surrogates, at most U+10FFFF), or nullopt when all of `text` is UTF-8.
std::optional<std::size_t> first_invalid_utf8(std::string_view text);

// 1-based line and column of byte `offset` in `text` (columns count bytes, as yaml-cpp does).
InputLocation location_of_offset(std::string_view text, std::size_t offset,
                                 const std::string& file);

// Throws InputError at the first byte of `text` that is not UTF-8, naming it in hex.
void require_utf8(std::string_view text, const std::string& file, const std::string& what);

}  // namespace gearmc
