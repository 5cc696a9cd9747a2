#include "monitor_client.hpp"

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <sys/socket.h>

#include <chrono>

#include <nlohmann/json.hpp>

namespace keel::bench {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;

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
    for (;;) {
      beast::error_code read_error;
      impl_->ws.read(buffer, read_error);
      if (read_error) return;  // closed by the destructor, or by the server
      messages_.fetch_add(1, std::memory_order_relaxed);
      if (!impl_->ws.got_text()) {
        data_.fetch_add(1, std::memory_order_relaxed);
      } else {
        // Subscribes to every channel it is told of, as a page showing everything does.
        const auto m = nlohmann::json::parse(beast::buffers_to_string(buffer.data()), nullptr, false);
        if (m.is_object() && m.value("op", "") == "advertise") {
          nlohmann::json subs = nlohmann::json::array();
          for (const auto& c : m["channels"]) subs.push_back({{"id", next_id++}, {"channelId", c["id"]}});
          beast::error_code write_error;
          impl_->ws.text(true);
          impl_->ws.write(net::buffer(nlohmann::json{{"op", "subscribe"}, {"subscriptions", subs}}.dump()),
                          write_error);
        }
      }
      buffer.consume(buffer.size());
    }
  });
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
