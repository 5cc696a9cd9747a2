// The monitor's server (docs/monitor.md): one port serving the web page over HTTP and the
// Foxglove WebSocket protocol to any number of clients, on one io thread of its own (Boost.Beast;
// decision 0014). It never makes its callers wait: publish() hands a message over and returns;
// each client has a bounded queue, and a client too slow to empty it loses messages, counted
// and told, never slowing the others or the run. Browsers from another origin are refused, and
// so is a Host the server does not answer to (DNS rebinding).
// Thread-safety: publish(), advertise(), unadvertise(), subscribed() from any thread.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "keel/result.hpp"
#include "monitor/foxglove.hpp"

namespace keel::monitor {

struct ServerOptions {
  std::string address = "127.0.0.1";  // 0.0.0.0 or :: for every interface
  std::uint16_t port = 0;             // 0: any free port
  /// Origins allowed beyond the page's own (keel run --monitor-origin), e.g. a Foxglove app's.
  std::vector<std::string> allowed_origins;
  std::size_t max_client_message = std::size_t{64} * 1024;      // a longer one closes the connection (1009)
  std::size_t max_queued_bytes = std::size_t{4} * 1024 * 1024;  // per client: beyond, messages are dropped
  std::string page;                                             // served at `/`
  std::string server_info;                                      // the serverInfo message sent first
  std::vector<foxglove::Service> services;
};

/// What a client's service call gets: a JSON response, or a failure message.
struct ServiceReply {
  bool ok = false;
  std::string body;  // ok: the response's JSON; else why it failed
};

/// Called on the io thread for each service call; `reply` may be called later, from any thread.
using ServiceHandler = std::function<void(foxglove::ServiceCall, std::function<void(ServiceReply)> reply)>;

class Server {
 public:
  static Result<std::unique_ptr<Server>> start(ServerOptions options, ServiceHandler on_service_call);
  ~Server();  // closes every connection and joins the io thread
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// The port it listens on (the one chosen when asked for 0).
  std::uint16_t port() const;

  /// Offers `channels` to every client, now and to come (ids unique).
  void advertise(std::vector<foxglove::Channel> channels);
  void unadvertise(std::vector<std::uint32_t> channel_ids);
  /// What a channel's new subscriber is sent first.
  enum class Retain {
    None,     // nothing: it sees what comes after it subscribed
    Latest,   // the newest message (a state snapshot)
    History,  // the last kHistory messages (the fault records: a page opened late shows them)
  };
  static constexpr std::size_t kHistory = 5000;
  /// Sends `payload` (JSON) on `channel` to its subscribers, and keeps it as `retain` says.
  void publish(std::uint32_t channel, std::uint64_t timestamp_ns, std::shared_ptr<const std::string> payload,
               Retain retain = Retain::None);
  /// Whether any client subscribes to `channel` now.
  bool subscribed(std::uint32_t channel) const;

  struct Impl;

 private:
  explicit Server(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace keel::monitor
