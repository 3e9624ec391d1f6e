// Byte buffers for partial results exchanged between processes (core/ranks): fixed-width
// little-endian-as-in-memory fields appended to a std::string and read back in the same order.
// Both ends run the same executable on the same kind of machine, so values are copied bit for bit
// (a double arrives with exactly the bits it left with). A read past the end throws
// std::runtime_error (a truncated message is a bug, not bad input).
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

namespace gearmc {

class ByteWriter {
 public:
  explicit ByteWriter(std::string& out) : out_(out) {}
  template <typename T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const char*>(&value);
    out_.append(p, sizeof(T));
  }
  void put_text(std::string_view text) {
    put<std::uint64_t>(text.size());
    out_.append(text.data(), text.size());
  }

 private:
  std::string& out_;
};

class ByteReader {
 public:
  explicit ByteReader(std::string_view in) : in_(in) {}
  template <typename T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    T value;
    std::memcpy(&value, in_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }
  std::string get_text() {
    const auto n = static_cast<std::size_t>(get<std::uint64_t>());
    need(n);
    std::string text(in_.substr(pos_, n));
    pos_ += n;
    return text;
  }
  bool done() const { return pos_ == in_.size(); }

 private:
  void need(std::size_t n) const {
    if (in_.size() - pos_ < n) throw std::runtime_error("ByteReader: truncated partial result");
  }
  std::string_view in_;
  std::size_t pos_ = 0;
};

}  // namespace gearmc
