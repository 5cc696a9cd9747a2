#include "monitor_client.hpp"

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <sys/socket.h>

#include <chrono>

#include <nlohmann/json.hpp>

#include "monitor/little_endian.hpp"

namespace keel::bench {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;

namespace {

std::int64_t wallNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

struct MonitorClient::Impl {
  net::io_context io;
  websocket::stream<tcp::socket> ws{io};
  int fd = -1;
};

MonitorClient::MonitorClient(std::uint16_t port) : impl_(std::make_unique<Impl>()) {
  beast::error_code ec;
  auto& ws = impl_->ws;
  ws.next_layer().connect({net::ip::make_address("127.0.0.1"), port}, ec);
  if (!ec) {
    ws.set_option(websocket::stream_base::decorator([](websocket::request_type& req) {
      req.set(beast::http::field::sec_websocket_protocol, "foxglove.websocket.v1");
    }));
    ws.handshake("127.0.0.1:" + std::to_string(port), "/", ec);
  }
  if (ec) {
    error_ = "monitor client: " + ec.message();
    return;
  }
  impl_->fd = ws.next_layer().native_handle();
  thread_ = std::thread([this] {
    beast::flat_buffer buffer;
    std::uint32_t next_id = 0;
    std::int64_t start_unix_ns = 0;
    std::uint32_t faults_subscription = UINT32_MAX;
    for (;;) {
      beast::error_code read_error;
      impl_->ws.read(buffer, read_error);
      if (read_error) return;  // closed by the destructor, or by the server
      const auto received = wallNs();
      const std::string bytes = beast::buffers_to_string(buffer.data());
      buffer.consume(buffer.size());
      if (!impl_->ws.got_text()) {
        data_.fetch_add(1, std::memory_order_relaxed);
        // Message Data: 0x01, u32 subscription, u64 timestamp, then the JSON.
        monitor::ByteCursor in(bytes);
        if (in.u8() != 0x01 || in.u32() != faults_subscription) continue;
        (void)in.u64();  // its timestamp: the latency is taken from the record's own time
        if (!in.ok()) continue;
        const auto r = nlohmann::json::parse(in.rest(), nullptr, false);
        if (r.is_object() && r.value("event", "") == "detected") {
          std::lock_guard lock(latencies_mutex_);
          latencies_ns_.push_back(received - (start_unix_ns + r.value("t_ns", std::int64_t{0})));
        }
        continue;
      }
      const auto m = nlohmann::json::parse(bytes, nullptr, false);
      if (!m.is_object()) continue;
      if (m.value("op", "") == "serverInfo")
        start_unix_ns = std::stoll(m["metadata"].value("start_unix_ns", std::string("0")));
      if (m.value("op", "") != "advertise") continue;
      // Subscribes to every channel it is told of, as a page showing everything does.
      nlohmann::json subs = nlohmann::json::array();
      for (const auto& c : m["channels"]) {
        if (c.value("topic", "") == "/keel/faults") faults_subscription = next_id;
        subs.push_back({{"id", next_id++}, {"channelId", c["id"]}});
      }
      beast::error_code write_error;
      impl_->ws.text(true);
      impl_->ws.write(net::buffer(nlohmann::json{{"op", "subscribe"}, {"subscriptions", subs}}.dump()), write_error);
    }
  });
}

std::vector<std::int64_t> MonitorClient::detectionLatencies() const {
  std::lock_guard lock(latencies_mutex_);
  return latencies_ns_;
}

MonitorClient::~MonitorClient() {
  // The reader blocks in read(): the descriptor, shut down from here, ends it (the socket object
  // itself is its thread's alone).
  if (impl_->fd >= 0) ::shutdown(impl_->fd, SHUT_RDWR);
  if (thread_.joinable()) thread_.join();
}

bool MonitorClient::waitForData() {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (data_.load(std::memory_order_relaxed) == 0) {
    if (!error_.empty() || std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

}  // namespace keel::bench
