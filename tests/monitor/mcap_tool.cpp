// keel's MCAP writer and reader from the command line, for mcap_peer_test.py, which holds them
// against PyPI's `mcap`, an independent implementation:
//   keel_mcap_tool write OUT N   N messages over three channels (two share a schema), a chunk
//                                per 7 messages so that a small file has several; message i is
//                                {"i": i, "channel": ID} at log time T0 + i ms; prints
//                                {"messages": N, "bytes": B}
//   keel_mcap_tool read IN       a JSON line per message ({"topic", "log_time", "payload"}), then
//                                one {"complete", "stopped_at", "channels", "metadata"}
// Exit status 1 with the error on stderr when the writer or the reader returns one.
#include <charconv>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "monitor/mcap_reader.hpp"
#include "monitor/mcap_writer.hpp"

namespace {

using keel::monitor::McapWriter;

constexpr std::uint64_t kT0 = 1'700'000'000'000'000'000ULL;  // ns since the Unix epoch
constexpr int kMessagesPerChunk = 7;

int fail(const std::string& message) {
  std::cerr << "keel_mcap_tool: " << message << "\n";
  return 1;
}

int write(const std::string& path, int n) {
  auto w = McapWriter::create(path, "keel mcap_tool", {{"profile", "robot.xml"}, {"keel_version", "0.1.0"}});
  if (!w) return fail(w.error().message);
  const char* fault = R"({"type":"object","properties":{"i":{"type":"integer"},"topic":{"type":"string"}}})";
  const std::uint16_t channels[] = {
      w->addChannel("/keel/faults", "keel.Fault", fault),
      w->addChannel("/keel/state", "keel.State", R"({"type":"object"})"),
      w->addChannel("/keel/ports/arm/pose", "keel.Fault", fault),
  };
  for (int i = 0; i < n; ++i) {
    const std::uint16_t c = channels[i % 3];
    w->write(c, kT0 + static_cast<std::uint64_t>(i) * 1'000'000, nlohmann::json{{"i", i}, {"channel", c}}.dump());
    if ((i + 1) % kMessagesPerChunk == 0) {
      if (auto r = w->flush(); !r) return fail(r.error().message);
    }
  }
  if (auto r = w->close(); !r) return fail(r.error().message);
  std::cout << nlohmann::json{{"messages", w->messagesWritten()}, {"bytes", w->bytesWritten()}}.dump() << "\n";
  return 0;
}

int read(const std::string& path) {
  auto file = keel::monitor::readMcap(path);
  if (!file) return fail(file.error().message);
  for (const auto& m : file->messages) {
    const auto* c = file->channel(m.channel);
    nlohmann::json line{{"topic", c ? c->topic : ""}, {"log_time", m.log_time}, {"payload", m.payload}};
    std::cout << line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
  }
  nlohmann::json end{{"complete", file->complete}, {"stopped_at", file->stopped_at}, {"library", file->library}};
  end["channels"] = nlohmann::json::array();
  for (const auto& c : file->channels) {
    end["channels"].push_back({{"id", c.id},
                               {"topic", c.topic},
                               {"message_encoding", c.message_encoding},
                               {"schema_name", c.schema_name},
                               {"schema_encoding", c.schema_encoding},
                               {"schema", c.schema}});
  }
  end["metadata"] = nlohmann::json::array();
  for (const auto& m : file->metadata) end["metadata"].push_back({{"name", m.name}, {"values", m.values}});
  std::cout << end.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
  return 0;
}

int run(int argc, char** argv) {
  const std::string usage = "usage: keel_mcap_tool write OUT N_MESSAGES | read IN";
  if (argc == 4 && std::string(argv[1]) == "write") {
    const std::string n_text = argv[3];
    int n = 0;
    const auto [end, ec] = std::from_chars(n_text.data(), n_text.data() + n_text.size(), n);
    if (ec != std::errc{} || end != n_text.data() + n_text.size() || n < 0) return fail(usage);
    return write(argv[2], n);
  }
  if (argc == 3 && std::string(argv[1]) == "read") return read(argv[2]);
  return fail(usage);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {  // std::bad_alloc, or a bug in the JSON output
    return fail(e.what());
  }
}
