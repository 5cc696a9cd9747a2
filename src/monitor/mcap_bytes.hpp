// MCAP's byte layer (https://mcap.dev/spec), shared by McapWriter and readMcap: the magic, the
// opcodes, its Map types and records, over the little-endian integers and bounded reader of
// monitor/little_endian.hpp.
// Thread-safety: plain functions and a value type with one owner.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>

#include "monitor/little_endian.hpp"

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

using monitor::putLittleEndian;
using monitor::putString;
using monitor::putU16;
using monitor::putU32;
using monitor::putU64;
using monitor::putU8;

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

using monitor::ByteCursor;

/// Map<String, String>, read from `in`; a malformed map fails `in`.
inline std::map<std::string, std::string> readStringMap(ByteCursor& in) {
  ByteCursor entries(in.string());
  std::map<std::string, std::string> m;
  while (in.ok() && entries.ok() && !entries.atEnd()) {
    std::string key(entries.string());
    m[key] = std::string(entries.string());
  }
  if (!entries.ok()) in.fail();
  return m;
}

}  // namespace keel::monitor::mcap
