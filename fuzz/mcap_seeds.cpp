// Writes the mcap_reader target's seeds (docs/fuzzing.md) with keel's own MCAP writer, so that
// they are the files `keel run --record` makes, whole and cut:
//   mcap_seeds DIR
//   DIR/whole.mcap                 3 channels (two share a schema), metadata, 12 messages in 3
//                                  chunks, Data End, summary, footer: what a finished run leaves
//   DIR/cut_mid_chunk.mcap         whole.mcap cut in the middle of its second chunk (a torn write)
//   DIR/killed_after_chunk.mcap    whole.mcap as a kill -9 after the last chunk leaves it: no
//                                  Data End, no summary, no footer
//   DIR/no_summary.mcap            a complete file with no summary section and no chunks (its
//                                  records in the data section itself), built record by record,
//                                  as other writers may make them
// Built on demand by the `fuzz` preset (cmake --build build-fuzz --target fuzz_mcap_seeds), not
// by keel_fuzz. The output is deterministic: fixed log times, no clock.
// Thread-safety: a program with one thread.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include "monitor/mcap_bytes.hpp"
#include "monitor/mcap_writer.hpp"

namespace {

namespace fs = std::filesystem;
namespace mcap = keel::monitor::mcap;
using keel::monitor::McapWriter;

constexpr std::uint64_t kT0 = 1'700'000'000'000'000'000ULL;  // ns since the Unix epoch
constexpr const char* kFaultSchema = R"({"type":"object","properties":{"component":{"type":"string"}}})";

bool save(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return static_cast<bool>(out);
}

std::string load(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool fail(const std::string& message) {
  std::cerr << "mcap_seeds: " << message << "\n";
  return false;
}

/// keel's writer: whole.mcap's bytes, and the file's size after each chunk was written.
bool writeWhole(const fs::path& path, std::string& bytes, std::vector<std::uint64_t>& chunk_ends) {
  auto w = McapWriter::create(path.string(), "keel mcap_seeds", {{"profile", "robot.xml"}, {"keel_version", "0.1.0"}});
  if (!w) return fail(w.error().message);
  const std::uint16_t channels[] = {
      w->addChannel("/keel/faults", "keel.Fault", kFaultSchema),
      w->addChannel("/keel/state", "keel.State", R"({"type":"object"})"),
      w->addChannel("/keel/ports/arm/pose", "keel.Fault", kFaultSchema),
  };
  for (int i = 0; i < 12; ++i) {
    const std::uint16_t c = channels[i % 3];
    w->write(c, kT0 + static_cast<std::uint64_t>(i) * 1'000'000,
             R"({"i":)" + std::to_string(i) + R"(,"component":"arm"})");
    if ((i + 1) % 4 == 0) {
      if (auto r = w->flush(); !r) return fail(r.error().message);
      chunk_ends.push_back(w->bytesWritten());
    }
  }
  if (auto r = w->close(); !r) return fail(r.error().message);
  bytes = load(path);
  return !bytes.empty();
}

/// Magic, Header, Schema, Channel, two Messages, Data End (CRC 0: not computed), Footer with no
/// summary (all 0), magic.
std::string noSummary() {
  std::string out(mcap::kMagic);
  auto at = mcap::beginRecord(out, mcap::Op::Header);
  mcap::putString(out, "");
  mcap::putString(out, "hand-built");
  mcap::endRecord(out, at);
  at = mcap::beginRecord(out, mcap::Op::Schema);
  mcap::putU16(out, 1);
  mcap::putString(out, "keel.Fault");
  mcap::putString(out, "jsonschema");
  mcap::putString(out, kFaultSchema);
  mcap::endRecord(out, at);
  at = mcap::beginRecord(out, mcap::Op::Channel);
  mcap::putU16(out, 1);
  mcap::putU16(out, 1);
  mcap::putString(out, "/keel/faults");
  mcap::putString(out, "json");
  mcap::putStringMap(out, {});
  mcap::endRecord(out, at);
  for (std::uint32_t i = 0; i < 2; ++i) {
    at = mcap::beginRecord(out, mcap::Op::Message);
    mcap::putU16(out, 1);
    mcap::putU32(out, i);
    mcap::putU64(out, kT0 + i);
    mcap::putU64(out, kT0 + i);
    out += R"({"component":"arm"})";
    mcap::endRecord(out, at);
  }
  at = mcap::beginRecord(out, mcap::Op::DataEnd);
  mcap::putU32(out, 0);
  mcap::endRecord(out, at);
  at = mcap::beginRecord(out, mcap::Op::Footer);
  mcap::putU64(out, 0);
  mcap::putU64(out, 0);
  mcap::putU32(out, 0);
  mcap::endRecord(out, at);
  out += mcap::kMagic;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: mcap_seeds DIR\n";
    return 2;
  }
  const fs::path dir = argv[1];
  std::error_code ec;
  fs::create_directories(dir, ec);
  std::string whole;
  std::vector<std::uint64_t> chunk_ends;
  if (!writeWhole(dir / "whole.mcap", whole, chunk_ends) || chunk_ends.size() != 3) return 1;
  const bool ok = save(dir / "cut_mid_chunk.mcap", whole.substr(0, (chunk_ends[0] + chunk_ends[1]) / 2)) &&
                  save(dir / "killed_after_chunk.mcap", whole.substr(0, chunk_ends[2])) &&
                  save(dir / "no_summary.mcap", noSummary());
  if (!ok) {
    std::cerr << "mcap_seeds: cannot write into " << dir << "\n";
    return 1;
  }
  std::cout << "mcap_seeds: 4 seeds in " << dir.string() << " (whole.mcap: " << whole.size() << " bytes)\n";
  return 0;
}
