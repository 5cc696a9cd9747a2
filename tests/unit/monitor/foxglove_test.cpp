#include "monitor/foxglove.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace keel::monitor::foxglove {
namespace {

using nlohmann::json;
using namespace std::string_literals;

std::string serviceCallBytes(std::uint32_t service, std::uint32_t call, std::string_view encoding,
                             std::string_view payload) {
  std::string out(1, '\x02');
  for (std::uint32_t v : {service, call, static_cast<std::uint32_t>(encoding.size())})
    for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xFF);
  out += encoding;
  out += payload;
  return out;
}

TEST(FoxgloveProtocol, MessageDataHeaderIsOpcodeSubscriptionAndTimestampLittleEndian) {
  const std::string h = messageDataHeader(0x01020304, 0x1122334455667788ULL);
  ASSERT_EQ(h.size(), kMessageDataHeader);
  EXPECT_EQ(h, std::string("\x01\x04\x03\x02\x01\x88\x77\x66\x55\x44\x33\x22\x11", 13));
}

TEST(FoxgloveProtocol, ServiceCallResponseCarriesItsIdsEncodingAndPayload) {
  const std::string r = serviceCallResponse(7, 9, R"({"ok":true})");
  EXPECT_EQ(r, "\x03\x07\0\0\0\x09\0\0\0\x04\0\0\0json{\"ok\":true}"s);
}

TEST(FoxgloveProtocol, AdvertiseDescribesEachChannelWithItsJsonSchema) {
  const json m = json::parse(advertise({{3, "/keel/state", "keel.State", R"({"type":"object"})"}}));
  EXPECT_EQ(m["op"], "advertise");
  ASSERT_EQ(m["channels"].size(), 1U);
  const auto& c = m["channels"][0];
  EXPECT_EQ(c["id"], 3);
  EXPECT_EQ(c["topic"], "/keel/state");
  EXPECT_EQ(c["encoding"], "json");
  EXPECT_EQ(c["schemaEncoding"], "jsonschema");
  EXPECT_EQ(c["schema"], R"({"type":"object"})");
}

TEST(FoxgloveProtocol, ServerInfoAnnouncesServicesAndJson) {
  const json m = json::parse(serverInfo("keel", {{"run", "robot"}}, "42-1"));
  EXPECT_EQ(m["op"], "serverInfo");
  EXPECT_EQ(m["capabilities"], json::array({"services"}));
  EXPECT_EQ(m["supportedEncodings"], json::array({"json"}));
  EXPECT_EQ(m["metadata"]["run"], "robot");
  EXPECT_EQ(m["sessionId"], "42-1");
}

TEST(FoxgloveProtocol, ReadsSubscribeAndUnsubscribe) {
  auto sub = parseClient(R"({"op":"subscribe","subscriptions":[{"id":0,"channelId":2},{"id":5,"channelId":1}]})",
                         false);
  ASSERT_TRUE(std::holds_alternative<Subscribe>(sub));
  const auto& s = std::get<Subscribe>(sub).subscriptions;
  ASSERT_EQ(s.size(), 2U);
  EXPECT_EQ(s[1].id, 5U);
  EXPECT_EQ(s[1].channel_id, 1U);
  auto unsub = parseClient(R"({"op":"unsubscribe","subscriptionIds":[0,5]})", false);
  ASSERT_TRUE(std::holds_alternative<Unsubscribe>(unsub));
  EXPECT_EQ(std::get<Unsubscribe>(unsub).subscription_ids, (std::vector<std::uint32_t>{0, 5}));
}

TEST(FoxgloveProtocol, ReadsAServiceCall) {
  auto m = parseClient(serviceCallBytes(1, 77, "json", R"({"token":"t"})"), true);
  ASSERT_TRUE(std::holds_alternative<ServiceCall>(m));
  const auto& c = std::get<ServiceCall>(m);
  EXPECT_EQ(c.service_id, 1U);
  EXPECT_EQ(c.call_id, 77U);
  EXPECT_EQ(c.encoding, "json");
  EXPECT_EQ(c.payload, R"({"token":"t"})");
}

TEST(FoxgloveProtocol, IgnoresOpsOfCapabilitiesKeelDoesNotOffer) {
  EXPECT_TRUE(std::holds_alternative<Unsupported>(parseClient(R"({"op":"getParameters","parameterNames":[]})", false)));
  EXPECT_TRUE(std::holds_alternative<Unsupported>(parseClient(std::string("\x01\0\0\0\0{}", 7), true)));
}

TEST(FoxgloveProtocol, EveryMalformedMessageIsInvalidSayingWhy) {
  const std::pair<std::string, bool> bad[] = {
      {"not json", false},
      {"[1,2]", false},
      {R"({"subscriptions":[]})", false},
      {R"({"op":42})", false},
      {R"({"op":"fly"})", false},
      {R"({"op":"subscribe"})", false},
      {R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":2}]})", false},
      {R"({"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":2}]})", false},
      {R"({"op":"subscribe","subscriptions":[{"id":"0","channelId":2}]})", false},
      {R"({"op":"subscribe","subscriptions":[7]})", false},
      {R"({"op":"unsubscribe","subscriptionIds":["a"]})", false},
      {"", true},
      {"\x09", true},
      {std::string("\x02\x01\0\0", 4), true},
      {serviceCallBytes(1, 2, "json", "").substr(0, 12), true},
      {std::string("\x02\x01\0\0\0\x02\0\0\0\xff\xff\xff\xff", 13), true},  // encoding past the end
  };
  for (const auto& [data, binary] : bad) {
    auto m = parseClient(data, binary);
    ASSERT_TRUE(std::holds_alternative<Invalid>(m)) << data;
    EXPECT_FALSE(std::get<Invalid>(m).why.empty());
  }
}

}  // namespace
}  // namespace keel::monitor::foxglove
