// A WebSocket client of the monitor (monitor/server_impl.hpp), and the server's fan-out to its
// clients. On the io thread only.
#include <fmt/format.h>

#include <boost/asio/post.hpp>

#include <array>

#include "monitor/server_impl.hpp"

namespace keel::monitor {

namespace {
constexpr auto kDroppedToldEvery = std::chrono::seconds(1);
}

void startClientSession(tcp::socket socket, http::request<http::string_body> req, Server::Impl& server) {
  auto session = std::make_shared<ClientSession>(std::move(socket), server);
  server.sessions.insert(session);
  session->start(std::move(req));
}

ClientSession::ClientSession(tcp::socket socket, Server::Impl& server) : ws_(std::move(socket)), server_(server) {}

void ClientSession::start(http::request<http::string_body> req) {
  req_ = std::move(req);
  // A client that stops answering is found by pings and closed: its queue is not kept forever.
  websocket::stream_base::timeout timeouts{};
  timeouts.handshake_timeout = std::chrono::seconds(10);
  timeouts.idle_timeout = std::chrono::seconds(20);
  timeouts.keep_alive_pings = true;
  ws_.set_option(timeouts);
  ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& res) {
    res.set(http::field::server, "keel");
    res.set(http::field::sec_websocket_protocol, foxglove::kSubprotocol);
  }));
  ws_.read_message_max(server_.options.max_client_message);
  ws_.async_accept(req_, [self = shared_from_this()](beast::error_code ec) {
    if (ec) return self->finish();
    self->open_ = true;
    self->sendText(self->server_.options.server_info);
    std::vector<foxglove::Channel> channels;
    for (const auto& [id, c] : self->server_.channels) channels.push_back(c);
    if (!channels.empty()) self->sendText(foxglove::advertise(channels));
    if (!self->server_.options.services.empty())
      self->sendText(foxglove::advertiseServices(self->server_.options.services));
    self->read();
  });
}

void ClientSession::read() {
  ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (ec) return self->finish();  // closed, too long a message (1009), a dead peer
    std::string data = beast::buffers_to_string(self->buffer_.data());
    self->buffer_.consume(self->buffer_.size());
    self->onMessage(data, !self->ws_.got_text());
    self->read();
  });
}

void ClientSession::onMessage(const std::string& data, bool binary) {
  auto message = foxglove::parseClient(data, binary);
  if (auto* s = std::get_if<foxglove::Subscribe>(&message)) return subscribe(*s);
  if (auto* u = std::get_if<foxglove::Unsubscribe>(&message)) return unsubscribe(*u);
  if (auto* c = std::get_if<foxglove::ServiceCall>(&message)) return call(std::move(*c));
  if (auto* bad = std::get_if<foxglove::Invalid>(&message)) {
    sendText(foxglove::status(foxglove::StatusLevel::Error, "keel cannot read that message: " + bad->why, "keel.bad"));
  }
  // Unsupported: a capability keel does not announce; ignored, as the protocol has it.
}

void ClientSession::subscribe(const foxglove::Subscribe& s) {
  for (const auto& one : s.subscriptions) {
    if (subscriptions_.count(one.id)) {
      sendText(foxglove::status(foxglove::StatusLevel::Error, fmt::format("subscription id {} is in use", one.id),
                                "keel.subscribe"));
      continue;
    }
    if (!server_.channels.count(one.channel_id)) {
      sendText(foxglove::status(foxglove::StatusLevel::Warning, fmt::format("no channel {}", one.channel_id),
                                "keel.subscribe"));
      continue;
    }
    if (by_channel_.count(one.channel_id)) {
      sendText(foxglove::status(foxglove::StatusLevel::Warning,
                                fmt::format("channel {} is subscribed already", one.channel_id), "keel.subscribe"));
      continue;
    }
    subscriptions_[one.id] = one.channel_id;
    by_channel_[one.channel_id] = one.id;
    server_.countSubscriber(one.channel_id, +1);
    // What the channel keeps (the state now, the faults so far): a new subscriber sees the run.
    if (auto kept = server_.kept.find(one.channel_id); kept != server_.kept.end())
      for (const auto& k : kept->second) sendMessage(one.channel_id, k.timestamp_ns, k.payload);
  }
}

void ClientSession::unsubscribe(const foxglove::Unsubscribe& u) {
  for (auto id : u.subscription_ids) {
    auto it = subscriptions_.find(id);
    if (it == subscriptions_.end()) {
      sendText(
          foxglove::status(foxglove::StatusLevel::Warning, fmt::format("no subscription {}", id), "keel.subscribe"));
      continue;
    }
    server_.countSubscriber(it->second, -1);
    by_channel_.erase(it->second);
    subscriptions_.erase(it);
  }
}

void ClientSession::call(foxglove::ServiceCall c) {
  const auto service_id = c.service_id;
  const auto call_id = c.call_id;
  const bool known = std::any_of(server_.options.services.begin(), server_.options.services.end(),
                                 [&](const foxglove::Service& s) { return s.id == service_id; });
  if (!known)
    return sendText(foxglove::serviceCallFailure(service_id, call_id, fmt::format("no service {}", service_id)));
  if (c.encoding != "json")
    return sendText(foxglove::serviceCallFailure(service_id, call_id, "keel's services take the encoding json"));
  std::weak_ptr<ClientSession> weak = shared_from_this();
  auto& io = server_.io;
  server_.on_service_call(std::move(c), [weak, &io, service_id, call_id](ServiceReply reply) {
    net::post(io, [weak, service_id, call_id, reply = std::move(reply)] {
      auto self = weak.lock();
      if (!self || self->finished_) return;
      if (reply.ok) self->sendBinary(foxglove::serviceCallResponse(service_id, call_id, reply.body));
      else self->sendText(foxglove::serviceCallFailure(service_id, call_id, reply.body));
    });
  });
}

void ClientSession::sendText(std::string text) { enqueue({std::move(text), nullptr, false}); }

void ClientSession::sendBinary(std::string bytes) { enqueue({std::move(bytes), nullptr, true}); }

void ClientSession::sendMessage(std::uint32_t channel, std::uint64_t timestamp_ns,
                                const std::shared_ptr<const std::string>& payload) {
  auto sub = by_channel_.find(channel);
  if (sub == by_channel_.end() || finished_) return;
  Out out{foxglove::messageDataHeader(sub->second, timestamp_ns), payload, true};
  if (queued_bytes_ + out.size() > server_.options.max_queued_bytes) {
    // Too slow a reader loses messages, never the robot: counted, and told at most once a second.
    ++dropped_;
    const auto now = std::chrono::steady_clock::now();
    if (now - dropped_told_ >= kDroppedToldEvery) {
      dropped_told_ = now;
      sendText(foxglove::status(foxglove::StatusLevel::Warning,
                                fmt::format("{} messages dropped: this client reads too slowly", dropped_),
                                "keel.dropped"));
    }
    return;
  }
  enqueue(std::move(out));
}

void ClientSession::enqueue(Out out) {
  if (finished_) return;
  queued_bytes_ += out.size();
  queue_.push_back(std::move(out));
  if (!writing_) write();
}

void ClientSession::write() {
  if (queue_.empty() || finished_) {
    writing_ = false;
    return;
  }
  writing_ = true;
  const Out& out = queue_.front();
  ws_.binary(out.binary);
  std::array<net::const_buffer, 2> buffers{net::buffer(out.head),
                                           out.payload ? net::buffer(*out.payload) : net::const_buffer()};
  ws_.async_write(buffers, [self = shared_from_this()](beast::error_code ec, std::size_t) {
    self->queued_bytes_ -= self->queue_.front().size();
    self->queue_.pop_front();
    if (ec || self->finished_) {
      // The queue's buffers were in use until now: dropped only once the write is over.
      self->writing_ = false;
      self->queue_.clear();
      self->queued_bytes_ = 0;
      return self->finish();
    }
    self->write();
  });
}

void ClientSession::channelsGone(const std::vector<std::uint32_t>& ids) {
  for (auto channel : ids) {
    auto it = by_channel_.find(channel);
    if (it == by_channel_.end()) continue;
    server_.countSubscriber(channel, -1);
    subscriptions_.erase(it->second);
    by_channel_.erase(it);
  }
}

void ClientSession::close() {
  if (finished_) return;
  if (!open_) return finish();  // still shaking hands: no close frame to send
  ws_.async_close(websocket::close_code::going_away,
                  [self = shared_from_this()](beast::error_code) { self->finish(); });
}

void ClientSession::finish() {
  if (finished_) return;
  finished_ = true;
  for (const auto& [channel, sub] : by_channel_) server_.countSubscriber(channel, -1);
  by_channel_.clear();
  subscriptions_.clear();
  if (!writing_) {  // else the write in flight still reads the front: cleared when it ends
    queue_.clear();
    queued_bytes_ = 0;
  }
  beast::error_code ignored;
  beast::get_lowest_layer(ws_).socket().close(ignored);
  server_.sessions.erase(shared_from_this());
}

// ---- the server's fan-out ------------------------------------------------------------------

void Server::Impl::advertise(const std::vector<foxglove::Channel>& added) {
  for (const auto& c : added) channels[c.id] = c;
  const std::string message = foxglove::advertise(added);
  for (const auto& s : sessions) s->sendText(message);
}

void Server::Impl::unadvertise(const std::vector<std::uint32_t>& ids) {
  for (auto id : ids) {
    channels.erase(id);
    kept.erase(id);
  }
  const std::string message = foxglove::unadvertise(ids);
  for (const auto& s : sessions) {
    s->channelsGone(ids);
    s->sendText(message);
  }
}

void Server::Impl::publish(std::uint32_t channel, std::uint64_t timestamp_ns,
                           std::shared_ptr<const std::string> payload, Retain retain) {
  if (!channels.count(channel)) return;
  for (const auto& s : sessions) s->sendMessage(channel, timestamp_ns, payload);
  if (retain == Retain::None) return;
  auto& k = kept[channel];
  k.push_back({timestamp_ns, std::move(payload)});
  while (k.size() > (retain == Retain::Latest ? 1 : kHistory)) k.pop_front();
}

void Server::Impl::closeAll() const {
  auto all = sessions;  // close() may finish a session at once
  for (const auto& s : all) s->close();
}

void Server::Impl::countSubscriber(std::uint32_t channel, int delta) {
  std::lock_guard lock(subscribed_mutex);
  subscriber_counts[channel] += delta;
}

}  // namespace keel::monitor
