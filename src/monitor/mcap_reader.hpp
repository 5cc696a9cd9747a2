// readMcap: keel's reader of MCAP files (https://mcap.dev/spec), for `keel report FILE.mcap` and
// the tests: one linear scan from the start, tolerant of a file cut anywhere (a kill -9 of the
// writer) and of garbage: it stops at the first record that is cut or malformed, or at a chunk
// whose CRC does not match, returns everything before it, and says where and why it stopped.
// A bad chunk yields none of its messages. A Message record before any Channel record of its
// channel id is malformed (the spec requires the Channel first), so every message returned has
// its channel among the file's channels. Reads uncompressed chunks only (keel writes no other;
// PyPI's `mcap` writes them with CompressionType.NONE).
// Thread-safety: plain functions and values.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "keel/result.hpp"

namespace keel::monitor {

struct McapChannel {
  std::uint16_t id = 0;
  std::string topic;
  std::string message_encoding;
  std::uint16_t schema_id = 0;  // 0: none
  std::string schema_name;      // "" when the channel has no schema, or it was not found
  std::string schema_encoding;
  std::string schema;  // the schema's data (for keel: a JSON Schema text)
};

struct McapMessage {
  std::uint16_t channel = 0;
  std::uint64_t log_time = 0;
  std::string payload;
};

struct McapMetadata {
  std::string name;
  std::map<std::string, std::string> values;
};

struct McapFile {
  std::string library;                // the Header's
  std::vector<McapChannel> channels;  // by id, as first defined
  std::vector<McapMessage> messages;  // in file order
  std::vector<McapMetadata> metadata;
  /// The footer and the closing magic were found after a Data End record, and the data section's
  /// CRC matched (or the writer left it 0: not computed), and nothing on the way was wrong.
  bool complete = false;
  /// Why the file is not complete ("" if and only if it is): where the scan stopped before the
  /// footer, e.g. "a chunk cut at byte 81234", or what was wrong with the end.
  std::string stopped_at;

  const McapChannel* channel(std::uint16_t id) const;
};

/// Reads the MCAP file at `path`. Errors: the file cannot be read; it does not start with the
/// MCAP magic (a file shorter than the magic that is a prefix of it is a cut MCAP file, empty);
/// a chunk is compressed.
Result<McapFile> readMcap(const std::string& path);

/// The same over bytes in memory; `name` goes into the error messages in place of the path.
Result<McapFile> readMcapBytes(std::string_view bytes, const std::string& name);

}  // namespace keel::monitor
