// libFuzzer target for the live monitor's reader of Foxglove WebSocket client messages
// (src/monitor/foxglove.hpp): every text or binary frame a client sends goes through
// keel::monitor::foxglove::parseClient(), and so does every input here.
//
// Input layout: the first byte picks the frame's kind, the rest is the frame.
//   first byte odd  (e.g. '1'): a binary frame (a service call is opcode 0x02, then the ids)
//   first byte even (e.g. '0'): a text frame (JSON: subscribe, unsubscribe, getParameters, ...)
// so a seed reads `0{"op":"subscribe",...}` or `1\x02...`.
//
// Beyond "no crash, no hang, no leak, no UB", it checks what must hold of any answer:
//   - a text frame never gives a ServiceCall, a binary one never a Subscribe or Unsubscribe;
//   - a ServiceCall came from opcode 0x02, its ids are the header's little-endian words, and
//     its encoding and payload are the input's bytes after the 13-byte header, in order: their
//     sizes add up to the frame's size minus 13;
//   - every Subscribe and Unsubscribe id is written, in decimal, in the input, and each
//     subscription is an object of its own (a `{` of the input);
//   - an Unsupported text op is one of the protocol's ops keel ignores; a binary one is 0x01;
//   - an Invalid says why, and the status keel answers with is JSON that parses.
// Nothing is caught: an exception escaping parseClient aborts the run, and is a finding.
// Built by the `fuzz` preset (fuzz/CMakeLists.txt); run by scripts/fuzz.sh monitor_client SECONDS.
// Thread-safety: one input at a time, as libFuzzer calls it.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <variant>

#include "monitor/foxglove.hpp"

namespace {

namespace fox = keel::monitor::foxglove;

/// A failed check names itself on stderr and aborts: a finding, with its input kept.
void check(bool ok, int line, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, line, what);
  std::abort();
}
#define CHECK(condition) check((condition), __LINE__, #condition)

std::uint32_t le32(std::string_view s, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 4; i-- > 0;) v = (v << 8) | static_cast<unsigned char>(s[at + i]);
  return v;
}

bool written(std::string_view data, std::uint32_t id) {
  return data.find(std::to_string(id)) != std::string_view::npos;
}

void checkText(std::string_view data, const fox::ClientMessage& m) {
  CHECK(!std::holds_alternative<fox::ServiceCall>(m));
  if (const auto* s = std::get_if<fox::Subscribe>(&m)) {
    // The message is an object, and so is each subscription: one `{` each, at least.
    CHECK(s->subscriptions.size() < static_cast<std::size_t>(std::count(data.begin(), data.end(), '{')));
    for (const auto& one : s->subscriptions) CHECK(written(data, one.id) && written(data, one.channel_id));
  } else if (const auto* u = std::get_if<fox::Unsubscribe>(&m)) {
    for (auto id : u->subscription_ids) CHECK(written(data, id));
  } else if (const auto* un = std::get_if<fox::Unsupported>(&m)) {
    CHECK(std::find(std::begin(fox::kUnsupportedOps), std::end(fox::kUnsupportedOps), un->op) !=
          std::end(fox::kUnsupportedOps));
  }
}

void checkBinary(std::string_view data, const fox::ClientMessage& m) {
  CHECK(!std::holds_alternative<fox::Subscribe>(m) && !std::holds_alternative<fox::Unsubscribe>(m));
  if (const auto* c = std::get_if<fox::ServiceCall>(&m)) {
    CHECK(data.size() >= 13 && data[0] == '\x02');
    CHECK(c->service_id == le32(data, 1) && c->call_id == le32(data, 5) && c->encoding.size() == le32(data, 9));
    CHECK(c->encoding.size() + c->payload.size() == data.size() - 13);
    CHECK(data.substr(13, c->encoding.size()) == c->encoding && data.substr(13 + c->encoding.size()) == c->payload);
  } else if (std::holds_alternative<fox::Unsupported>(m)) {
    CHECK(!data.empty() && data[0] == '\x01');
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* bytes, std::size_t size) {
  if (size == 0) return -1;  // no kind: not worth keeping
  const bool binary = (bytes[0] & 1U) != 0;
  const std::string_view data(reinterpret_cast<const char*>(bytes) + 1, size - 1);
  const fox::ClientMessage m = fox::parseClient(data, binary);
  if (binary) {
    checkBinary(data, m);
  } else {
    checkText(data, m);
  }
  if (const auto* bad = std::get_if<fox::Invalid>(&m)) {
    CHECK(!bad->why.empty());
    // What the session answers (client_session.cpp): the reason may quote the input's bytes.
    const std::string answer = fox::status(fox::StatusLevel::Error, "keel cannot read that message: " + bad->why,
                                           "keel.bad");
    CHECK(!nlohmann::json::parse(answer, nullptr, false).is_discarded());
  }
  return 0;
}
