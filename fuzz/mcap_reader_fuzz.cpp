// libFuzzer target for keel's tolerant MCAP reader (src/monitor/mcap_reader.hpp), which reads
// the recordings of `keel run --record` (and keel report will): the input bytes are a file
// that keel::monitor::readMcapBytes() reads whole, as readMcap() does once it has read it.
//
// Beyond "no crash, no hang, no leak, no UB", it checks what the reader promises:
//   - an error names the file, and says why;
//   - `complete` if and only if `stopped_at` is empty: a file that is not complete says why;
//   - every message's channel is one of the returned channels (the reader takes a Message only
//     after a Channel record of its id), and no channel id is returned twice;
//   - nothing returned is bigger than the input: messages' payloads and schemas are its bytes.
// Nothing is caught: an exception escaping readMcapBytes aborts the run, and is a finding.
// Built by the `fuzz` preset (fuzz/CMakeLists.txt); run by scripts/fuzz.sh mcap_reader SECONDS.
// Thread-safety: one input at a time, as libFuzzer calls it.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>

#include "monitor/mcap_reader.hpp"

namespace {

/// A failed check names itself on stderr and aborts: a finding, with its input kept.
void check(bool ok, int line, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, line, what);
  std::abort();
}
#define CHECK(condition) check((condition), __LINE__, #condition)

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* bytes, std::size_t size) {
  const std::string_view data(reinterpret_cast<const char*>(bytes), size);
  static const std::string kName = "fuzz.mcap";
  auto file = keel::monitor::readMcapBytes(data, kName);
  if (!file) {
    const std::string& why = file.error().message;
    CHECK(why.size() > kName.size() + 2 && why.compare(0, kName.size() + 2, kName + ": ") == 0);
    return 0;
  }
  CHECK(file->complete == file->stopped_at.empty());
  std::set<std::uint16_t> ids;
  for (const auto& c : file->channels) {
    CHECK(ids.insert(c.id).second);
    CHECK(c.topic.size() + c.schema.size() <= size);
  }
  std::size_t payloads = 0;
  for (const auto& m : file->messages) {
    CHECK(ids.count(m.channel) == 1 && file->channel(m.channel) != nullptr);
    payloads += m.payload.size();
  }
  CHECK(payloads <= size);
  return 0;
}
