#include "monitor/foxglove.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "monitor/little_endian.hpp"

namespace keel::monitor::foxglove {
namespace {

using nlohmann::json;

std::string dump(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

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
  for (auto known : kUnsupportedOps)
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
  ByteCursor in(data.substr(1));
  ServiceCall call;
  call.service_id = in.u32();
  call.call_id = in.u32();
  call.encoding = std::string(in.string());
  if (!in.ok()) return Invalid{"a service call whose encoding runs past its end"};
  call.payload = std::string(in.rest());
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
  putU8(out, 0x01);
  putU32(out, subscription_id);
  putU64(out, timestamp_ns);
  return out;
}

std::string serviceCallResponse(std::uint32_t service_id, std::uint32_t call_id, std::string_view json_payload) {
  std::string out;
  putU8(out, 0x03);
  putU32(out, service_id);
  putU32(out, call_id);
  putString(out, "json");
  out += json_payload;
  return out;
}

ClientMessage parseClient(std::string_view data, bool binary) { return binary ? parseBinary(data) : parseText(data); }

}  // namespace keel::monitor::foxglove
