#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <random>

#include "monitor/crc32.hpp"
#include "monitor/mcap_bytes.hpp"
#include "monitor/mcap_reader.hpp"
#include "monitor/mcap_writer.hpp"

namespace keel::monitor {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFaultSchema = R"({"type":"object","properties":{"event":{"type":"string"}}})";
constexpr const char* kStateSchema = R"({"type":"object","properties":{"components":{"type":"array"}}})";
constexpr std::uint64_t kT0 = 1'700'000'000'000'000'000ULL;  // a log time in 2023, ns

std::uint64_t steadyNowNs() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
          .count());
}

std::string payload(int i) { return R"({"event":"e)" + std::to_string(i) + R"("})"; }

std::string contents(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The u64 at `at` in `bytes`, read here rather than with the code under test.
std::uint64_t u64At(const std::string& bytes, std::size_t at) {
  std::uint64_t v = 0;
  for (std::size_t i = 8; i-- > 0;) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
  return v;
}

class Mcap : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("keel_mcap_" + std::to_string(::getpid()) + "_" + test->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  McapWriter writer(const std::string& name) {
    auto w = McapWriter::create((dir_ / name).string(), "keel test", {{"profile", "robot.xml"}, {"start", "0"}});
    EXPECT_TRUE(w) << w.error().message;
    return std::move(w).value();
  }

  /// Two chunks of 3 and 2 messages on two channels; where each Chunk record starts and ends.
  struct TwoChunks {
    std::string bytes;
    std::uint64_t chunk_start[2];
    std::uint64_t chunk_end[2];
  };
  TwoChunks twoChunks() {
    auto w = writer("two.mcap");
    const auto faults = w.addChannel("/keel/faults", "keel.Fault", kFaultSchema);
    const auto state = w.addChannel("/keel/state", "keel.State", kStateSchema);
    TwoChunks out{};
    for (int c = 0, i = 0; c < 2; ++c) {
      out.chunk_start[c] = w.bytesWritten();
      for (int n = 0; n < 3 - c; ++n, ++i) w.write(i % 2 ? state : faults, kT0 + i, payload(i));
      EXPECT_TRUE(w.flush());
    }
    EXPECT_TRUE(w.close());
    out.bytes = contents(dir_ / "two.mcap");
    for (int c = 0; c < 2; ++c) {
      EXPECT_EQ(out.bytes[out.chunk_start[c]], '\x06') << "a Chunk record";
      out.chunk_end[c] = out.chunk_start[c] + mcap::kRecordPrefix + u64At(out.bytes, out.chunk_start[c] + 1);
    }
    return out;
  }

  fs::path dir_;
};

TEST(Crc32, MatchesTheKnownVectorsAndContinues) {
  EXPECT_EQ(crc32(""), 0U);
  EXPECT_EQ(crc32("123456789"), 0xCBF43926U);
  EXPECT_EQ(crc32("The quick brown fox jumps over the lazy dog"), 0x414FA339U);
  EXPECT_EQ(crc32("56789", crc32("1234")), 0xCBF43926U);
}

TEST_F(Mcap, RoundTripsSeveralChannelsOverSeveralChunks) {
  auto w = writer("round.mcap");
  const auto faults = w.addChannel("/keel/faults", "keel.Fault", kFaultSchema);
  const auto state = w.addChannel("/keel/state", "keel.State", kStateSchema);
  for (int i = 0; i < 10; ++i) w.write(i % 2 ? state : faults, kT0 + i, payload(i));
  ASSERT_TRUE(w.flush());
  const auto port = w.addChannel("/keel/ports/arm/pose", "keel.Fault", kFaultSchema);  // added mid-file
  for (int i = 10; i < 25; ++i) {
    w.write(i % 3 == 0 ? port : faults, kT0 + i, payload(i));
    if (i == 17) {
      ASSERT_TRUE(w.flush());
    }
  }
  ASSERT_TRUE(w.close());
  EXPECT_EQ(w.messagesWritten(), 25U);
  EXPECT_EQ(w.bytesWritten(), fs::file_size(dir_ / "round.mcap"));

  auto file = readMcap((dir_ / "round.mcap").string());
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_TRUE(file->complete) << file->stopped_at;
  EXPECT_EQ(file->stopped_at, "");
  EXPECT_EQ(file->library, "keel test");
  ASSERT_EQ(file->metadata.size(), 1U);
  EXPECT_EQ(file->metadata[0].name, "keel");
  EXPECT_EQ(file->metadata[0].values.at("profile"), "robot.xml");
  ASSERT_EQ(file->channels.size(), 3U);
  EXPECT_EQ(file->channels[0].topic, "/keel/faults");
  EXPECT_EQ(file->channels[0].message_encoding, "json");
  EXPECT_EQ(file->channels[0].schema_encoding, "jsonschema");
  EXPECT_EQ(file->channels[1].schema, kStateSchema);
  EXPECT_EQ(file->channels[2].topic, "/keel/ports/arm/pose");
  ASSERT_EQ(file->messages.size(), 25U);
  for (int i = 0; i < 25; ++i) {
    const auto& m = file->messages[static_cast<std::size_t>(i)];
    EXPECT_EQ(m.log_time, kT0 + static_cast<std::uint64_t>(i));
    EXPECT_EQ(m.payload, payload(i));
    EXPECT_EQ(m.channel, i < 10 ? (i % 2 ? state : faults) : (i % 3 == 0 ? port : faults));
  }
}

TEST_F(Mcap, OneSchemaPerDistinctNameAndText) {
  auto w = writer("schemas.mcap");
  EXPECT_EQ(w.addChannel("/a", "keel.Fault", kFaultSchema), 1);  // ids from 1
  EXPECT_EQ(w.addChannel("/b", "keel.Fault", kFaultSchema), 2);
  EXPECT_EQ(w.addChannel("/c", "keel.Fault", kStateSchema), 3);
  EXPECT_EQ(w.addChannel("/d", "keel.State", kFaultSchema), 4);
  for (std::uint16_t c = 1; c <= 4; ++c) w.write(c, kT0 + c, "{}");
  ASSERT_TRUE(w.close());

  auto file = readMcap((dir_ / "schemas.mcap").string());
  ASSERT_TRUE(file) << file.error().message;
  ASSERT_EQ(file->channels.size(), 4U);
  EXPECT_EQ(file->channels[0].schema_id, 1);
  EXPECT_EQ(file->channels[1].schema_id, 1);
  EXPECT_EQ(file->channels[2].schema_id, 2);
  EXPECT_EQ(file->channels[3].schema_id, 3);
  EXPECT_EQ(file->channels[3].schema_name, "keel.State");
  EXPECT_EQ(file->channels[3].schema, kFaultSchema);
}

TEST_F(Mcap, AFileCutAtAnyByteGivesExactlyTheWholeChunksBeforeTheCut) {
  const TwoChunks two = twoChunks();
  for (std::size_t cut = 0; cut <= two.bytes.size(); ++cut) {
    auto file = readMcapBytes(std::string_view(two.bytes).substr(0, cut), "cut.mcap");
    ASSERT_TRUE(file) << "cut at " << cut << ": " << file.error().message;
    const std::size_t whole = (cut >= two.chunk_end[0] ? 3U : 0U) + (cut >= two.chunk_end[1] ? 2U : 0U);
    ASSERT_EQ(file->messages.size(), whole) << "cut at " << cut << ": " << file->stopped_at;
    for (std::size_t i = 0; i < whole; ++i) EXPECT_EQ(file->messages[i].payload, payload(static_cast<int>(i)));
    EXPECT_EQ(file->complete, cut == two.bytes.size()) << "cut at " << cut;
    EXPECT_EQ(file->stopped_at.empty(), cut == two.bytes.size()) << "cut at " << cut << ": " << file->stopped_at;
  }
}

TEST_F(Mcap, SaysWhereTheFileWasCut) {
  const TwoChunks two = twoChunks();
  auto file = readMcapBytes(std::string_view(two.bytes).substr(0, two.chunk_end[1] - 5), "cut.mcap");
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_EQ(file->stopped_at, "a chunk cut at byte " + std::to_string(two.chunk_end[1] - 5) + " (it starts at byte " +
                                  std::to_string(two.chunk_start[1]) + ")");
}

TEST_F(Mcap, AFlippedByteInAChunkLosesThatChunkOnly) {
  const TwoChunks two = twoChunks();
  for (int c = 0; c < 2; ++c) {
    std::string bytes = two.bytes;
    bytes[two.chunk_end[c] - 3] ^= 0x20;  // inside the last message's payload
    auto file = readMcapBytes(bytes, "flipped.mcap");
    ASSERT_TRUE(file) << file.error().message;
    EXPECT_EQ(file->messages.size(), c == 0 ? 0U : 3U);
    EXPECT_FALSE(file->complete);
    EXPECT_NE(file->stopped_at.find("chunk CRC mismatch at byte"), std::string::npos) << file->stopped_at;
  }
}

TEST_F(Mcap, AFlippedByteOutsideTheChunksFailsTheDataSectionCrc) {
  std::string bytes = twoChunks().bytes;
  const auto at = bytes.find("robot.xml");  // in the Metadata record, before the chunks
  ASSERT_NE(at, std::string::npos);
  bytes[at] = 'R';
  auto file = readMcapBytes(bytes, "flipped.mcap");
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_EQ(file->messages.size(), 5U);
  EXPECT_FALSE(file->complete);
  EXPECT_NE(file->stopped_at.find("data section CRC mismatch"), std::string::npos) << file->stopped_at;
}

TEST_F(Mcap, FlushIfDueWritesAChunkOnceItIsASecondOld) {
  auto w = writer("due.mcap");
  const auto c = w.addChannel("/keel/faults", "keel.Fault", kFaultSchema);
  const std::uint64_t before = steadyNowNs();
  ASSERT_TRUE(w.flushIfDue(before + 5 * McapWriter::kChunkAgeNs));  // no messages: nothing to write
  const std::uint64_t header_bytes = w.bytesWritten();
  w.write(c, kT0, payload(0));
  const std::uint64_t after = steadyNowNs();
  ASSERT_TRUE(w.flushIfDue(before + McapWriter::kChunkAgeNs - 1));
  EXPECT_EQ(w.bytesWritten(), header_bytes);
  EXPECT_EQ(w.messagesWritten(), 0U);
  ASSERT_TRUE(w.flushIfDue(after + McapWriter::kChunkAgeNs));
  EXPECT_GT(w.bytesWritten(), header_bytes);
  EXPECT_EQ(w.messagesWritten(), 1U);
}

TEST_F(Mcap, FlushIfDueWritesAChunkOnceItIsAMebibyte) {
  auto w = writer("big.mcap");
  const auto c = w.addChannel("/keel/faults", "keel.Fault", kFaultSchema);
  const std::string big(std::size_t{64} * 1024, 'x');
  const std::uint64_t now = steadyNowNs();                // before the first message: never a second old
  for (int i = 0; i < 15; ++i) w.write(c, kT0 + i, big);  // 15 × (64 KiB + 31 B) < 1 MiB
  ASSERT_TRUE(w.flushIfDue(now));
  EXPECT_EQ(w.messagesWritten(), 0U);
  w.write(c, kT0 + 15, big);
  ASSERT_TRUE(w.flushIfDue(now));
  EXPECT_EQ(w.messagesWritten(), 16U);
}

TEST_F(Mcap, AFileWithNoMessagesHasNoChunkAndIsComplete) {
  auto w = writer("empty.mcap");
  (void)w.addChannel("/keel/faults", "keel.Fault", kFaultSchema);
  const std::uint64_t header_bytes = w.bytesWritten();
  ASSERT_TRUE(w.flush());
  EXPECT_EQ(w.bytesWritten(), header_bytes);
  ASSERT_TRUE(w.close());
  const std::string bytes = contents(dir_ / "empty.mcap");
  EXPECT_EQ(bytes.find(std::string(1, '\x06') + std::string(1, '\0')), std::string::npos) << "no Chunk record";
  auto file = readMcapBytes(bytes, "empty.mcap");
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_TRUE(file->complete) << file->stopped_at;
  EXPECT_TRUE(file->messages.empty());
  ASSERT_EQ(file->channels.size(), 1U);  // from the summary
  EXPECT_EQ(file->channels[0].topic, "/keel/faults");
}

TEST_F(Mcap, TheDestructorAndAMoveCloseTheFileOnce) {
  {
    std::optional<McapWriter> w(writer("moved.mcap"));
    const auto c = w->addChannel("/keel/faults", "keel.Fault", kFaultSchema);
    w->write(c, kT0, payload(0));
    McapWriter moved = std::move(*w);
    w.reset();  // the moved-from writer goes first: it must leave the file alone
    moved.write(c, kT0 + 1, payload(1));
  }  // no close(): the destructor's
  auto file = readMcap((dir_ / "moved.mcap").string());
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_TRUE(file->complete) << file->stopped_at;
  EXPECT_EQ(file->messages.size(), 2U);
}

TEST_F(Mcap, CreateNamesAPathItCannotWrite) {
  auto w = McapWriter::create((dir_ / "no" / "such" / "dir.mcap").string(), "keel", {});
  ASSERT_FALSE(w);
  EXPECT_EQ(w.error().message,
            (dir_ / "no" / "such" / "dir.mcap").string() + ": cannot create: No such file or directory");
}

TEST_F(Mcap, ReadingAFileThatIsNotMcapIsAnError) {
  auto file = readMcapBytes("{\"t_ns\": 1}\n", "log.jsonl");
  ASSERT_FALSE(file);
  EXPECT_EQ(file.error().message, "log.jsonl: not an MCAP file");
  auto missing = readMcap((dir_ / "missing.mcap").string());
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("missing.mcap: cannot open"), std::string::npos) << missing.error().message;
}

TEST_F(Mcap, ACompressedChunkIsAnErrorNamingItsCompression) {
  std::string bytes(mcap::kMagic);
  auto at = mcap::beginRecord(bytes, mcap::Op::Header);
  mcap::putString(bytes, "");
  mcap::putString(bytes, "other");
  mcap::endRecord(bytes, at);
  const std::size_t chunk_at = bytes.size();
  at = mcap::beginRecord(bytes, mcap::Op::Chunk);
  mcap::putU64(bytes, kT0);
  mcap::putU64(bytes, kT0);
  mcap::putU64(bytes, 100);  // uncompressed: more than the 4 bytes compressed
  mcap::putU32(bytes, 0x12345678);
  mcap::putString(bytes, "zstd");
  mcap::putU64(bytes, 4);
  bytes += "\x28\xb5\x2f\xfd";
  mcap::endRecord(bytes, at);
  auto file = readMcapBytes(bytes, "z.mcap");
  ASSERT_FALSE(file);
  EXPECT_EQ(file.error().message, "z.mcap: the chunk at byte " + std::to_string(chunk_at) +
                                      " is compressed with zstd: keel reads uncompressed MCAP only");
}

/// A file built record by record, for what keel's writer never writes.
struct Records {
  std::string bytes{mcap::kMagic};

  std::size_t add(mcap::Op op, const std::string& content) {
    const std::size_t at = bytes.size();
    const auto length = mcap::beginRecord(bytes, op);
    bytes += content;
    mcap::endRecord(bytes, length);
    return at;
  }
  static std::string header() {
    std::string c;
    mcap::putString(c, "");
    mcap::putString(c, "hand-built");
    return c;
  }
  static std::string channel(std::uint16_t id) {
    std::string c;
    mcap::putU16(c, id);
    mcap::putU16(c, 0);
    mcap::putString(c, "/keel/faults");
    mcap::putString(c, "json");
    mcap::putStringMap(c, {});
    return c;
  }
  static std::string message(std::uint16_t channel) {
    std::string c;
    mcap::putU16(c, channel);
    mcap::putU32(c, 0);
    mcap::putU64(c, kT0);
    mcap::putU64(c, kT0);
    return c + payload(channel);
  }
  static std::string u32(std::uint32_t v) {
    std::string c;
    mcap::putU32(c, v);
    return c;
  }
  /// A Footer with no summary, and the closing magic.
  void end() {
    add(mcap::Op::Footer, std::string(20, '\0'));
    bytes += mcap::kMagic;
  }
};

// Found by the mcap_reader fuzz target (fuzz/corpus/mcap_reader/regression_message_before_its_channel):
// a message whose channel was never defined came back, and channel() of it was null.
TEST(McapReader, AMessageBeforeAChannelOfItsIdIsMalformed) {
  Records f;
  f.add(mcap::Op::Header, Records::header());
  f.add(mcap::Op::Channel, Records::channel(1));
  f.add(mcap::Op::Message, Records::message(1));
  const std::size_t bad = f.add(mcap::Op::Message, Records::message(2));
  f.add(mcap::Op::Channel, Records::channel(2));  // too late
  f.add(mcap::Op::DataEnd, Records::u32(0));
  f.end();
  auto file = readMcapBytes(f.bytes, "early.mcap");
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_FALSE(file->complete);
  EXPECT_EQ(file->stopped_at, "a malformed record at byte " + std::to_string(bad));
  ASSERT_EQ(file->messages.size(), 1U);
  EXPECT_EQ(file->messages[0].channel, 1U);
  ASSERT_EQ(file->channels.size(), 1U);

  // In a chunk, likewise: the chunk is malformed and gives none of its messages.
  Records chunked;
  chunked.add(mcap::Op::Header, Records::header());
  std::string records;
  for (const auto& [op, content] :
       {std::pair{mcap::Op::Channel, Records::channel(1)}, std::pair{mcap::Op::Message, Records::message(1)},
        std::pair{mcap::Op::Message, Records::message(3)}}) {
    const auto at = mcap::beginRecord(records, op);
    records += content;
    mcap::endRecord(records, at);
  }
  std::string chunk;
  mcap::putU64(chunk, kT0);
  mcap::putU64(chunk, kT0);
  mcap::putU64(chunk, records.size());
  mcap::putU32(chunk, crc32(records));
  mcap::putString(chunk, "");
  mcap::putU64(chunk, records.size());
  const std::size_t chunk_at = chunked.add(mcap::Op::Chunk, chunk + records);
  auto in_chunk = readMcapBytes(chunked.bytes, "early.mcap");
  ASSERT_TRUE(in_chunk) << in_chunk.error().message;
  EXPECT_EQ(in_chunk->stopped_at, "a malformed chunk at byte " + std::to_string(chunk_at));
  EXPECT_TRUE(in_chunk->messages.empty());
}

TEST(McapReader, AFooterWithoutADataEndIsNotCompleteAndSaysWhy) {
  Records f;
  f.add(mcap::Op::Header, Records::header());
  const std::size_t footer = f.bytes.size();
  f.end();
  auto file = readMcapBytes(f.bytes, "no_data_end.mcap");
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_FALSE(file->complete);
  EXPECT_EQ(file->stopped_at, "no Data End record before the footer at byte " + std::to_string(footer));
}

TEST(McapReader, ASecondDataEndDoesNotMakeUpForABadCrc) {
  Records f;
  f.add(mcap::Op::Header, Records::header());
  const std::size_t bad = f.add(mcap::Op::DataEnd, Records::u32(0xDEADBEEF));
  f.add(mcap::Op::DataEnd, Records::u32(0));  // "not computed"
  f.end();
  auto file = readMcapBytes(f.bytes, "two_ends.mcap");
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_FALSE(file->complete);
  EXPECT_EQ(file->stopped_at, "data section CRC mismatch (the Data End at byte " + std::to_string(bad) + ")");
}

TEST_F(Mcap, GarbageNeverCrashesTheReader) {
  const std::string good = twoChunks().bytes;
  std::mt19937 random(16);  // NOLINT(cert-msc51-cpp): a fixed seed, so that a failure reproduces
  std::uniform_int_distribution<std::size_t> where(8, good.size() - 1);
  std::uniform_int_distribution<int> value(0, 255);
  for (int round = 0; round < 3000; ++round) {
    std::string bytes = good;
    for (int k = 0; k <= round % 4; ++k) bytes[where(random)] = static_cast<char>(value(random));
    bytes.resize(where(random));
    auto file = readMcapBytes(bytes, "garbage.mcap");
    if (file) {
      EXPECT_LE(file->messages.size(), 5U);
    }
  }
}

}  // namespace
}  // namespace keel::monitor
