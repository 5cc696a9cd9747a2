#include "monitor/mcap_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <system_error>

#include "monitor/crc32.hpp"
#include "monitor/mcap_bytes.hpp"

namespace keel::monitor {
namespace {

using mcap::Op;

std::uint64_t steadyNowNs() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
          .count());
}

void putSchema(std::string& out, std::uint16_t id, std::string_view name, std::string_view json_schema) {
  auto at = mcap::beginRecord(out, Op::Schema);
  mcap::putU16(out, id);
  mcap::putString(out, name);
  mcap::putString(out, "jsonschema");
  mcap::putString(out, json_schema);
  mcap::endRecord(out, at);
}

void putChannel(std::string& out, std::uint16_t id, std::uint16_t schema_id, std::string_view topic) {
  auto at = mcap::beginRecord(out, Op::Channel);
  mcap::putU16(out, id);
  mcap::putU16(out, schema_id);
  mcap::putString(out, topic);
  mcap::putString(out, "json");
  mcap::putStringMap(out, {});
  mcap::endRecord(out, at);
}

/// A summary group: its records, all of one opcode, and where they start in the file.
struct Group {
  Op op;
  std::uint64_t start;
  std::uint64_t length;
};

}  // namespace

Result<McapWriter> McapWriter::create(const std::string& path, std::string_view library,
                                      const std::map<std::string, std::string>& metadata) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return Error{path + ": cannot create: " + std::generic_category().message(errno)};
  McapWriter w(fd, path);

  std::string head(mcap::kMagic);
  auto at = mcap::beginRecord(head, Op::Header);
  mcap::putString(head, "");  // profile: no well-known profile fits keel's JSON channels
  mcap::putString(head, library);
  mcap::endRecord(head, at);
  // The run's description sits in the data section, outside chunks, before any of them: it is
  // there in a file cut a moment after it started.
  const std::uint64_t metadata_offset = head.size();
  at = mcap::beginRecord(head, Op::Metadata);
  mcap::putString(head, "keel");
  mcap::putStringMap(head, metadata);
  mcap::endRecord(head, at);
  w.s_.metadata.push_back({metadata_offset, head.size() - metadata_offset, "keel"});

  if (auto r = w.writeOut(head); !r) return r.error();
  return w;
}

McapWriter::McapWriter(McapWriter&& other) noexcept : fd_(std::exchange(other.fd_, -1)), s_(std::move(other.s_)) {}

McapWriter& McapWriter::operator=(McapWriter&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) (void)close();
    fd_ = std::exchange(other.fd_, -1);
    s_ = std::move(other.s_);
  }
  return *this;
}

McapWriter::~McapWriter() {
  if (fd_ >= 0) (void)close();
}

std::uint16_t McapWriter::addChannel(std::string topic, std::string schema_name, std::string json_schema) {
  if (s_.channels.size() >= 0xFFFFU) return 0;  // MCAP's u16 ids are all taken: write() ignores 0
  auto same = [&](const Schema& s) { return s.name == schema_name && s.data == json_schema; };
  auto schema = std::find_if(s_.schemas.begin(), s_.schemas.end(), same);
  std::uint16_t schema_id = 0;
  if (schema != s_.schemas.end()) {
    schema_id = schema->id;
  } else {
    schema_id = static_cast<std::uint16_t>(s_.schemas.size() + 1);
    s_.schemas.push_back({schema_id, std::move(schema_name), std::move(json_schema)});
  }
  const auto id = static_cast<std::uint16_t>(s_.channels.size() + 1);
  s_.channels.push_back({id, schema_id, std::move(topic)});
  return id;
}

/// The Schema and Channel records of `channel`, into the chunk, the first time it is used in the
/// file: a reader of a file cut before the summary finds them before the channel's messages.
void McapWriter::appendDefinitions(Channel& channel) {
  std::string& out = s_.chunk.records;
  Schema& schema = s_.schemas[channel.schema_id - 1];
  if (!schema.in_file) {
    putSchema(out, schema.id, schema.name, schema.data);
    schema.in_file = true;
  }
  putChannel(out, channel.id, channel.schema_id, channel.topic);
  channel.in_file = true;
}

void McapWriter::write(std::uint16_t channel, std::uint64_t log_time_ns, std::string_view json_payload) {
  if (channel == 0 || channel > s_.channels.size() || !s_.error.empty() || fd_ < 0) return;
  Channel& c = s_.channels[channel - 1];
  Chunk& chunk = s_.chunk;
  if (chunk.message_count == 0) {
    chunk.first_steady_ns = steadyNowNs();
    chunk.start_time = chunk.end_time = log_time_ns;
  }
  if (!c.in_file) appendDefinitions(c);

  chunk.index[channel].emplace_back(log_time_ns, chunk.records.size());
  auto at = mcap::beginRecord(chunk.records, Op::Message);
  mcap::putU16(chunk.records, channel);
  mcap::putU32(chunk.records, static_cast<std::uint32_t>(c.message_count));  // sequence, per channel
  mcap::putU64(chunk.records, log_time_ns);
  mcap::putU64(chunk.records, log_time_ns);  // publish_time: keel knows only when it logged
  chunk.records.append(json_payload);
  mcap::endRecord(chunk.records, at);

  chunk.start_time = std::min(chunk.start_time, log_time_ns);
  chunk.end_time = std::max(chunk.end_time, log_time_ns);
  ++chunk.message_count;
  ++c.message_count;
}

/// The chunk as it goes to the file: the Chunk record, then one Message Index per channel in it.
/// Fills in `index` for the summary.
std::string McapWriter::chunkBytes(ChunkIndex& index) const {
  const Chunk& chunk = s_.chunk;
  std::string out;
  out.reserve(chunk.records.size() + 64 + chunk.message_count * 16 + chunk.index.size() * 16);
  auto at = mcap::beginRecord(out, Op::Chunk);
  mcap::putU64(out, chunk.start_time);
  mcap::putU64(out, chunk.end_time);
  mcap::putU64(out, chunk.records.size());
  mcap::putU32(out, crc32(chunk.records));  // never 0: a reader's one way to see a torn chunk
  mcap::putString(out, "");                 // no compression
  mcap::putU64(out, chunk.records.size());
  out.append(chunk.records);
  mcap::endRecord(out, at);

  index = {chunk.start_time, chunk.end_time, s_.offset, out.size(), {}, 0, chunk.records.size()};
  for (const auto& [channel, entries] : chunk.index) {
    index.message_index_offsets[channel] = s_.offset + out.size();
    const std::size_t start = out.size();
    at = mcap::beginRecord(out, Op::MessageIndex);
    mcap::putU16(out, channel);
    mcap::putU32(out, static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [log_time, offset] : entries) {
      mcap::putU64(out, log_time);
      mcap::putU64(out, offset);
    }
    mcap::endRecord(out, at);
    index.message_index_length += out.size() - start;
  }
  return out;
}

Result<void> McapWriter::flushIfDue(std::uint64_t now_steady_ns) {
  const Chunk& chunk = s_.chunk;
  if (chunk.message_count == 0) return {};
  const bool old = now_steady_ns >= chunk.first_steady_ns && now_steady_ns - chunk.first_steady_ns >= kChunkAgeNs;
  if (!old && chunk.records.size() < kChunkBytes) return {};
  return flush();
}

Result<void> McapWriter::flush() {
  if (!s_.error.empty()) return Error{s_.error};
  if (fd_ < 0 || s_.chunk.message_count == 0) return {};
  ChunkIndex index{};
  const std::string bytes = chunkBytes(index);
  // One write(2) for the chunk and its indexes: a kill -9 cuts at most this one.
  if (auto r = writeOut(bytes); !r) return r;
  s_.start_time = s_.chunk_indexes.empty() ? s_.chunk.start_time : std::min(s_.start_time, s_.chunk.start_time);
  s_.end_time = std::max(s_.end_time, s_.chunk.end_time);
  s_.messages_written += s_.chunk.message_count;
  s_.chunk_indexes.push_back(std::move(index));
  s_.chunk = Chunk{};
  return {};
}

Result<void> McapWriter::writeOut(const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return ioError("cannot write");
    done += static_cast<std::size_t>(n);
  }
  s_.data_crc = crc32(bytes, s_.data_crc);
  s_.offset += bytes.size();
  return {};
}

Result<void> McapWriter::ioError(const char* what) {
  // Sticky: after a failed or partial write the file's offsets are unknown, so nothing more
  // can be appended that a reader could trust.
  if (s_.error.empty()) s_.error = s_.path + ": " + what + ": " + std::generic_category().message(errno);
  return Error{s_.error};
}

void McapWriter::putStatistics(std::string& out) const {
  std::map<std::uint16_t, std::uint64_t> counts;
  for (const Channel& c : s_.channels) counts[c.id] = c.message_count;
  auto at = mcap::beginRecord(out, Op::Statistics);
  mcap::putU64(out, s_.messages_written);
  mcap::putU16(out, static_cast<std::uint16_t>(s_.schemas.size()));
  mcap::putU32(out, static_cast<std::uint32_t>(s_.channels.size()));
  mcap::putU32(out, 0);  // attachments
  mcap::putU32(out, static_cast<std::uint32_t>(s_.metadata.size()));
  mcap::putU32(out, static_cast<std::uint32_t>(s_.chunk_indexes.size()));
  mcap::putU64(out, s_.start_time);
  mcap::putU64(out, s_.end_time);
  mcap::putChannelMap(out, counts);
  mcap::endRecord(out, at);
}

void McapWriter::putChunkIndex(std::string& out, const ChunkIndex& c) {
  auto at = mcap::beginRecord(out, Op::ChunkIndex);
  mcap::putU64(out, c.start_time);
  mcap::putU64(out, c.end_time);
  mcap::putU64(out, c.offset);
  mcap::putU64(out, c.length);
  mcap::putChannelMap(out, c.message_index_offsets);
  mcap::putU64(out, c.message_index_length);
  mcap::putString(out, "");           // compression
  mcap::putU64(out, c.records_size);  // compressed size: the same, uncompressed
  mcap::putU64(out, c.records_size);
  mcap::endRecord(out, at);
}

/// The summary (a group of records per opcode) for a summary starting at file offset `start`,
/// a Summary Offset per group, the Footer and the closing magic.
std::string McapWriter::summaryAndFooter(std::uint64_t start) const {
  std::string out;
  std::vector<Group> groups;
  auto group = [&](Op op, auto&& put_records) {
    const std::size_t begin = out.size();
    put_records();
    if (out.size() > begin) groups.push_back({op, start + begin, out.size() - begin});
  };
  // Every channel (not only those with messages) and its schema: a reader looking up a chunk's
  // channel in the summary must find it there.
  group(Op::Schema, [&] {
    for (const Schema& s : s_.schemas) putSchema(out, s.id, s.name, s.data);
  });
  group(Op::Channel, [&] {
    for (const Channel& c : s_.channels) putChannel(out, c.id, c.schema_id, c.topic);
  });
  group(Op::Statistics, [&] { putStatistics(out); });
  group(Op::MetadataIndex, [&] {
    for (const MetadataIndex& m : s_.metadata) {
      auto at = mcap::beginRecord(out, Op::MetadataIndex);
      mcap::putU64(out, m.offset);
      mcap::putU64(out, m.length);
      mcap::putString(out, m.name);
      mcap::endRecord(out, at);
    }
  });
  group(Op::ChunkIndex, [&] {
    for (const ChunkIndex& c : s_.chunk_indexes) putChunkIndex(out, c);
  });

  const std::uint64_t offsets_start = start + out.size();
  for (const Group& g : groups) {
    auto at = mcap::beginRecord(out, Op::SummaryOffset);
    mcap::putU8(out, static_cast<std::uint8_t>(g.op));
    mcap::putU64(out, g.start);
    mcap::putU64(out, g.length);
    mcap::endRecord(out, at);
  }
  // The Footer by hand: its summary CRC covers its own opcode, length and first two fields.
  mcap::putU8(out, static_cast<std::uint8_t>(Op::Footer));
  mcap::putU64(out, 8 + 8 + 4);
  mcap::putU64(out, start);
  mcap::putU64(out, offsets_start);
  mcap::putU32(out, crc32(out));
  out.append(mcap::kMagic);
  return out;
}

Result<void> McapWriter::close() {
  if (fd_ < 0) return s_.error.empty() ? Result<void>{} : Result<void>{Error{s_.error}};
  Result<void> r = flush();
  if (r) {
    std::string tail;
    auto at = mcap::beginRecord(tail, Op::DataEnd);
    mcap::putU32(tail, s_.data_crc);  // every byte before this record
    mcap::endRecord(tail, at);
    const std::uint64_t summary_start = s_.offset + tail.size();
    tail += summaryAndFooter(summary_start);
    r = writeOut(tail);
  }
  if (::close(std::exchange(fd_, -1)) != 0 && r) r = ioError("cannot close");
  return r;
}

}  // namespace keel::monitor
