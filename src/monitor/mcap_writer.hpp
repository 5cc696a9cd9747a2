// McapWriter: keel's own writer of MCAP files (https://mcap.dev/spec), for `keel run --record
// FILE.mcap`: JSON messages on channels with JSON Schemas, in uncompressed chunks, each followed
// by its Message Index records, and at close a summary (schemas, channels, statistics, metadata
// and chunk indexes) that Foxglove and PyPI's `mcap` use to seek.
//
// Crash guarantee: messages are built into a chunk in memory; a chunk goes to the kernel in one
// write(2) (no fsync: a kill -9 does not lose what the kernel has) once it is a second old or
// 1 MiB (flushIfDue), so a kill -9 loses at most the chunk being built, i.e. the last second when
// flushIfDue is called at least once a second. SIGKILL can tear that one write; readMcap and
// other readers detect the torn chunk by its CRC. A file cut anywhere keeps every whole chunk
// readable: each chunk carries the Schema and Channel records of its channels' first use.
// Thread-safety: not thread-safe; one owner calls every member (the recorder's thread).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "keel/result.hpp"

namespace keel::monitor {

class McapWriter {
 public:
  /// A chunk is written once it is this old (since its first message)...
  static constexpr std::uint64_t kChunkAgeNs = 1'000'000'000;
  /// ... or this big (its records, uncompressed).
  static constexpr std::size_t kChunkBytes = 1U << 20;

  /// Creates (or truncates) `path` and writes the magic, the Header (profile "", `library`) and a
  /// Metadata record named "keel" holding `metadata` (the run's profile, start time, ...).
  static Result<McapWriter> create(const std::string& path, std::string_view library,
                                   const std::map<std::string, std::string>& metadata);

  McapWriter(McapWriter&& other) noexcept;
  McapWriter& operator=(McapWriter&& other) noexcept;
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;
  /// Closes the file if close() was not called, ignoring errors (call close() to see them).
  ~McapWriter();

  /// A new channel (ids from 1) on `topic`, its messages JSON described by `json_schema` (a JSON
  /// Schema text). Channels with the same (schema_name, json_schema) share one Schema record.
  /// Any time, also between messages: nothing is written until the channel's first message.
  std::uint16_t addChannel(std::string topic, std::string schema_name, std::string json_schema);

  /// Appends a message to the chunk being built (`log_time_ns`: ns since the Unix epoch).
  /// Never drops: the chunk grows until flushIfDue or flush writes it. After an I/O error
  /// (flush returned it), messages are discarded: the file cannot take them any more.
  void write(std::uint16_t channel, std::uint64_t log_time_ns, std::string_view json_payload);

  /// Writes the chunk if it is ≥ kChunkAgeNs old or ≥ kChunkBytes. `now_steady_ns`: the
  /// std::chrono::steady_clock time, in ns since its epoch (the clock write() reads).
  Result<void> flushIfDue(std::uint64_t now_steady_ns);
  /// Writes the chunk now (nothing when it has no messages).
  Result<void> flush();
  /// Flushes, then writes the Data End record, the summary, the footer and the closing magic, and
  /// closes the file. Later calls return the same result and write nothing.
  Result<void> close();

  /// Messages handed to the kernel (in written chunks), and the file's size so far.
  std::uint64_t messagesWritten() const { return s_.messages_written; }
  std::uint64_t bytesWritten() const { return s_.offset; }

 private:
  struct Schema {
    std::uint16_t id;
    std::string name;
    std::string data;
    bool in_file = false;  // its record was already written into a chunk
  };
  struct Channel {
    std::uint16_t id;
    std::uint16_t schema_id;
    std::string topic;
    std::uint64_t message_count = 0;
    bool in_file = false;
  };
  /// The chunk being built: its records, and for the Message Index records, where each message is.
  struct Chunk {
    std::string records;
    std::uint64_t start_time = 0;
    std::uint64_t end_time = 0;
    std::uint64_t first_steady_ns = 0;
    std::uint64_t message_count = 0;
    std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> index;  // (log_time, offset)
  };
  /// What the summary's Chunk Index record needs of a written chunk.
  struct ChunkIndex {
    std::uint64_t start_time, end_time, offset, length;
    std::map<std::uint16_t, std::uint64_t> message_index_offsets;
    std::uint64_t message_index_length, records_size;
  };
  struct MetadataIndex {
    std::uint64_t offset, length;
    std::string name;
  };

  /// Everything but the descriptor, so that a move is the descriptor's exchange and a
  /// member-wise move of this.
  struct State {
    std::string path;
    std::uint64_t offset = 0;       // bytes written so far: the next record's file offset
    std::uint32_t data_crc = 0;     // CRC-32 of every byte written, until the Data End
    std::string error;              // the first I/O error; the file takes nothing after it
    std::vector<Schema> schemas;    // schemas[id - 1]
    std::vector<Channel> channels;  // channels[id - 1]
    std::vector<MetadataIndex> metadata;
    std::vector<ChunkIndex> chunk_indexes;
    Chunk chunk;
    std::uint64_t messages_written = 0;
    std::uint64_t start_time = 0, end_time = 0;  // over the written messages
  };

  McapWriter(int fd, std::string path) : fd_(fd) { s_.path = std::move(path); }

  void appendDefinitions(Channel& channel);
  std::string chunkBytes(ChunkIndex& index) const;
  void putStatistics(std::string& out) const;
  static void putChunkIndex(std::string& out, const ChunkIndex& c);
  std::string summaryAndFooter(std::uint64_t start) const;
  Result<void> writeOut(const std::string& bytes);
  Result<void> ioError(const char* what);

  int fd_ = -1;  // -1: closed (or moved from)
  State s_;
};

}  // namespace keel::monitor
