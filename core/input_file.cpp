// Safe reading of input files and UTF-8 checking (see input_file.h).
#include "core/input_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace gearmc {
namespace {

std::string mib(std::uintmax_t bytes) {
  std::ostringstream s;
  if (bytes % (1ull << 20) == 0) {
    s << (bytes >> 20) << " MiB";
  } else {
    s << bytes << " bytes";
  }
  return s.str();
}

}  // namespace

std::optional<std::string> unreadable_input_reason(const std::string& path, const std::string& what,
                                                   std::uintmax_t max_bytes) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) return std::string(std::strerror(errno));
  if (S_ISDIR(info.st_mode)) return std::string("it is a directory");
  if (!S_ISREG(info.st_mode)) {
    const char* kind = S_ISFIFO(info.st_mode)                           ? "a FIFO (named pipe)"
                       : S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode) ? "a device"
                       : S_ISSOCK(info.st_mode)                         ? "a socket"
                                                                        : "not a regular file";
    return std::string("it is ") + kind + ", expected a regular file";
  }
  if (static_cast<std::uintmax_t>(info.st_size) > max_bytes) {
    return "it has " + std::to_string(info.st_size) + " bytes, more than the " + mib(max_bytes) +
           " a " + what + " may have";
  }
  return std::nullopt;
}

std::string read_input_file(const std::string& path, const std::string& what,
                            std::uintmax_t max_bytes) {
  const std::string cannot = path + ": cannot read the " + what + ": ";
  if (const auto reason = unreadable_input_reason(path, what, max_bytes)) {
    throw InputError({path, 0, 0}, cannot + *reason);
  }
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw InputError({path, 0, 0}, cannot + std::strerror(errno));
  }
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int code = errno;
    throw InputError({path, 0, 0}, cannot + (code != 0 ? std::strerror(code) : "cannot open it"));
  }
  // Read at most max_bytes + 1 bytes: the file may have grown since stat.
  std::string text;
  text.resize(static_cast<std::size_t>(info.st_size));
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw InputError({path, 0, 0}, cannot + "read error");
  if (in && in.peek() != std::char_traits<char>::eof()) {
    std::string more(4096, '\0');
    while (in && text.size() <= max_bytes) {
      in.read(more.data(), static_cast<std::streamsize>(more.size()));
      text.append(more.data(), static_cast<std::size_t>(in.gcount()));
    }
    if (text.size() > max_bytes) {
      throw InputError({path, 0, 0}, cannot + "it has more than the " + mib(max_bytes) + " a " +
                                         what + " may have");
    }
  }
  return text;
}

std::optional<std::size_t> first_invalid_utf8(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  std::size_t i = 0;
  while (i < text.size()) {
    const unsigned char b = byte(i);
    if (b < 0x80) {
      ++i;
      continue;
    }
    std::size_t length = 0;
    unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte (RFC 3629 table)
    if (b >= 0xC2 && b <= 0xDF) {
      length = 2;
    } else if (b >= 0xE0 && b <= 0xEF) {
      length = 3;
      if (b == 0xE0) lo = 0xA0;  // no overlong forms
      if (b == 0xED) hi = 0x9F;  // no surrogates
    } else if (b >= 0xF0 && b <= 0xF4) {
      length = 4;
      if (b == 0xF0) lo = 0x90;  // no overlong forms
      if (b == 0xF4) hi = 0x8F;  // at most U+10FFFF
    } else {
      return i;
    }
    if (i + length > text.size()) return i;
    if (byte(i + 1) < lo || byte(i + 1) > hi) return i;
    for (std::size_t k = 2; k < length; ++k) {
      if ((byte(i + k) & 0xC0) != 0x80) return i;
    }
    i += length;
  }
  return std::nullopt;
}

InputLocation location_of_offset(std::string_view text, std::size_t offset,
                                 const std::string& file) {
  int line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return {file, line, column};
}

void require_utf8(std::string_view text, const std::string& file, const std::string& what) {
  const std::optional<std::size_t> bad = first_invalid_utf8(text);
  if (!bad) return;
  char hex[8];
  std::snprintf(hex, sizeof hex, "0x%02X", static_cast<unsigned char>(text[*bad]));
  throw InputError(location_of_offset(text, *bad, file),
                   "the " + what + " must be UTF-8 text, but byte " + std::string(hex) +
                       " here is not part of a UTF-8 character (save the file as UTF-8)");
}

}  // namespace gearmc
