// The server's io thread: accepting, HTTP (the page, the handshake's checks) and the clients'
// WebSocket sessions (monitor/client_session.cpp). Everything here runs on that one thread;
// the public calls post to it.
#include "monitor/server.hpp"

#include <fmt/format.h>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>

#include <algorithm>
#include <optional>
#include <thread>

#include "monitor/server_impl.hpp"

namespace keel::monitor {

namespace {

/// `host:port` as a Host header or an origin names it (IPv6 addresses in brackets).
std::string hostPort(const std::string& host, std::uint16_t port) {
  return host.find(':') != std::string::npos ? fmt::format("[{}]:{}", host, port) : fmt::format("{}:{}", host, port);
}

constexpr int kSendBuffer = 256 * 1024;
constexpr std::uint32_t kRequestLimit = 16 * 1024;  // a page request or a handshake: headers only

bool anyAddress(const std::string& address) { return address == "0.0.0.0" || address == "::"; }

/// One HTTP connection: the page, or a WebSocket handshake handed to a ClientSession.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Server::Impl& server) : stream_(std::move(socket)), server_(server) {}

  void run() { read(); }

 private:
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  Server::Impl& server_;

  void read() {
    parser_.emplace();
    parser_->header_limit(kRequestLimit);
    parser_->body_limit(kRequestLimit);
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, *parser_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) { self->onRead(ec); });
  }

  void onRead(beast::error_code ec) {
    if (ec) return close();
    http::request<http::string_body> req = parser_->release();
    if (std::string why = server_.refusal(req); !why.empty()) {
      return respond(req, http::status::forbidden, "text/plain; charset=utf-8", why + "\n", false);
    }
    if (websocket::is_upgrade(req)) {
      const std::string offered(req[http::field::sec_websocket_protocol]);
      if (!offersSubprotocol(offered)) {
        return respond(req, http::status::bad_request, "text/plain; charset=utf-8",
                       fmt::format("keel speaks the WebSocket subprotocol {}\n", foxglove::kSubprotocol), false);
      }
      stream_.expires_never();
      return startClientSession(stream_.release_socket(), std::move(req), server_);
    }
    if (req.method() != http::verb::get)
      return respond(req, http::status::method_not_allowed, "text/plain; charset=utf-8", "GET only\n", true);
    const auto target = req.target();
    const auto path = target.substr(0, target.find('?'));
    if (path == "/" || path == "/index.html")
      return respond(req, http::status::ok, "text/html; charset=utf-8", server_.options.page, true);
    respond(req, http::status::not_found, "text/plain; charset=utf-8", "not found\n", true);
  }

  static bool offersSubprotocol(std::string_view offered) {
    while (!offered.empty()) {
      const auto comma = offered.find(',');
      std::string_view one = offered.substr(0, comma);
      while (!one.empty() && one.front() == ' ') one.remove_prefix(1);
      while (!one.empty() && one.back() == ' ') one.remove_suffix(1);
      if (one == foxglove::kSubprotocol) return true;
      if (comma == std::string_view::npos) break;
      offered.remove_prefix(comma + 1);
    }
    return false;
  }

  void respond(const http::request<http::string_body>& req, http::status status, std::string_view type,
               std::string body, bool keep_alive) {
    auto res = std::make_shared<http::response<http::string_body>>(status, req.version());
    res->set(http::field::server, "keel");
    res->set(http::field::content_type, type);
    res->set(http::field::cache_control, "no-store");
    res->set("Referrer-Policy", "no-referrer");
    res->set("X-Content-Type-Options", "nosniff");
    res->set("X-Frame-Options", "DENY");
    // The page's own script and style, inline; it talks to this server only.
    res->set("Content-Security-Policy",
             "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data:; "
             "connect-src 'self'; frame-ancestors 'none'");
    res->keep_alive(keep_alive && req.keep_alive());
    res->body() = std::move(body);
    res->prepare_payload();
    http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
      if (ec || !res->keep_alive()) return self->close();
      self->read();
    });
  }

  void close() {
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
    stream_.close();
  }
};

}  // namespace

std::string Server::Impl::refusal(const http::request<http::string_body>& req) const {
  // A page elsewhere must not reach this server through a name that resolves to it (DNS
  // rebinding): the Host must be one it answers to. Bound to every interface, any name is.
  const std::string host(req[http::field::host]);
  if (!anyAddress(options.address) && std::find(hosts.begin(), hosts.end(), host) == hosts.end())
    return fmt::format("keel's monitor does not answer to the host '{}'", host.substr(0, 200));
  // A browser says where the page asking comes from: only this server's own page, or an
  // origin allowed by --monitor-origin, may connect. A client that is no browser sends none.
  const auto origin_field = req.find(http::field::origin);
  if (origin_field == req.end()) return {};
  const std::string origin(origin_field->value());
  for (const auto& h : anyAddress(options.address) ? std::vector<std::string>{host} : hosts)
    if (origin == "http://" + h) return {};
  for (const auto& allowed : options.allowed_origins)
    if (origin == allowed) return {};
  return fmt::format("keel's monitor refuses the origin '{}' (allow it with --monitor-origin)", origin.substr(0, 200));
}

Result<std::unique_ptr<Server>> Server::start(ServerOptions options, ServiceHandler on_service_call) {
  auto impl = std::make_unique<Impl>();
  impl->options = std::move(options);
  impl->on_service_call = std::move(on_service_call);
  beast::error_code ec;
  const auto address = net::ip::make_address(impl->options.address, ec);
  if (ec) return Error{fmt::format("monitor: '{}' is not an IP address", impl->options.address)};
  const tcp::endpoint endpoint{address, impl->options.port};
  auto& acceptor = impl->acceptor;
  if (acceptor.open(endpoint.protocol(), ec); !ec) acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (ec)
    return Error{fmt::format("monitor: cannot listen on {}: {}", hostPort(impl->options.address, endpoint.port()),
                             ec.message())};
  impl->port = acceptor.local_endpoint().port();
  for (const std::string& name : {impl->options.address, std::string("127.0.0.1"), std::string("localhost")})
    impl->hosts.push_back(hostPort(name, impl->port));
  if (impl->options.address == "::" || impl->options.address == "::1")
    impl->hosts.push_back(hostPort("::1", impl->port));
  impl->accept();
  impl->thread = std::thread([raw = impl.get()] { raw->io.run(); });
  return std::unique_ptr<Server>(new Server(std::move(impl)));
}

void Server::Impl::accept() {
  acceptor.async_accept(io, [this](beast::error_code ec, tcp::socket socket) {
    if (ec == net::error::operation_aborted || !acceptor.is_open()) return;
    if (!ec) {
      socket.set_option(tcp::no_delay(true), ec);  // a fault's few hundred bytes go out now
      // What a client has not read waits in its queue, where it is counted and dropped, rather
      // than in megabytes of kernel buffer: a stalled client is found in seconds, not minutes.
      socket.set_option(net::socket_base::send_buffer_size(kSendBuffer), ec);
      std::make_shared<HttpSession>(std::move(socket), *this)->run();
    }
    accept();
  });
}

Server::Server(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Server::~Server() {
  net::post(impl_->io, [impl = impl_.get()] {
    beast::error_code ignored;
    impl->acceptor.close(ignored);
    impl->closeAll();
  });
  // Sessions get a moment to say goodbye; then the loop is stopped whatever they wait for.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
  while (!impl_->io.stopped() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  impl_->io.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

std::uint16_t Server::port() const { return impl_->port; }

void Server::advertise(std::vector<foxglove::Channel> channels) {
  net::post(impl_->io, [impl = impl_.get(), channels = std::move(channels)] { impl->advertise(channels); });
}

void Server::unadvertise(std::vector<std::uint32_t> channel_ids) {
  net::post(impl_->io, [impl = impl_.get(), ids = std::move(channel_ids)] { impl->unadvertise(ids); });
}

void Server::publish(std::uint32_t channel, std::uint64_t timestamp_ns, std::shared_ptr<const std::string> payload,
                     Retain retain) {
  net::post(impl_->io, [impl = impl_.get(), channel, timestamp_ns, payload = std::move(payload), retain]() mutable {
    impl->publish(channel, timestamp_ns, std::move(payload), retain);
  });
}

bool Server::subscribed(std::uint32_t channel) const {
  std::lock_guard lock(impl_->subscribed_mutex);
  auto it = impl_->subscriber_counts.find(channel);
  return it != impl_->subscriber_counts.end() && it->second > 0;
}

}  // namespace keel::monitor
