#include "monitor/monitor.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "engine/engine.hpp"
#include "monitor/log_follower.hpp"
#include "monitor/mcap_writer.hpp"
#include "monitor/page.hpp"
#include "monitor/port_tap.hpp"
#include "monitor/run_model.hpp"
#include "monitor/server.hpp"
#include "monitor/token.hpp"
#include "runtime/component_core.hpp"
#include "runtime/job_thread.hpp"
#include "runtime/port_access.hpp"

namespace keel::monitor {

namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr std::uint32_t kStateChannel = 1;
constexpr std::uint32_t kFaultsChannel = 2;
constexpr std::uint32_t kFirstPortChannel = 3;
constexpr std::size_t kTapCapacity = 16384;  // values per port between two drains: 0.8 s at 20 kHz
constexpr std::uint32_t kEmergencyService = 1;
constexpr std::uint32_t kClearService = 2;
constexpr auto kStateEvery = std::chrono::seconds(1);      // a snapshot at least once a second
constexpr auto kWait = std::chrono::milliseconds(100);     // the hub's longest sleep
constexpr auto kPortWait = std::chrono::milliseconds(20);  // ... while it takes port values
constexpr auto kSettle = std::chrono::milliseconds(1);     // from a write to the hub's reading it

const std::string& faultRecordSchema() {
  static const std::string schema = json{
      {"type", "object"},
      {"title", "keel.FaultLogRecord"},
      {"description", "One record of keel's fault log (docs/fault-log.md), as written"},
      {"properties",
       {{"event", {{"type", "string"}}},
        {"t_ns", {{"type", "integer"}, {"description", "ns since the run started (steady clock)"}}},
        {"fault_id", {{"type", "integer"}}},
        {"component", {{"type", "string"}}}}},
      {"required", {"event", "t_ns"}},
      {"additionalProperties", true}}.dump();
  return schema;
}

std::vector<foxglove::Service> services() {
  const std::string request =
      json{{"type", "object"}, {"properties", {{"token", {{"type", "string"}}}}}, {"required", {"token"}}}.dump();
  const std::string response = json{{"type", "object"},
                                    {"properties", {{"ok", {{"type", "boolean"}}}, {"detail", {{"type", "string"}}}}}}
                                   .dump();
  return {{kEmergencyService, "/keel/emergency_stop", "keel/Control", request, response},
          {kClearService, "/keel/clear_emergency", "keel/Control", request, response}};
}

std::string portSchema(const char* json_type) {
  json value = {{"type", json_type}};
  if (std::string_view(json_type) == "array") value["items"] = {{"type", "number"}};
  return json{{"type", "object"},
              {"title", "keel.PortValue"},
              {"description", "A value an output port sent, and when (ns since the run started)"},
              {"properties", {{"t_ns", {{"type", "integer"}}}, {"value", std::move(value)}}}}
      .dump();
}

Topology topologyOf(const engine::Engine& engine) {
  Topology t;
  const auto& plan = engine.plan();
  t.run = plan.name;
  for (const auto& i : plan.instances) t.components.push_back({i.name, i.application, i.process});
  for (const auto& c : plan.connections)
    t.connections.push_back({c.source.component, c.source.port, c.target.component, c.target.port,
                             c.type == PortKind::Data    ? "data"
                             : c.type == PortKind::Event ? "event"
                                                         : "service"});
  return t;
}

std::int64_t wallNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

struct Monitor::Impl {
  engine::Engine& engine;
  MonitorOptions options;
  std::string token;
  std::string address;
  std::int64_t start_unix_ns = 0;  // the wall-clock time of the log's t_ns 0
  std::unique_ptr<Server> server;  // null: recording only
  std::optional<McapWriter> recording;
  std::uint16_t record_state = 0, record_faults = 0;  // the recording's channel ids
  Result<void> record_result;
  std::optional<LogFollower> follower;
  struct Port {
    std::unique_ptr<PortTap> tap;
    foxglove::Channel channel;
    std::uint16_t record_channel = 0;
  };
  std::vector<Port> ports;
  RunModel model;
  std::thread hub;
  std::atomic<bool> stopping{false};
  Clock::time_point last_state{};  // the hub's: when /keel/state was last sent

  // The control thread: an emergency stop may take its containment bound; never the io thread's.
  runtime::JobThread control;

  Impl(engine::Engine& e, MonitorOptions o) : engine(e), options(std::move(o)), model(topologyOf(e)) {}

  void onServiceCall(const foxglove::ServiceCall& call, std::function<void(ServiceReply)> reply);
  void runHub();
  void handle(const std::vector<std::string>& lines);
  void publishState();
  void send(std::uint32_t channel, std::int64_t t_ns, std::string payload, Server::Retain retain);
  void makePortChannels();
  bool takePortValues();
};

Result<std::pair<std::string, std::uint16_t>> parseListen(const std::string& text) {
  std::string address = "127.0.0.1";
  std::string port = text;
  if (!text.empty() && text.front() == '[') {  // [IPv6]:PORT
    const auto close = text.find("]:");
    if (close == std::string::npos) return Error{fmt::format("--monitor '{}': expected [ADDRESS]:PORT", text)};
    address = text.substr(1, close - 1);
    port = text.substr(close + 2);
  } else if (const auto colon = text.rfind(':'); colon != std::string::npos) {
    address = text.substr(0, colon);
    port = text.substr(colon + 1);
  }
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos ||
      std::stoul(port) > 65535)
    return Error{fmt::format("--monitor '{}': the port must be a number from 0 to 65535", text)};
  return std::pair{address, static_cast<std::uint16_t>(std::stoul(port))};
}

Result<std::unique_ptr<Monitor>> Monitor::start(engine::Engine& engine, MonitorOptions options) {
  auto impl = std::make_unique<Impl>(engine, std::move(options));
  auto token = newToken();
  if (!token) return token.error();
  impl->token = std::move(*token);
  const auto& log = engine.log();
  impl->start_unix_ns = wallNs() - (log.now());
  auto follower = LogFollower::open(impl->options.log_path);
  if (!follower) return follower.error();
  impl->follower.emplace(std::move(*follower));

  if (!impl->options.record.empty()) {
    auto recording = McapWriter::create(impl->options.record, "keel",
                                        {{"run", engine.plan().name},
                                         {"profile", impl->options.profile},
                                         {"start_unix_ns", std::to_string(impl->start_unix_ns)}});
    if (!recording) return Error{"--record: " + recording.error().message};
    impl->recording.emplace(std::move(*recording));
    impl->record_state = impl->recording->addChannel("/keel/state", "keel.State", RunModel::snapshotSchema());
    impl->record_faults = impl->recording->addChannel("/keel/faults", "keel.FaultLogRecord", faultRecordSchema());
  }
  if (impl->options.listen.empty()) {
    impl->makePortChannels();
    impl->hub = std::thread([raw = impl.get()] { raw->runHub(); });
    return std::unique_ptr<Monitor>(new Monitor(std::move(impl)));
  }
  auto listen = parseListen(impl->options.listen);
  if (!listen) return listen.error();
  impl->address = listen->first;
  ServerOptions so;
  so.address = listen->first;
  so.port = listen->second;
  so.allowed_origins = impl->options.allowed_origins;
  so.max_queued_bytes = impl->options.queue_bytes;
  so.page = std::string(pageHtml());
  so.server_info = foxglove::serverInfo("keel",
                                        {{"run", engine.plan().name},
                                         {"profile", impl->options.profile},
                                         {"start_unix_ns", std::to_string(impl->start_unix_ns)},
                                         {"pid", std::to_string(::getpid())}},
                                        fmt::format("{}-{}", ::getpid(), impl->start_unix_ns));
  so.services = services();
  auto server = Server::start(std::move(so), [raw = impl.get()](const foxglove::ServiceCall& call, auto reply) {
    raw->onServiceCall(call, std::move(reply));
  });
  if (!server) return server.error();
  impl->server = std::move(*server);
  // Last, once nothing can fail: a tap is a connection of its port for as long as the port lives.
  impl->makePortChannels();
  std::vector<foxglove::Channel> channels{{kStateChannel, "/keel/state", "keel.State", RunModel::snapshotSchema()},
                                          {kFaultsChannel, "/keel/faults", "keel.FaultLogRecord", faultRecordSchema()}};
  for (const auto& p : impl->ports) channels.push_back(p.channel);
  impl->server->advertise(std::move(channels));
  impl->hub = std::thread([raw = impl.get()] { raw->runHub(); });
  return std::unique_ptr<Monitor>(new Monitor(std::move(impl)));
}

Monitor::Monitor(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Monitor::~Monitor() { (void)stop(); }

std::string Monitor::url() const {
  if (!impl_->server) return {};
  const std::string host = impl_->address.find(':') != std::string::npos ? "[" + impl_->address + "]" : impl_->address;
  return fmt::format("http://{}:{}/?token={}", host, impl_->server->port(), impl_->token);
}

Result<void> Monitor::stop() {
  if (impl_->stopping.exchange(true)) return impl_->record_result;
  if (impl_->hub.joinable()) impl_->hub.join();
  impl_->control.stop();
  impl_->server.reset();
  if (impl_->recording) {
    if (auto closed = impl_->recording->close(); !closed && impl_->record_result)
      impl_->record_result = Error{"--record: " + closed.error().message};
  }
  return impl_->record_result;
}

void Monitor::Impl::onServiceCall(const foxglove::ServiceCall& call, std::function<void(ServiceReply)> reply) {
  const json request = json::parse(call.payload, nullptr, false);
  const auto given = request.is_object() ? request.find("token") : request.end();
  if (!request.is_object() || given == request.end() || !given->is_string())
    return reply({false, "token required: open the address keel run printed (with ?token=)"});
  if (!tokenMatches(token, given->get_ref<const std::string&>())) return reply({false, "bad token"});
  const bool emergency = call.service_id == kEmergencyService;
  control.post([this, emergency, reply = std::move(reply)] {
    if (emergency) {
      const auto stopped = engine.emergencyStop("monitor");
      reply({true,
             json{{"ok", true},
                  {"detail", fmt::format("emergency stop latched: {} components stopped in neutral", stopped.size())}}
                 .dump()});
    } else {
      const bool cleared = engine.clearEmergency("monitor");
      reply(
          {true, json{{"ok", cleared}, {"detail", cleared ? "emergency cleared" : "no emergency was latched"}}.dump()});
    }
  });
}

void Monitor::Impl::publishState() {
  const std::int64_t t = std::max(model.lastTime(), engine.log().now());
  last_state = Clock::now();
  send(kStateChannel, t, model.snapshot(t).dump(), Server::Retain::Latest);
}

void Monitor::Impl::send(std::uint32_t channel, std::int64_t t_ns, std::string payload, Server::Retain retain) {
  const auto log_time = static_cast<std::uint64_t>(start_unix_ns + t_ns);
  if (recording) {
    const std::uint16_t to = channel == kStateChannel    ? record_state
                             : channel == kFaultsChannel ? record_faults
                                                         : ports[channel - kFirstPortChannel].record_channel;
    recording->write(to, log_time, payload);
  }
  if (server) server->publish(channel, log_time, std::make_shared<const std::string>(std::move(payload)), retain);
}

void Monitor::Impl::makePortChannels() {
  // The output ports of keel run's own components whose values have a JSON form; a component
  // in a process of its own sends from there (not shown yet).
  for (const auto& instance : engine.instances()) {
    if (!instance.component) continue;
    for (detail::PortBase* base : runtime::coreOf(*instance.component).ports) {
      if (base->direction() != PortDirection::Output || base->kind() == PortKind::Service) continue;
      auto& port = static_cast<detail::OutputPortBase&>(*base);
      const char* type = detail::PortAccess::jsonType(port);
      if (type == nullptr) continue;
      auto tap = std::make_unique<PortTap>(port, kTapCapacity);
      if (!tap->attach()) continue;
      Port p;
      p.channel = {kFirstPortChannel + static_cast<std::uint32_t>(ports.size()),
                   fmt::format("/keel/ports/{}/{}", instance.plan->name, port.name()), "keel.PortValue",
                   portSchema(type)};
      if (recording) {
        p.record_channel = recording->addChannel(p.channel.topic, p.channel.schema_name, p.channel.schema);
        tap->setActive(true);  // a recording has every value
      }
      p.tap = std::move(tap);
      ports.push_back(std::move(p));
    }
  }
}

bool Monitor::Impl::takePortValues() {
  bool taking = false;
  for (auto& p : ports) {
    auto publish = [&](std::int64_t steady_ns, const std::string& value) {
      const std::int64_t t = engine.log().sinceStart(steady_ns);
      send(p.channel.id, t, fmt::format(R"({{"t_ns":{},"value":{}}})", t, value), Server::Retain::Latest);
    };
    if (!recording) {
      const bool wanted = server && server->subscribed(p.channel.id);
      // A first subscriber sees what the port sent last (maybe long ago: a stopped component).
      if (wanted && !p.tap->active()) p.tap->newest(publish);
      p.tap->setActive(wanted);
    }
    p.tap->drain(publish);
    taking |= p.tap->active();
  }
  return taking;
}

void Monitor::Impl::handle(const std::vector<std::string>& lines) {
  bool changed = false;
  for (const auto& line : lines) {
    json record = json::parse(line, nullptr, false);
    if (!record.is_object()) continue;  // not a record (a torn line a killed process left)
    changed |= model.apply(record);
    send(kFaultsChannel, record.value("t_ns", std::int64_t{0}), line, Server::Retain::History);
  }
  if (changed) publishState();
}

void Monitor::Impl::runHub() {
  std::vector<std::string> lines;
  publishState();
  for (;;) {
    const bool last = stopping.load(std::memory_order_acquire);
    lines.clear();
    follower->read(lines);
    handle(lines);
    if (Clock::now() - last_state >= kStateEvery) publishState();
    // A chunk goes out before it is a second old (the hub looks every kWait at the latest):
    // a kill -9 loses at most the last second of the recording.
    if (recording && record_result) {
      const auto soon = Clock::now() + kWait;
      auto flushed = recording->flushIfDue(static_cast<std::uint64_t>(
          std::chrono::duration_cast<std::chrono::nanoseconds>(soon.time_since_epoch()).count()));
      if (!flushed) record_result = Error{"--record: " + flushed.error().message};
    }
    const bool taking = takePortValues();
    if (last) return;  // read once more after stop(): the run's last records go out too
    follower->wait(taking ? kPortWait : kWait);
    // A fault's first records come while its recovery still runs: the monitor's work (and the
    // clients' it wakes) waits until that is over, for a reset (microseconds) at least.
    std::this_thread::sleep_for(kSettle);
  }
}

}  // namespace keel::monitor
