// MCAP's byte layer (https://mcap.dev/spec), shared by McapWriter and readMcap: the magic, the
// opcodes, little-endian appenders for its primitive types (integers, String, Bytes, Map) and
// records, and ByteCursor, a bounded reader that never reads past its view: a short or malformed
// input sets a sticky failure instead of reading out of bounds or throwing.
// Thread-safety: plain functions and a value type with one owner.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>

namespace keel::monitor::mcap {

/// At the start and at the end of every MCAP file: 0x89 "MCAP0\r\n".
inline constexpr std::string_view kMagic{"\x89MCAP0\r\n", 8};

/// Every record: u8 opcode, u64 content length, then the content.
inline constexpr std::size_t kRecordPrefix = 9;

enum class Op : std::uint8_t {
  Header = 0x01,
  Footer = 0x02,
  Schema = 0x03,
  Channel = 0x04,
  Message = 0x05,
  Chunk = 0x06,
  MessageIndex = 0x07,
  ChunkIndex = 0x08,
  Attachment = 0x09,
  AttachmentIndex = 0x0A,
  Statistics = 0x0B,
  Metadata = 0x0C,
  MetadataIndex = 0x0D,
  SummaryOffset = 0x0E,
  DataEnd = 0x0F,
};

// --- writing: append to a byte buffer ------------------------------------------------------

/// Appends `value` in `width` little-endian bytes.
inline void putLittleEndian(std::string& out, std::uint64_t value, int width) {
  for (int i = 0; i < width; ++i) out.push_back(static_cast<char>((value >> (8 * i)) & 0xFFU));
}
inline void putU8(std::string& out, std::uint8_t v) { putLittleEndian(out, v, 1); }
inline void putU16(std::string& out, std::uint16_t v) { putLittleEndian(out, v, 2); }
inline void putU32(std::string& out, std::uint32_t v) { putLittleEndian(out, v, 4); }
inline void putU64(std::string& out, std::uint64_t v) { putLittleEndian(out, v, 8); }

/// String and u32-length Bytes have the same layout: u32 length, then the bytes.
inline void putString(std::string& out, std::string_view s) {
  putU32(out, static_cast<std::uint32_t>(s.size()));
  out.append(s);
}

/// Map<String, String>: u32 byte length of the entries, then key, value, key, value...
inline void putStringMap(std::string& out, const std::map<std::string, std::string>& m) {
  std::string entries;
  for (const auto& [key, value] : m) {
    putString(entries, key);
    putString(entries, value);
  }
  putString(out, entries);
}

/// Map<u16, u64> (message counts and message index offsets per channel).
inline void putChannelMap(std::string& out, const std::map<std::uint16_t, std::uint64_t>& m) {
  std::string entries;
  for (const auto& [channel, value] : m) {
    putU16(entries, channel);
    putU64(entries, value);
  }
  putString(out, entries);
}

/// Starts a record: its opcode and a length that endRecord fills in once the content is there.
/// Returns where the length is.
inline std::size_t beginRecord(std::string& out, Op op) {
  putU8(out, static_cast<std::uint8_t>(op));
  const std::size_t at = out.size();
  putU64(out, 0);
  return at;
}

/// Ends the record begun at `at`: everything appended since is its content.
inline void endRecord(std::string& out, std::size_t at) {
  std::uint64_t length = out.size() - at - 8;
  for (int i = 0; i < 8; ++i, length >>= 8) out[at + i] = static_cast<char>(length & 0xFFU);
}

// --- reading: a bounded cursor -------------------------------------------------------------

/// Reads MCAP primitives from a view. Each read past the end returns a zero value and makes
/// ok() false for good, so a parser reads a whole record and checks once.
class ByteCursor {
 public:
  explicit ByteCursor(std::string_view bytes) : bytes_(bytes) {}

  bool ok() const { return ok_; }
  std::size_t position() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  bool atEnd() const { return pos_ == bytes_.size(); }

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
      ok_ = false;
      pos_ = bytes_.size();
      return {};
    }
    pos_ += static_cast<std::size_t>(n);
    return bytes_.substr(pos_ - static_cast<std::size_t>(n), static_cast<std::size_t>(n));
  }
  /// A String or u32-length Bytes.
  std::string_view string() { return bytes(u32()); }
  /// The rest of the view (a Message's data).
  std::string_view rest() { return bytes(remaining()); }

  /// Map<String, String>.
  std::map<std::string, std::string> stringMap() {
    ByteCursor entries(string());
    std::map<std::string, std::string> m;
    while (ok_ && entries.ok() && !entries.atEnd()) {
      std::string key(entries.string());
      m[key] = std::string(entries.string());
    }
    if (!entries.ok()) ok_ = false;
    return m;
  }

 private:
  bool take(std::size_t n) {
    if (n <= remaining()) {
      pos_ += n;
      return true;
    }
    ok_ = false;
    pos_ = bytes_.size();
    return false;
  }

  std::string_view bytes_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace keel::monitor::mcap
