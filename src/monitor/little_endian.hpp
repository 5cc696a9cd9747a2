// Little-endian bytes, as MCAP and the Foxglove WebSocket protocol lay them out: appenders for
// integers and u32-length-prefixed bytes, and ByteCursor, a bounded reader that never reads past
// its view (a short or malformed input sets a sticky failure instead of reading out of bounds).
// Shared by the MCAP writer and reader (monitor/mcap_bytes.hpp) and the protocol's codec.
// Thread-safety: plain functions and a value type with one owner.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace keel::monitor {

/// Appends `value` in `width` little-endian bytes.
inline void putLittleEndian(std::string& out, std::uint64_t value, int width) {
  for (int i = 0; i < width; ++i) out.push_back(static_cast<char>((value >> (8 * i)) & 0xFFU));
}
inline void putU8(std::string& out, std::uint8_t v) { putLittleEndian(out, v, 1); }
inline void putU16(std::string& out, std::uint16_t v) { putLittleEndian(out, v, 2); }
inline void putU32(std::string& out, std::uint32_t v) { putLittleEndian(out, v, 4); }
inline void putU64(std::string& out, std::uint64_t v) { putLittleEndian(out, v, 8); }

/// u32 length, then the bytes (MCAP's String and Bytes).
inline void putString(std::string& out, std::string_view s) {
  putU32(out, static_cast<std::uint32_t>(s.size()));
  out.append(s);
}

/// Reads little-endian integers and length-prefixed bytes from a view. Each read past the end
/// returns a zero value and makes ok() false for good, so a parser reads a whole record (or
/// message) and checks once.
class ByteCursor {
 public:
  explicit ByteCursor(std::string_view bytes) : bytes_(bytes) {}

  bool ok() const { return ok_; }
  std::size_t position() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  bool atEnd() const { return pos_ == bytes_.size(); }
  /// Marks the input malformed (a reader of a composite found its parts wrong): ok() is false
  /// from now on, and nothing more is read.
  void fail() {
    ok_ = false;
    pos_ = bytes_.size();
  }

  std::uint64_t littleEndian(std::size_t width) {
    if (!take(width)) return 0;
    std::uint64_t v = 0;
    for (std::size_t i = width; i-- > 0;) v = (v << 8) | static_cast<unsigned char>(bytes_[pos_ - width + i]);
    return v;
  }
  std::uint8_t u8() { return static_cast<std::uint8_t>(littleEndian(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(littleEndian(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(littleEndian(4)); }
  std::uint64_t u64() { return littleEndian(8); }

  /// The next `n` bytes (a view into the input), or "" past the end.
  std::string_view bytes(std::uint64_t n) {
    if (n > remaining()) {
      fail();
      return {};
    }
    pos_ += static_cast<std::size_t>(n);
    return bytes_.substr(pos_ - static_cast<std::size_t>(n), static_cast<std::size_t>(n));
  }
  /// u32 length, then that many bytes (MCAP's String and Bytes).
  std::string_view string() { return bytes(u32()); }
  /// The rest of the view (a message's payload).
  std::string_view rest() { return bytes(remaining()); }

 private:
  bool take(std::size_t n) {
    if (n <= remaining()) {
      pos_ += n;
      return true;
    }
    fail();
    return false;
  }

  std::string_view bytes_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace keel::monitor
