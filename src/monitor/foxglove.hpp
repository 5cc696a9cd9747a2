// The Foxglove WebSocket protocol v1 (subprotocol foxglove.websocket.v1), as keel's monitor
// speaks it (docs/monitor.md): the server's messages encoded, the client's parsed. Pure
// functions over bytes, no sockets, so every client message can be fuzzed
// (fuzz/monitor_client_fuzz.cpp). Byte layouts are little-endian, as the protocol has them.
// Thread-safety: plain functions.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace keel::monitor::foxglove {

inline constexpr std::string_view kSubprotocol = "foxglove.websocket.v1";

/// A topic the server offers: JSON messages described by a JSON schema.
struct Channel {
  std::uint32_t id = 0;
  std::string topic;
  std::string schema_name;
  std::string schema;  // JSON schema text
};

/// A service a client may call with a JSON request (keel's controls).
struct Service {
  std::uint32_t id = 0;
  std::string name;
  std::string type;
  std::string request_schema;
  std::string response_schema;
};

enum class StatusLevel : int { Info = 0, Warning = 1, Error = 2 };

// Server → client, text (JSON).
std::string serverInfo(std::string_view name, const std::map<std::string, std::string>& metadata,
                       std::string_view session_id);
std::string advertise(const std::vector<Channel>& channels);
std::string unadvertise(const std::vector<std::uint32_t>& channel_ids);
std::string advertiseServices(const std::vector<Service>& services);
std::string status(StatusLevel level, std::string_view message, std::string_view id);
std::string serviceCallFailure(std::uint32_t service_id, std::uint32_t call_id, std::string_view message);

// Server → client, binary.
inline constexpr std::size_t kMessageDataHeader = 1 + 4 + 8;
/// The 13-byte header of a Message Data (0x01) whose payload follows it.
std::string messageDataHeader(std::uint32_t subscription_id, std::uint64_t timestamp_ns);
/// A Service Call Response (0x03) with a JSON payload.
std::string serviceCallResponse(std::uint32_t service_id, std::uint32_t call_id, std::string_view json);

// Client → server.
struct Subscribe {
  struct One {
    std::uint32_t id;
    std::uint32_t channel_id;
  };
  std::vector<One> subscriptions;
};
struct Unsubscribe {
  std::vector<std::uint32_t> subscription_ids;
};
struct ServiceCall {
  std::uint32_t service_id = 0;
  std::uint32_t call_id = 0;
  std::string encoding;
  std::string payload;
};
/// The protocol's client ops for capabilities keel does not announce: ignored, as the protocol
/// has it.
inline constexpr std::string_view kUnsupportedOps[] = {"advertise",
                                                       "unadvertise",
                                                       "getParameters",
                                                       "setParameters",
                                                       "subscribeParameterUpdates",
                                                       "unsubscribeParameterUpdates",
                                                       "subscribeConnectionGraph",
                                                       "unsubscribeConnectionGraph",
                                                       "fetchAsset"};

/// A well-formed message for a capability keel does not offer (one of kUnsupportedOps, or
/// client message data): ignored.
struct Unsupported {
  std::string op;
};
/// A message keel cannot read: why, for the status it answers with.
struct Invalid {
  std::string why;
};
using ClientMessage = std::variant<Subscribe, Unsubscribe, ServiceCall, Unsupported, Invalid>;

/// Reads one client message: a text frame (`binary` false) is JSON, a binary one starts with
/// its opcode. Never throws; anything malformed is Invalid, saying what.
ClientMessage parseClient(std::string_view data, bool binary);

}  // namespace keel::monitor::foxglove
