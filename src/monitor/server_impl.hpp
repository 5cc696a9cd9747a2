// The server's insides (monitor/server.hpp), shared by its two files: server.cpp (accepting,
// HTTP) and client_session.cpp (a WebSocket client). The only header that includes Boost; it
// is private to them. Everything here runs on the io thread, except the subscriber
// counts (read from any thread).
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <atomic>
#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "monitor/server.hpp"

namespace keel::monitor {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;

class ClientSession;

struct Server::Impl {
  net::io_context io{1};  // first: destroyed last, after everything bound to it
  ServerOptions options;
  ServiceHandler on_service_call;
  tcp::acceptor acceptor{io};
  std::thread thread;
  std::uint16_t port = 0;
  std::vector<std::string> hosts;  // host:port names a Host header may give

  // io thread only
  std::map<std::uint32_t, foxglove::Channel> channels;
  struct Kept {
    std::uint64_t timestamp_ns = 0;
    std::shared_ptr<const std::string> payload;
  };
  std::map<std::uint32_t, std::deque<Kept>> kept;  // what a new subscriber gets first (Retain)
  std::set<std::shared_ptr<ClientSession>> sessions;

  mutable std::mutex subscribed_mutex;
  std::map<std::uint32_t, int> subscriber_counts;  // channel → subscriptions, all clients

  /// Why a request must be refused (its Host or Origin), or empty.
  std::string refusal(const http::request<http::string_body>& req) const;
  void accept();
  void advertise(const std::vector<foxglove::Channel>& added);
  void unadvertise(const std::vector<std::uint32_t>& ids);
  void publish(std::uint32_t channel, std::uint64_t timestamp_ns, std::shared_ptr<const std::string> payload,
               Retain retain);
  void closeAll() const;
  void countSubscriber(std::uint32_t channel, int delta);
};

/// A WebSocket client of the Foxglove protocol: its subscriptions and its bounded queue.
class ClientSession : public std::enable_shared_from_this<ClientSession> {
 public:
  ClientSession(tcp::socket socket, Server::Impl& server);
  void start(http::request<http::string_body> req);
  /// Protocol messages (serverInfo, status, replies): always queued.
  void sendText(std::string text);
  void sendBinary(std::string bytes);
  /// A channel's message to whoever subscribes to it here; dropped when the queue is full.
  void sendMessage(std::uint32_t channel, std::uint64_t timestamp_ns,
                   const std::shared_ptr<const std::string>& payload);
  void channelsGone(const std::vector<std::uint32_t>& ids);
  void close();

 private:
  struct Out {
    std::string head;                            // a whole text/binary message, or a Message Data header
    std::shared_ptr<const std::string> payload;  // the shared payload after `head`, or null
    bool binary = false;
    std::size_t size() const { return head.size() + (payload ? payload->size() : 0); }
  };
  websocket::stream<beast::tcp_stream> ws_;
  http::request<http::string_body> req_;
  beast::flat_buffer buffer_;
  Server::Impl& server_;
  std::deque<Out> queue_;
  std::size_t queued_bytes_ = 0;
  bool writing_ = false;
  bool open_ = false;  // the handshake is done
  bool finished_ = false;
  std::map<std::uint32_t, std::uint32_t> subscriptions_;  // subscription id → channel
  std::map<std::uint32_t, std::uint32_t> by_channel_;     // channel → subscription id
  std::uint64_t dropped_ = 0;
  std::chrono::steady_clock::time_point dropped_told_{};

  void read();
  void onMessage(const std::string& data, bool binary);
  void subscribe(const foxglove::Subscribe& s);
  void unsubscribe(const foxglove::Unsubscribe& u);
  void call(foxglove::ServiceCall c);
  void enqueue(Out out);
  void write();
  void finish();  // gone: out of the server's sessions, its subscriptions uncounted
};

void startClientSession(tcp::socket socket, http::request<http::string_body> req, Server::Impl& server);

}  // namespace keel::monitor
