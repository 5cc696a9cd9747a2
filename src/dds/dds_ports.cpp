// DDS writers and readers for keel's data ports (dds_ports.hpp).
#include "dds/dds_ports.hpp"

#include <dds/dds.h>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <optional>
#include <set>

#include "dds/qos.hpp"
#include "dds/type_registry.hpp"
#include "keel/component.hpp"
#include "keel/msg/rmw_dds_common/msg/participant_entities_info.hpp"
#include "runtime/clock.hpp"

namespace keel::dds {

std::string ddsTopicName(const std::string& topic) { return "rt" + topic; }

std::string ddsTypeName(const std::string& type) {
  const std::size_t a = type.find('/');
  const std::size_t b = type.rfind('/');
  return type.substr(0, a) + "::msg::dds_::" + type.substr(b + 1) + "_";
}

Result<int> effectiveDomain(int domain) {
  const char* env = std::getenv("ROS_DOMAIN_ID");
  if (env == nullptr || *env == '\0') return domain;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(env, &end, 10);
  if (errno != 0 || !std::isdigit(static_cast<unsigned char>(*env)) || *end != '\0' || v > 232)
    return fail(fmt::format("ROS_DOMAIN_ID='{}' is not a DDS domain id (a whole number from 0 to 232)", env));
  return static_cast<int>(v);
}

/// One subscription: the connection its samples go to, and its outage (one fault per outage).
struct DdsPorts::Reader {
  DdsPorts* owner = nullptr;
  const detail::DdsType* type = nullptr;
  detail::ConnectionBase* connection = nullptr;
  profile::DdsBinding binding;
  std::string instance;
  dds_entity_t entity = 0;  // its DDS reader
  std::mutex mutex;         // serialises outages' beginnings and ends; guards held, warned_incompatible
  // The fault id of the outage under way (kNoId: one not reported), 0: none. Atomic so that a
  // sample's arrival checks it without the lock.
  std::atomic<std::uint64_t> outage{0};
  // False while a standby's: samples are dropped, an outage is held, not reported. Written
  // under the mutex, read without it by each sample.
  std::atomic<bool> serving{true};
  std::optional<std::string> held;  // an outage that began while standing by and lasts: why
  bool warned_incompatible = false;
  // A ROS 2 node's output topic: samples of the node's own writers go into its stand-in's
  // output port (not to a connection); others' are dropped. The stand-in changes when an
  // alternative takes the node's place (nodeServedBy).
  bool node = false;
  std::atomic<detail::PortBase*> node_port{nullptr};
  std::atomic<std::int64_t> last_ns{0};  // its last sample of the node's (steady); keel's deadline
  std::atomic<bool> armed{false};        // a sample since the node was quiet: its deadline counts
  std::mutex writers_mutex;
  std::set<dds_instance_handle_t> node_writers;  // writers known to be the node's
  std::set<dds_instance_handle_t> retired;       // the writers of a node an alternative replaced

  /// Whether the writer of a sample (its publication handle) is the node's.
  bool fromNode(dds_entity_t reader, dds_instance_handle_t writer) {
    {
      std::lock_guard lock(writers_mutex);
      if (node_writers.contains(writer)) return true;
      if (retired.contains(writer)) return false;
    }
    dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(reader, writer);
    if (e == nullptr) return false;
    const bool mine = owner->graph_ && owner->graph_->ownedBy(instance, e->participant_key.v);
    dds_builtintopic_free_endpoint(e);
    if (!mine) return false;  // another's, or one not known yet: asked again at its next sample
    std::lock_guard lock(writers_mutex);
    node_writers.insert(writer);
    return true;
  }
  static constexpr std::uint64_t kNoId = std::numeric_limits<std::uint64_t>::max();

  void lost(const std::string& why) {
    if (owner->ending_.load(std::memory_order_acquire)) return;  // keel run's end silenced it
    std::lock_guard lock(mutex);
    if (!serving.load(std::memory_order_relaxed)) {
      held = why;  // the active host reports this outage; the standby only remembers it
      return;
    }
    raise(why);
  }
  /// A peer whose QoS cannot match (it never will): a warning, once.
  static void incompatible(dds_entity_t, dds_requested_incompatible_qos_status_t status, void* arg);
  void back() {
    if (!serving.load(std::memory_order_acquire)) {
      std::lock_guard lock(mutex);
      held.reset();
      return;
    }
    if (outage.load(std::memory_order_acquire) == 0) return;  // every sample asks: no lock then
    std::lock_guard lock(mutex);
    const std::uint64_t id = outage.exchange(0, std::memory_order_acq_rel);
    if (id != 0 && id != kNoId) owner->watch_.peerBack(instance, id, runtime::steadyNs());
  }
  void serve() {
    std::lock_guard lock(mutex);
    serving.store(true, std::memory_order_release);
  }
  void reportHeld() {
    std::lock_guard lock(mutex);
    if (held) raise(*held);
    held.reset();
  }

 private:
  void raise(const std::string& why) {  // the mutex held
    if (outage.load(std::memory_order_relaxed) != 0) return;
    FaultEvent f(FaultKind::Remote, instance, why);
    f.t_ns = runtime::steadyNs();
    const std::uint64_t id = owner->watch_.peerLost(instance, f);
    // Not reported (a node's silence of its own doing): no outage, asked again at the next miss.
    if (id != 0) outage.store(id, std::memory_order_release);
  }
};

namespace {

std::string ms(double v) { return fmt::format("{:g} ms", v); }

void onData(dds_entity_t reader, void* arg) {
  auto* r = static_cast<DdsPorts::Reader*>(arg);
  bool any = false;
  constexpr std::uint32_t kBatch = 16;
  void* samples[kBatch];
  dds_sample_info_t infos[kBatch];
  for (;;) {
    samples[0] = nullptr;  // loaned: no copy out of CycloneDDS's buffers
    const dds_return_t n = dds_take(reader, samples, infos, kBatch, kBatch);
    if (n <= 0) break;
    // A standby's: taken (nothing stale is left for its takeover) and dropped; its active
    // host has them.
    const bool serving = r->serving.load(std::memory_order_acquire);
    for (dds_return_t i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      if (r->node) {
        if (!r->fromNode(reader, infos[i].publication_handle)) continue;
        r->last_ns.store(runtime::steadyNs(), std::memory_order_relaxed);
        r->armed.store(true, std::memory_order_release);
      }
      any = true;
      if (!serving) continue;
      try {
        if (r->node) {
          // A stand-in that is not running (being reset, stopped, a preloaded alternative not
          // yet switched in) takes no value: what its node still says is what made it faulty.
          detail::PortBase& port = *r->node_port.load(std::memory_order_acquire);
          if (port.owner().state() == State::Active) r->type->push(samples[i], port);
        } else {
          r->type->deliver(samples[i], *r->connection);
        }
      } catch (...) {  // a C callback: nothing may leave it (the conversion could not allocate)
      }
    }
    dds_return_loan(reader, samples, n);
  }
  if (any) r->back();
}

void onDeadline(dds_entity_t, const dds_requested_deadline_missed_status_t status, void* arg) {
  auto* r = static_cast<DdsPorts::Reader*>(arg);
  if (status.total_count_change <= 0) return;
  r->lost(fmt::format("no sample on {} within its deadline of {}", r->binding.topic, ms(*r->binding.deadline_ms)));
}

void onLiveliness(dds_entity_t, const dds_liveliness_changed_status_t status, void* arg) {
  auto* r = static_cast<DdsPorts::Reader*>(arg);
  if (status.alive_count == 0 && status.not_alive_count_change > 0) {
    r->lost(r->binding.liveliness_ms ? fmt::format("the writer of {} lost its liveliness (lease {})", r->binding.topic,
                                                   ms(*r->binding.liveliness_ms))
                                     : fmt::format("the writer of {} lost its liveliness", r->binding.topic));
  } else if (status.alive_count_change > 0 && !r->binding.deadline_ms) {
    // A writer alive again ends an outage of liveliness. With a deadline the outage ends with
    // the first sample instead: a writer can be alive long before it writes (a ROS 2 node
    // starting), and the deadline, firing meanwhile, would open a second fault for one outage.
    r->back();
  }
}

}  // namespace

void DdsPorts::Reader::incompatible(dds_entity_t, const dds_requested_incompatible_qos_status_t status, void* arg) {
  auto* r = static_cast<Reader*>(arg);
  {
    std::lock_guard lock(r->mutex);
    if (r->warned_incompatible) return;
    r->warned_incompatible = true;
  }
  r->owner->warn_(fmt::format("{}: <subscribe> of {}.{}: a writer of {} offers an incompatible {} and is not heard",
                              r->binding.where.str(), r->instance, r->binding.endpoint.port, r->binding.topic,
                              policyName(static_cast<dds_qos_policy_id_t>(status.last_policy_id))));
}

DdsPorts::DdsPorts(PeerWatch& watch, runtime::Warn warn) : watch_(watch), warn_(std::move(warn)) {}

DdsPorts::~DdsPorts() { close(); }

Result<std::int32_t> DdsPorts::participant(int domain) {
  const auto domain_id = effectiveDomain(domain);
  if (!domain_id) return domain_id.error();
  const int d = *domain_id;
  if (const auto it = participants_.find(d); it != participants_.end()) return it->second;
  const dds_entity_t made = dds_create_participant(static_cast<dds_domainid_t>(d), nullptr, nullptr);
  if (made < 0) {
    const char* uri = std::getenv("CYCLONEDDS_URI");
    return fail(fmt::format("CycloneDDS could not join domain {}: {} (its configuration: CYCLONEDDS_URI={})", d,
                            dds_strretcode(made), uri ? uri : "unset"));
  }
  participants_.emplace(d, made);
  return made;
}

Result<void> DdsPorts::publishDiagnostics(int domain, DiagnosticsWriter::Snapshot snapshot) {
  const detail::DdsType* type = findType("diagnostic_msgs/msg/DiagnosticArray");
  if (type == nullptr) return fail("/diagnostics: diagnostic_msgs/msg/DiagnosticArray is not linked into keel");
  auto pp = participant(domain);
  if (!pp) return fail("/diagnostics: " + pp.error().message);
  const auto* descriptor = static_cast<const dds_topic_descriptor_t*>(type->descriptor);
  const dds_entity_t topic = dds_create_topic(*pp, descriptor, "rt/diagnostics", nullptr, nullptr);
  if (topic < 0) return fail(fmt::format("/diagnostics: CycloneDDS refused the topic: {}", dds_strretcode(topic)));
  profile::DdsBinding b;  // ROS 2's default QoS, as diagnostic_updater publishes
  const Qos qos = qosOf(b);
  const dds_entity_t writer = dds_create_writer(*pp, topic, qos.get(), nullptr);
  if (writer < 0) return fail(fmt::format("/diagnostics: CycloneDDS refused the writer: {}", dds_strretcode(writer)));
  endpoints_.push_back({*pp, writer, true});
  std::shared_ptr<detail::ByteEnd> outlet = type->make_outlet(writer);
  auto publish = [outlet](const msg::diagnostic_msgs::DiagnosticArray& a) {
    static_cast<detail::Connection<msg::diagnostic_msgs::DiagnosticArray>&>(outlet->connection()).send(a);
  };
  diagnostics_ = std::make_unique<DiagnosticsWriter>(std::move(snapshot), std::move(publish));
  return {};
}

std::string rosNodeName(std::string_view name) {
  std::string out(name);
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  if (out.empty() || out.front() == '_' || std::isdigit(static_cast<unsigned char>(out.front()))) out = "keel_" + out;
  return out;
}

namespace {

msg::rmw_dds_common::Gid gidOf(dds_entity_t entity) {
  msg::rmw_dds_common::Gid gid;
  dds_guid_t guid;
  if (dds_get_guid(entity, &guid) == DDS_RETCODE_OK) std::memcpy(gid.data.data(), guid.v, gid.data.size());
  return gid;
}

}  // namespace

Result<void> DdsPorts::joinGraph(int domain, std::string_view name) {
  const detail::DdsType* type = findType("rmw_dds_common/msg/ParticipantEntitiesInfo");
  if (type == nullptr)
    return fail("the ROS 2 graph: rmw_dds_common/msg/ParticipantEntitiesInfo is not linked into keel");
  if (auto pp = participant(domain); !pp) return fail("the ROS 2 graph: " + pp.error().message);
  const auto* descriptor = static_cast<const dds_topic_descriptor_t*>(type->descriptor);
  profile::DdsBinding b;  // as every rmw writes it: reliable, transient local, keep last 1
  b.qos = profile::DdsQos::TransientLocal;
  const Qos qos = qosOf(b);
  std::lock_guard lock(graph_mutex_);
  graph_name_ = rosNodeName(name);
  for (const auto& [d, participant] : participants_) {
    // Its own name, no "rt/": not a ROS 2 topic but the graph's.
    const dds_entity_t topic = dds_create_topic(participant, descriptor, "ros_discovery_info", nullptr, nullptr);
    if (topic < 0)
      return fail(fmt::format("the ROS 2 graph: CycloneDDS refused ros_discovery_info: {}", dds_strretcode(topic)));
    const dds_entity_t writer = dds_create_writer(participant, topic, qos.get(), nullptr);
    if (writer < 0)
      return fail(fmt::format("the ROS 2 graph: CycloneDDS refused the writer: {}", dds_strretcode(writer)));
    listings_.push_back({participant, type->make_outlet(writer)});
    publishListing(listings_.back());
  }
  return {};
}

void DdsPorts::publishListing(const Listing& l) {
  msg::rmw_dds_common::ParticipantEntitiesInfo info;
  info.gid = gidOf(l.participant);
  msg::rmw_dds_common::NodeEntitiesInfo node;
  node.node_namespace = "/keel";
  node.node_name = graph_name_;
  for (const Endpoint& e : endpoints_) {
    if (e.participant != l.participant) continue;
    (e.writer ? node.writer_gid_seq : node.reader_gid_seq).push_back(gidOf(e.entity));
  }
  info.node_entities_info_seq.push_back(std::move(node));
  static_cast<detail::Connection<msg::rmw_dds_common::ParticipantEntitiesInfo>&>(l.outlet->connection()).send(info);
}

void DdsPorts::renewLifecycleRequests(const std::string& instance, const std::string& name) {
  if (!lifecycles_) return;
  const auto replaced = lifecycles_->renew(instance, name);
  if (replaced.empty()) return;
  std::lock_guard lock(graph_mutex_);
  for (Endpoint& e : endpoints_)
    for (const auto& [before, after] : replaced)
      if (e.entity == before) e.entity = after;
  for (const Listing& l : listings_) publishListing(l);
}

void DdsPorts::close() {
  if (node_timer_.joinable()) {
    {
      std::lock_guard lock(node_timer_mutex_);
      node_timer_ending_ = true;
    }
    node_timer_wake_.notify_all();
    node_timer_.join();
  }
  if (diagnostics_) diagnostics_->stop();             // before its writer goes
  if (node_diagnostics_) node_diagnostics_->close();  // before the graph it asks
  if (lifecycles_) lifecycles_->close();              // so do these
  if (graph_) graph_->close();                        // its watch hears nothing more
  if (parameters_) parameters_->close();              // nor this one
  if (safe_commands_) safe_commands_->stop();         // before its writers go
  // Deleting a participant deletes its topics, writers and readers, and waits for their
  // listeners: no sample is delivered after this. The outlets stay (ports may still hold
  // their connections): a write to a deleted writer fails and is dropped.
  for (const auto& [domain, participant] : participants_) dds_delete(participant);
  participants_.clear();
}

Result<void> DdsPorts::openSafeCommands(int domain, const std::vector<NodeSafeCommand>& commands) {
  if (commands.empty()) return {};
  auto pp = participant(domain);
  if (!pp) return fail("the nodes' safe commands: " + pp.error().message);
  safe_commands_ = std::make_unique<SafeCommands>();
  auto opened = safe_commands_->open(*pp, commands);
  for (const std::int32_t w : safe_commands_->writers()) endpoints_.push_back({*pp, w, true});  // in the graph
  return opened;
}

void DdsPorts::nodeExited(const std::string& instance, pid_t pid, const std::string& who, bool died) {
  // Disarmed here, not only when the timer sees the node quiet: a restart can follow the death
  // within a millisecond, between two of the timer's looks, and the new life is not to be timed
  // from the old one's last sample.
  for (const auto& r : readers_)
    if (r->node && r->instance == instance) r->armed.store(false, std::memory_order_release);
  if (died) writersDied(pid, who);
}

void DdsPorts::nodeServedBy(const std::string& instance,
                            const std::function<detail::PortBase*(const std::string&)>& port) {
  for (const auto& r : readers_) {
    if (!r->node || r->instance != instance) continue;
    detail::PortBase* to = port(r->binding.endpoint.port);
    if (to != nullptr && to->type() == r->type->type) r->node_port.store(to, std::memory_order_release);
    // The replaced node may publish on until the alternative's start ends it: what it still
    // says is not the role's any more (the values that made it faulty, most likely).
    std::lock_guard lock(r->writers_mutex);
    r->retired.merge(r->node_writers);
    r->node_writers.clear();
  }
}

void DdsPorts::writersDied(pid_t pid, const std::string& who) {
  if (!graph_ || pid <= 0) return;
  std::set<pid_t> dead;
  {
    std::lock_guard lock(dead_mutex_);
    dead_.insert(pid);
    dead = dead_;
  }
  for (const auto& r : readers_) {
    if (r->node || r->entity == 0) continue;
    if (!r->binding.deadline_ms && !r->binding.liveliness_ms) continue;  // it does not watch its writers
    std::vector<dds_instance_handle_t> writers(8);
    dds_return_t n = dds_get_matched_publications(r->entity, writers.data(), writers.size());
    if (n > static_cast<dds_return_t>(writers.size())) {
      writers.resize(static_cast<std::size_t>(n));
      n = dds_get_matched_publications(r->entity, writers.data(), writers.size());
    }
    if (n <= 0) continue;
    // A killed writer stays matched until its participant's lease ends: it counts as gone when
    // its process is one keel saw die; one of unknown process counts as alive.
    bool died = false, alive = false;
    for (std::size_t i = 0; i < std::min(writers.size(), static_cast<std::size_t>(n)); ++i) {
      dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(r->entity, writers[i]);
      if (e == nullptr) continue;
      const pid_t p = graph_->pidOf(e->participant_key.v);
      dds_builtintopic_free_endpoint(e);
      if (p == pid) died = true;
      else if (!dead.contains(p)) alive = true;
    }
    if (died && !alive) r->lost(fmt::format("the writer of {} died: {}", r->binding.topic, who));
  }
}

Result<void> DdsPorts::watchNodes(int domain, std::vector<WatchedNode> nodes, GraphWatch& watch) {
  auto pp = participant(domain);
  if (!pp) return fail("the ROS 2 graph: " + pp.error().message);
  graph_ = std::make_unique<Ros2Graph>(watch, warn_);
  if (auto r = graph_->open(*pp, nodes); !r) return r;
  node_diagnostics_ = std::make_unique<NodeDiagnostics>(*graph_, watch);
  return node_diagnostics_->open(*pp, std::move(nodes));
}

Result<void> DdsPorts::readNodeOutputs(int domain, const std::vector<NodeOutput>& outputs) {
  std::string errors;
  auto pp = participant(domain);
  if (!pp) return fail("the nodes' topics: " + pp.error().message);
  for (const NodeOutput& o : outputs) {
    const profile::DdsBinding& b = o.binding;
    auto problem = [&](const std::string& what) {
      errors += fmt::format("{}: output {} of node '{}' ({}): {}\n", b.where.str(), b.endpoint.port, o.instance,
                            b.topic, what);
    };
    const detail::DdsType* type = findType(b.type);
    if (type == nullptr || o.port == nullptr || o.port->type() != type->type) {
      problem(fmt::format("no message type '{}' is linked into this keel", b.type));
      continue;
    }
    const auto* descriptor = static_cast<const dds_topic_descriptor_t*>(type->descriptor);
    const std::string topic_name = ddsTopicName(b.topic);
    const dds_entity_t topic = dds_create_topic(*pp, descriptor, topic_name.c_str(), nullptr, nullptr);
    if (topic < 0) {
      problem(fmt::format("CycloneDDS refused the topic: {}", dds_strretcode(topic)));
      continue;
    }
    auto reader = std::make_unique<Reader>();
    reader->owner = this;
    reader->type = type;
    reader->node = true;
    reader->node_port.store(o.port, std::memory_order_relaxed);
    reader->binding = b;
    reader->instance = o.instance;
    // No deadline or liveliness asked of the writer: a ROS 2 publisher offers none (its
    // default), and a reader asking for one would not match it. keel times the samples.
    profile::DdsBinding asked = b;
    asked.deadline_ms.reset();
    asked.liveliness_ms.reset();
    const Qos qos = qosOf(asked);
    dds_listener_t* listener = dds_create_listener(reader.get());
    dds_lset_data_available(listener, onData);
    dds_lset_requested_incompatible_qos(listener, Reader::incompatible);
    const dds_entity_t made = dds_create_reader(*pp, topic, qos.get(), listener);
    dds_delete_listener(listener);
    if (made < 0) {
      problem(fmt::format("CycloneDDS refused the reader: {}", dds_strretcode(made)));
      continue;
    }
    endpoints_.push_back({*pp, made, false});
    if (b.deadline_ms) timed_.push_back(reader.get());
    readers_.push_back(std::move(reader));
  }
  if (!timed_.empty() && !node_timer_.joinable()) node_timer_ = std::thread([this] { timeNodeOutputs(); });
  if (!errors.empty()) {
    errors.pop_back();
    return fail(errors);
  }
  return {};
}

void DdsPorts::timeNodeOutputs() {
  double shortest = std::numeric_limits<double>::max();
  for (const Reader* r : timed_) shortest = std::min(shortest, *r->binding.deadline_ms);
  // A quarter of the shortest deadline between looks (at least 5 ms): a miss is seen within
  // 125 % of its deadline.
  const auto tick = std::chrono::microseconds(std::max<std::int64_t>(5000, static_cast<std::int64_t>(shortest * 250)));
  std::unique_lock lock(node_timer_mutex_);
  while (!node_timer_wake_.wait_for(lock, tick, [&] { return node_timer_ending_; })) {
    const std::int64_t now = runtime::steadyNs();
    for (Reader* r : timed_) {
      if (watch_.quiet(r->instance)) {  // dead, restarting, not up: counts from its next sample
        r->armed.store(false, std::memory_order_relaxed);
        continue;
      }
      if (!r->armed.load(std::memory_order_acquire)) {
        // No sample of this life yet: due within the time the node has to come up. A node that
        // is up but never publishes would otherwise never miss a deadline.
        if (const std::int64_t due = watch_.firstSampleDue(r->instance); due != 0 && now > due)
          r->lost(fmt::format("no sample on {} since the node started, within its start timeout", r->binding.topic));
        continue;
      }
      const auto deadline_ns = static_cast<std::int64_t>(*r->binding.deadline_ms * 1e6);
      if (now - r->last_ns.load(std::memory_order_relaxed) > deadline_ns)
        r->lost(
            fmt::format("no sample on {} within its deadline of {}", r->binding.topic, ms(*r->binding.deadline_ms)));
    }
  }
}

Result<void> DdsPorts::watchParameters(int domain, std::vector<WatchedNode> nodes, ParameterWatch& watch) {
  auto pp = participant(domain);
  if (!pp) return fail("/parameter_events: " + pp.error().message);
  parameters_ = std::make_unique<ParameterEvents>(watch, warn_);
  auto reader = parameters_->open(*pp, std::move(nodes));
  if (!reader) return reader.error();
  endpoints_.push_back({*pp, *reader, false});  // keel's node subscribes to it, as ROS 2 tools show
  return {};
}

Result<void> DdsPorts::watchLifecycles(int domain, const std::vector<LifecycleNode>& nodes, LifecycleWatch& watch) {
  if (!graph_) return fail("lifecycle nodes: the ROS 2 graph is not watched");
  auto pp = participant(domain);
  if (!pp) return fail("lifecycle nodes: " + pp.error().message);
  lifecycles_ = std::make_unique<LifecycleClients>(watch, *graph_);
  if (auto r = lifecycles_->open(*pp, nodes); !r) return r;
  for (const auto& [e, writer] : lifecycles_->entities())  // keel's node lists its clients' writers and readers
    endpoints_.push_back({*pp, e, writer});
  return {};
}

void DdsPorts::takeOver() {
  for (const auto& r : readers_) r->serve();
}

void DdsPorts::reportHeldOutages() {
  for (const auto& r : readers_) r->reportHeld();
}

Result<void> DdsPorts::open(const std::vector<plan::PlannedDds>& bindings, const FindPort& find, Readers readers) {
  std::string errors;
  auto problem = [&](const profile::DdsBinding& b, const std::string& what) {
    errors += fmt::format("{}: <{}> of {}.{}: {}\n", b.where.str(), b.publish ? "publish" : "subscribe",
                          b.endpoint.component, b.endpoint.port, what);
  };
  std::map<std::pair<std::int32_t, std::string>, dds_entity_t> topics;
  for (const plan::PlannedDds& d : bindings) {
    const profile::DdsBinding& b = d.binding;
    detail::PortBase* port = find(b.endpoint);
    if (port == nullptr) {
      problem(b, "the component's code has no such port");
      continue;
    }
    const detail::DdsType* type = findType(b.type);
    if (type == nullptr) {
      problem(b, fmt::format("no message type '{}' is linked into this keel (keel ships {}; "
                             "keel_add_messages gives others, linked into the component's library)",
                             b.type, fmt::join(typeNames(), ", ")));
      continue;
    }
    if (port->type() != type->type) {
      problem(b, fmt::format("the port's C++ type is '{}', not keel::msg's '{}' that topic {} carries",
                             port->typeName(), b.type, b.topic));
      continue;
    }
    const auto* descriptor = static_cast<const dds_topic_descriptor_t*>(type->descriptor);
    if (ddsTypeName(b.type) != descriptor->m_typename) {
      problem(b, fmt::format("the message code registered '{}' for DDS type '{}'", b.type, descriptor->m_typename));
      continue;
    }
    const auto pp = participant(d.domain);
    if (!pp) {
      problem(b, pp.error().message);
      continue;
    }
    const std::string topic_name = ddsTopicName(b.topic);
    auto& topic = topics[{*pp, topic_name}];
    if (topic == 0) {
      topic = dds_create_topic(*pp, descriptor, topic_name.c_str(), nullptr, nullptr);
      if (topic < 0) {
        problem(b, fmt::format("CycloneDDS refused topic {} ({}): {}", b.topic, topic_name, dds_strretcode(topic)));
        topic = 0;
        continue;
      }
    }
    const Qos qos = qosOf(b, b.publish ? d.redundancy : std::nullopt);
    if (b.publish) {
      const dds_entity_t writer = dds_create_writer(*pp, topic, qos.get(), nullptr);
      if (writer < 0) {
        problem(b, fmt::format("CycloneDDS refused the writer: {}", dds_strretcode(writer)));
        continue;
      }
      endpoints_.push_back({*pp, writer, true});
      auto outlet = type->make_outlet(writer);
      if (!static_cast<detail::OutputPortBase*>(port)->attach(outlet->connection())) {
        problem(b, "the port refused the connection");
        continue;
      }
      wires_.push_back({&outlet->connection(), port, nullptr});
      outlets_.push_back(std::move(outlet));
    } else {
      auto connection = static_cast<detail::InputPortBase*>(port)->makeConnection();
      auto reader = std::make_unique<Reader>();
      reader->owner = this;
      reader->type = type;
      reader->connection = connection.get();
      reader->binding = b;
      reader->instance = b.endpoint.component;
      reader->serving.store(readers == Readers::Serving, std::memory_order_relaxed);
      dds_listener_t* listener = dds_create_listener(reader.get());
      dds_lset_data_available(listener, onData);
      dds_lset_requested_deadline_missed(listener, onDeadline);
      dds_lset_liveliness_changed(listener, onLiveliness);
      dds_lset_requested_incompatible_qos(listener, Reader::incompatible);
      const dds_entity_t made = dds_create_reader(*pp, topic, qos.get(), listener);
      dds_delete_listener(listener);
      if (made < 0) {
        problem(b, fmt::format("CycloneDDS refused the reader: {}", dds_strretcode(made)));
        continue;
      }
      reader->entity = made;
      endpoints_.push_back({*pp, made, false});
      wires_.push_back({connection.get(), nullptr, port});
      inlets_.push_back(std::move(connection));
      readers_.push_back(std::move(reader));
    }
  }
  if (!errors.empty()) {
    close();
    errors.pop_back();
    return fail(errors);
  }
  return {};
}

}  // namespace keel::dds
