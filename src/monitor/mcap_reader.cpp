#include "monitor/mcap_reader.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <system_error>

#include "monitor/crc32.hpp"
#include "monitor/mcap_bytes.hpp"

namespace keel::monitor {
namespace {

using mcap::ByteCursor;
using mcap::Op;

struct Record {
  Op op;
  std::size_t start;  // of its opcode, in the file
  std::string_view content;
};

struct SchemaRecord {
  std::string name, encoding, data;
};
struct ChannelRecord {
  std::uint16_t id, schema_id;
  std::string topic, encoding;
};

/// Schema, Channel and Message records found, in a chunk or in the whole file: a chunk's are
/// kept apart until the whole chunk has been read, so that a bad chunk gives none of them.
struct Found {
  std::map<std::uint16_t, SchemaRecord> schemas;
  std::vector<ChannelRecord> channels;
  std::vector<McapMessage> messages;

  /// Adds a Schema, Channel or Message record (others are not this layer's). False if malformed,
  /// and a Message is malformed unless a Channel record before it, anywhere in the file so far,
  /// defined its channel (`defined`: their ids; a Channel adds to it), as the spec requires. So
  /// every message returned has its channel. (A bad chunk stops the scan, so the ids it defined
  /// need not be taken back.)
  bool add(Op op, std::string_view content, std::set<std::uint16_t>& defined) {
    ByteCursor in(content);
    if (op == Op::Schema) {
      const std::uint16_t id = in.u16();
      SchemaRecord s{std::string(in.string()), std::string(in.string()), std::string(in.string())};
      if (in.ok()) schemas.try_emplace(id, std::move(s));
    } else if (op == Op::Channel) {
      ChannelRecord c{in.u16(), in.u16(), {}, {}};
      c.topic = in.string();
      c.encoding = in.string();
      (void)mcap::readStringMap(in);
      if (in.ok()) {
        defined.insert(c.id);
        channels.push_back(std::move(c));
      }
    } else if (op == Op::Message) {
      McapMessage m;
      m.channel = in.u16();
      (void)in.u32();  // sequence
      m.log_time = in.u64();
      (void)in.u64();  // publish_time
      m.payload = in.rest();
      if (in.ok() && defined.count(m.channel) == 0) return false;
      if (in.ok()) messages.push_back(std::move(m));
    }
    return in.ok();
  }

  void merge(Found&& chunk) {
    for (auto& [id, s] : chunk.schemas) schemas.try_emplace(id, std::move(s));
    for (auto& c : chunk.channels) channels.push_back(std::move(c));
    for (auto& m : chunk.messages) messages.push_back(std::move(m));
  }
};

/// One pass over the file's records, from after the magic to the footer or the first thing that
/// is wrong.
class Scanner {
 public:
  Scanner(std::string_view bytes, std::string_view name) : bytes_(bytes), name_(name) {}

  Result<McapFile> run() {
    std::size_t pos = mcap::kMagic.size();
    bool first = true;
    while (true) {
      const std::optional<Record> r = next(pos);
      if (!r) break;
      if (first && r->op != Op::Header) {
        stop(fmt::format("no Header at byte {}", pos));
        break;
      }
      first = false;
      auto more = take(*r);
      if (!more) return more.error();
      if (!*more) break;
      pos += mcap::kRecordPrefix + r->content.size();
    }
    return finish();
  }

 private:
  /// The record at `pos`, or nothing (and why) if the file ends in it or before it.
  std::optional<Record> next(std::size_t pos) {
    if (pos == bytes_.size()) {
      stop(fmt::format("the file ends at byte {}, before a footer", pos));
      return std::nullopt;
    }
    ByteCursor in(bytes_.substr(pos));
    const auto op = static_cast<Op>(in.u8());
    const std::uint64_t length = in.u64();
    if (!in.ok() || length > in.remaining()) {
      const char* what = in.ok() && op == Op::Chunk ? "a chunk" : "a record";
      stop(fmt::format("{} cut at byte {} (it starts at byte {})", what, bytes_.size(), pos));
      return std::nullopt;
    }
    return Record{op, pos, in.bytes(length)};
  }

  /// Takes in one record. False: the scan stops here (stopped_at says why).
  Result<bool> take(const Record& r) {
    switch (r.op) {
      case Op::Header: return header(r);
      case Op::Chunk: return chunk(r);
      case Op::Schema:
      case Op::Channel:
      case Op::Message:
        if (!found_.add(r.op, r.content, defined_)) return malformed(r, "record");
        return true;
      case Op::Metadata: return metadata(r);
      case Op::DataEnd: return dataEnd(r);
      case Op::Footer: footer(r); return false;  // what follows the footer is the closing magic, checked there
      default: return true;                      // indexes, statistics, attachments, unknown opcodes: not needed here
    }
  }

  bool header(const Record& r) {
    ByteCursor in(r.content);
    (void)in.string();  // profile
    file_.library = in.string();
    return in.ok() || malformed(r, "Header");
  }

  Result<bool> chunk(const Record& r) {
    ByteCursor in(r.content);
    (void)in.u64();  // message start and end times
    (void)in.u64();
    const std::uint64_t size = in.u64();
    const std::uint32_t crc = in.u32();
    const std::string_view compression = in.string();
    const std::string_view records = in.bytes(in.u64());
    if (!in.ok()) return malformed(r, "chunk");
    if (!compression.empty()) {
      return Error{fmt::format("{}: the chunk at byte {} is compressed with {}: keel reads uncompressed MCAP only",
                               name_, r.start, compression)};
    }
    if (size != records.size()) return malformed(r, "chunk");  // uncompressed: the sizes are one
    // 0: the writer computed no CRC (the spec allows it); keel's writer always does.
    if (crc != 0 && crc32(records) != crc) return stop(fmt::format("chunk CRC mismatch at byte {}", r.start));
    Found inside;
    ByteCursor chunk_in(records);
    while (!chunk_in.atEnd()) {
      const auto op = static_cast<Op>(chunk_in.u8());
      const std::string_view content = chunk_in.bytes(chunk_in.u64());
      if (!chunk_in.ok() || !inside.add(op, content, defined_)) return malformed(r, "chunk");
    }
    found_.merge(std::move(inside));
    return true;
  }

  bool metadata(const Record& r) {
    ByteCursor in(r.content);
    McapMetadata m{std::string(in.string()), mcap::readStringMap(in)};
    if (!in.ok()) return malformed(r, "Metadata");
    file_.metadata.push_back(std::move(m));
    return true;
  }

  bool dataEnd(const Record& r) {
    ByteCursor in(r.content);
    const std::uint32_t crc = in.u32();
    if (!in.ok()) return malformed(r, "Data End");
    data_end_ = true;
    data_crc_ok_ = crc == 0 || crc == crc32(bytes_.substr(0, r.start));
    if (!data_crc_ok_) stop(fmt::format("data section CRC mismatch (the Data End at byte {})", r.start));
    return true;  // on to the summary: it may define channels that have no messages
  }

  void footer(const Record& r) {
    ByteCursor in(r.content);
    const std::uint64_t summary_start = in.u64();
    (void)in.u64();  // summary_offset_start
    const std::uint32_t summary_crc = in.u32();
    if (!in.ok()) return (void)malformed(r, "Footer");
    const std::size_t end = r.start + mcap::kRecordPrefix + r.content.size();
    if (bytes_.substr(end) != mcap::kMagic) return (void)stop(fmt::format("no closing magic at byte {}", end));
    // The summary CRC covers the summary and the footer up to its own field.
    const std::size_t crc_end = end - 4;
    if (summary_crc != 0 && summary_start != 0 &&
        (summary_start > crc_end || crc32(bytes_.substr(summary_start, crc_end - summary_start)) != summary_crc)) {
      return (void)stop("summary CRC mismatch");
    }
    if (!data_end_) stop(fmt::format("no Data End record before the footer at byte {}", r.start));
    // Complete only if nothing stopped the scan: a Data End with a bad CRC stops it, though the
    // scan goes on into the summary (and a later Data End must not make up for it).
    file_.complete = data_crc_ok_ && file_.stopped_at.empty();
  }

  bool malformed(const Record& r, const char* what) {
    return stop(fmt::format("a malformed {} at byte {}", what, r.start));
  }

  /// Notes why the scan is stopping (the first reason); returns false, for `return stop(...)`.
  bool stop(std::string why) {
    if (file_.stopped_at.empty()) file_.stopped_at = std::move(why);
    return false;
  }

  McapFile finish() {
    for (const ChannelRecord& c : found_.channels) {
      if (file_.channel(c.id)) continue;  // the first definition; the summary repeats it
      McapChannel out{c.id, c.topic, c.encoding, c.schema_id, {}, {}, {}};
      if (auto s = found_.schemas.find(c.schema_id); s != found_.schemas.end()) {
        out.schema_name = s->second.name;
        out.schema_encoding = s->second.encoding;
        out.schema = s->second.data;
      }
      file_.channels.push_back(std::move(out));
    }
    file_.messages = std::move(found_.messages);
    return std::move(file_);
  }

  std::string_view bytes_;
  std::string_view name_;
  Found found_;
  std::set<std::uint16_t> defined_;  // the ids of the Channel records so far
  McapFile file_;
  bool data_end_ = false;
  bool data_crc_ok_ = false;
};

}  // namespace

const McapChannel* McapFile::channel(std::uint16_t id) const {
  for (const McapChannel& c : channels) {
    if (c.id == id) return &c;
  }
  return nullptr;
}

Result<McapFile> readMcapBytes(std::string_view bytes, const std::string& name) {
  if (bytes.size() < mcap::kMagic.size() && bytes == mcap::kMagic.substr(0, bytes.size())) {
    McapFile cut;  // the writer was killed while writing the magic: an MCAP file with nothing in it
    cut.stopped_at = fmt::format("the file ends at byte {}, inside the magic", bytes.size());
    return cut;
  }
  if (bytes.substr(0, mcap::kMagic.size()) != mcap::kMagic) return Error{name + ": not an MCAP file"};
  return Scanner(bytes, name).run();
}

Result<McapFile> readMcap(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open: " + std::generic_category().message(errno)};
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) return Error{path + ": cannot read: " + std::generic_category().message(errno)};
  return readMcapBytes(bytes, path);
}

}  // namespace keel::monitor
