#include "monitor/foxglove.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

namespace keel::monitor::foxglove {
namespace {

using nlohmann::json;

std::string dump(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

void putLe(std::string& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out += static_cast<char>((v >> (8 * i)) & 0xFF);
}

std::uint32_t getU32(std::string_view s, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(s[at + static_cast<std::size_t>(i)]);
  return v;
}

json schemaPair(std::string_view schema_name, std::string_view schema) {
  return {{"encoding", "json"}, {"schemaName", schema_name}, {"schemaEncoding", "jsonschema"}, {"schema", schema}};
}

/// An unsigned 32-bit id member, or why not.
bool readId(const json& object, const char* key, std::uint32_t& out, std::string& why) {
  auto it = object.find(key);
  if (it == object.end() || !it->is_number_unsigned() || it->get<std::uint64_t>() > UINT32_MAX) {
    why = fmt::format("'{}' must be an unsigned 32-bit integer", key);
    return false;
  }
  out = it->get<std::uint32_t>();
  return true;
}

ClientMessage parseSubscribe(const json& m) {
  auto subs = m.find("subscriptions");
  if (subs == m.end() || !subs->is_array()) return Invalid{"subscribe: 'subscriptions' must be an array"};
  Subscribe out;
  std::string why;
  for (const auto& s : *subs) {
    Subscribe::One one{};
    if (!s.is_object()) return Invalid{"subscribe: each subscription must be an object"};
    if (!readId(s, "id", one.id, why) || !readId(s, "channelId", one.channel_id, why))
      return Invalid{"subscribe: " + why};
    out.subscriptions.push_back(one);
  }
  return out;
}

ClientMessage parseUnsubscribe(const json& m) {
  auto ids = m.find("subscriptionIds");
  if (ids == m.end() || !ids->is_array()) return Invalid{"unsubscribe: 'subscriptionIds' must be an array"};
  Unsubscribe out;
  for (const auto& id : *ids) {
    if (!id.is_number_unsigned() || id.get<std::uint64_t>() > UINT32_MAX)
      return Invalid{"unsubscribe: each subscription id must be an unsigned 32-bit integer"};
    out.subscription_ids.push_back(id.get<std::uint32_t>());
  }
  return out;
}

ClientMessage parseText(std::string_view data) {
  const json m = json::parse(data, nullptr, false);
  if (m.is_discarded()) return Invalid{"not JSON"};
  if (!m.is_object()) return Invalid{"a message must be a JSON object"};
  auto op = m.find("op");
  if (op == m.end() || !op->is_string()) return Invalid{"a message must have a string 'op'"};
  const auto& name = op->get_ref<const std::string&>();
  if (name == "subscribe") return parseSubscribe(m);
  if (name == "unsubscribe") return parseUnsubscribe(m);
  static constexpr std::string_view kKnown[] = {"advertise",
                                                "unadvertise",
                                                "getParameters",
                                                "setParameters",
                                                "subscribeParameterUpdates",
                                                "unsubscribeParameterUpdates",
                                                "subscribeConnectionGraph",
                                                "unsubscribeConnectionGraph",
                                                "fetchAsset"};
  for (auto known : kKnown)
    if (name == known) return Unsupported{name};
  return Invalid{fmt::format("unknown op '{}'", name.substr(0, 64))};
}

ClientMessage parseBinary(std::string_view data) {
  if (data.empty()) return Invalid{"an empty binary message"};
  const auto opcode = static_cast<unsigned char>(data[0]);
  if (opcode == 0x01) return Unsupported{"client message data (keel offers no clientPublish)"};
  if (opcode != 0x02) return Invalid{fmt::format("unknown binary opcode 0x{:02x}", opcode)};
  // 0x02 Service Call Request: u32 service id, u32 call id, u32 encoding length, encoding, payload.
  if (data.size() < 13) return Invalid{"a service call shorter than its 13-byte header"};
  ServiceCall call;
  call.service_id = getU32(data, 1);
  call.call_id = getU32(data, 5);
  const std::uint32_t encoding_length = getU32(data, 9);
  if (encoding_length > data.size() - 13) return Invalid{"a service call whose encoding runs past its end"};
  call.encoding = std::string(data.substr(13, encoding_length));
  call.payload = std::string(data.substr(13 + encoding_length));
  return call;
}

}  // namespace

std::string serverInfo(std::string_view name, const std::map<std::string, std::string>& metadata,
                       std::string_view session_id) {
  return dump({{"op", "serverInfo"},
               {"name", name},
               {"capabilities", {"services"}},
               {"supportedEncodings", {"json"}},
               {"metadata", metadata},
               {"sessionId", session_id}});
}

std::string advertise(const std::vector<Channel>& channels) {
  json list = json::array();
  for (const auto& c : channels) {
    json one = schemaPair(c.schema_name, c.schema);
    one["id"] = c.id;
    one["topic"] = c.topic;
    list.push_back(std::move(one));
  }
  return dump({{"op", "advertise"}, {"channels", std::move(list)}});
}

std::string unadvertise(const std::vector<std::uint32_t>& channel_ids) {
  return dump({{"op", "unadvertise"}, {"channelIds", channel_ids}});
}

std::string advertiseServices(const std::vector<Service>& services) {
  json list = json::array();
  for (const auto& s : services)
    list.push_back({{"id", s.id},
                    {"name", s.name},
                    {"type", s.type},
                    {"request", schemaPair(s.type + "_Request", s.request_schema)},
                    {"response", schemaPair(s.type + "_Response", s.response_schema)}});
  return dump({{"op", "advertiseServices"}, {"services", std::move(list)}});
}

std::string status(StatusLevel level, std::string_view message, std::string_view id) {
  return dump({{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}, {"id", id}});
}

std::string serviceCallFailure(std::uint32_t service_id, std::uint32_t call_id, std::string_view message) {
  return dump({{"op", "serviceCallFailure"}, {"serviceId", service_id}, {"callId", call_id}, {"message", message}});
}

std::string messageDataHeader(std::uint32_t subscription_id, std::uint64_t timestamp_ns) {
  std::string out;
  out.reserve(kMessageDataHeader);
  out += '\x01';
  putLe(out, subscription_id, 4);
  putLe(out, timestamp_ns, 8);
  return out;
}

std::string serviceCallResponse(std::uint32_t service_id, std::uint32_t call_id, std::string_view json_payload) {
  std::string out;
  out += '\x03';
  putLe(out, service_id, 4);
  putLe(out, call_id, 4);
  putLe(out, 4, 4);
  out += "json";
  out += json_payload;
  return out;
}

ClientMessage parseClient(std::string_view data, bool binary) { return binary ? parseBinary(data) : parseText(data); }

}  // namespace keel::monitor::foxglove
