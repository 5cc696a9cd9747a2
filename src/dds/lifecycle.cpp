// The lifecycle nodes' services and transition events as keel run reaches them (lifecycle.hpp).
#include "dds/lifecycle.hpp"

#include <dds/dds.h>
#include <fmt/format.h>

#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "dds/dds_ports.hpp"
#include "dds/qos.hpp"
#include "dds/take.hpp"
#include "dds/type_registry.hpp"
#include "keel/detail/connection.hpp"
#include "keel/msg/lifecycle_msgs/msg/transition_event.hpp"
#include "keel/msg/lifecycle_msgs/srv/change_state.hpp"
#include "keel/msg/lifecycle_msgs/srv/get_state.hpp"

namespace keel::dds {

namespace {

using msg::lifecycle_msgs::ChangeState_Request;
using msg::lifecycle_msgs::GetState_Request;
using msg::lifecycle_msgs::GetState_Response;
using msg::lifecycle_msgs::TransitionEvent;

/// What a reader's listener converts one sample into: the sample's value, kept for the listener.
template <class T>
struct Last final : detail::Sink<T> {
  Last() : connection(this) {}
  void deliver(const T& v) override { value = v; }
  std::optional<T> value;
  detail::Connection<T> connection;
};

/// The DDS topic of service `service` of node `name` ("/ns/node"): rmw's request ("rq") or
/// reply ("rr") topic, "rq/ns/node/change_stateRequest".
std::string serviceTopic(const std::string& name, const char* service, bool request) {
  return fmt::format("{}{}/{}{}", request ? "rq" : "rr", name, service, request ? "Request" : "Reply");
}

}  // namespace

// One node's writers and readers.
struct Client {
  LifecycleClients::State* owner = nullptr;
  std::string instance;
  std::string name;
  dds_entity_t change_topic = 0;
  dds_entity_t get_topic = 0;
  dds_entity_t change_writer = 0;  // the writers and outlets: guarded by write_mutex
  dds_entity_t get_writer = 0;
  std::unique_ptr<detail::ByteEnd> change_outlet;
  std::unique_ptr<detail::ByteEnd> get_outlet;
  std::mutex write_mutex;  // one request or renewal at a time: an outlet's conversion is not reentrant
  Last<TransitionEvent> event;
  Last<GetState_Response> reply;
};

struct LifecycleClients::State {
  State(LifecycleWatch& w, Ros2Graph& g) : watch(w), graph(g) {}
  LifecycleWatch& watch;
  Ros2Graph& graph;
  const detail::DdsType* event_type = nullptr;
  const detail::DdsType* reply_type = nullptr;
  const detail::DdsType* change_type = nullptr;
  const detail::DdsType* get_type = nullptr;
  dds_entity_t participant = 0;
  Qos requests;  // the requests' QoS: rmw's for services
  std::vector<std::unique_ptr<Client>> clients;
  std::vector<std::pair<dds_entity_t, bool>> entities;  // every writer (true) and reader, deleted by close()
  mutable std::mutex entities_mutex;                    // entities: renew() replaces writers
  std::mutex listener_mutex;                            // one listener at a time: the clients' Last values

  /// Whether the endpoint whose participant GUID is `key` is of the process keel runs as `c`.
  bool nodes(const Client& c, const dds_guid_t& key) {
    const pid_t pid = graph.pidOf(key.v);
    return pid != 0 && watch.runs(c.instance, c.name, pid);
  }
};

namespace {

/// Whether the writer of a sample (`info`) read by `reader` is of `c`'s node's own process.
bool fromNode(LifecycleClients::State& s, const Client& c, dds_entity_t reader, const dds_sample_info_t& info) {
  dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(reader, info.publication_handle);
  if (e == nullptr) return false;
  const bool mine = s.nodes(c, e->participant_key);
  dds_builtintopic_free_endpoint(e);
  return mine;
}

void onEvent(dds_entity_t reader, void* arg) {
  auto* c = static_cast<Client*>(arg);
  LifecycleClients::State& s = *c->owner;
  std::vector<std::pair<std::uint8_t, std::uint8_t>> seen;
  {
    std::lock_guard lock(s.listener_mutex);
    takeAll(reader, [&](const void* sample, const dds_sample_info_t& info) {
      if (!info.valid_data || !fromNode(s, *c, reader, info)) return;
      try {
        s.event_type->deliver(sample, c->event.connection);
      } catch (...) {  // a C callback: nothing may leave it
        return;
      }
      if (c->event.value) seen.emplace_back(c->event.value->start_state.id, c->event.value->goal_state.id);
      c->event.value.reset();
    });
  }
  for (const auto& [start, goal] : seen) s.watch.transitioned(c->instance, c->name, start, goal);
}

void onReply(dds_entity_t reader, void* arg) {
  auto* c = static_cast<Client*>(arg);
  LifecycleClients::State& s = *c->owner;
  std::vector<std::uint8_t> states;
  {
    std::lock_guard lock(s.listener_mutex);
    takeAll(reader, [&](const void* sample, const dds_sample_info_t& info) {
      if (!info.valid_data || !fromNode(s, *c, reader, info)) return;
      try {
        s.reply_type->deliver(sample, c->reply.connection);
      } catch (...) {
        return;
      }
      if (c->reply.value) states.push_back(c->reply.value->current_state.id);
      c->reply.value.reset();
    });
  }
  for (std::uint8_t state : states) s.watch.stateIs(c->instance, c->name, state);
}

/// Whether a participant's GUID is CycloneDDS's: its vendor id (the GUID's first two bytes) 01 10.
bool cyclone(const dds_guid_t& participant) { return participant.v[0] == 0x01 && participant.v[1] == 0x10; }

/// Whether a reader of `writer`'s topic in `c`'s node's own process is matched: Written when one
/// is, Cyclone when the node's is CycloneDDS's, else NotMatched.
LifecycleClients::Sent matchedToNode(LifecycleClients::State& s, const Client& c, dds_entity_t writer) {
  std::vector<dds_instance_handle_t> readers(8);
  dds_return_t n = dds_get_matched_subscriptions(writer, readers.data(), readers.size());
  if (n > static_cast<dds_return_t>(readers.size())) {  // more than room: ask again with room
    readers.resize(static_cast<std::size_t>(n));
    n = dds_get_matched_subscriptions(writer, readers.data(), readers.size());
  }
  for (dds_return_t i = 0; i < n && i < static_cast<dds_return_t>(readers.size()); ++i) {
    dds_builtintopic_endpoint_t* e = dds_get_matched_subscription_data(writer, readers[static_cast<std::size_t>(i)]);
    if (e == nullptr) continue;
    const bool mine = s.nodes(c, e->participant_key);
    const bool theirs = cyclone(e->participant_key);
    dds_builtintopic_free_endpoint(e);
    if (mine) return theirs ? LifecycleClients::Sent::Cyclone : LifecycleClients::Sent::Written;
  }
  return LifecycleClients::Sent::NotMatched;
}

}  // namespace

LifecycleClients::LifecycleClients(LifecycleWatch& watch, Ros2Graph& graph)
    : state_(std::make_unique<State>(watch, graph)) {}

LifecycleClients::~LifecycleClients() { close(); }

Result<void> LifecycleClients::open(std::int32_t participant, const std::vector<LifecycleNode>& nodes) {
  State& s = *state_;
  const detail::DdsType* change_type = s.change_type = findType("lifecycle_msgs/srv/ChangeState_Request");
  const detail::DdsType* get_type = s.get_type = findType("lifecycle_msgs/srv/GetState_Request");
  s.event_type = findType("lifecycle_msgs/msg/TransitionEvent");
  s.reply_type = findType("lifecycle_msgs/srv/GetState_Response");
  if (!change_type || !get_type || !s.event_type || !s.reply_type)
    return fail("lifecycle nodes: the lifecycle_msgs types are not linked into keel");
  s.participant = participant;
  // Requests as rmw's services write them: reliable, volatile, keep last 10. Replies and events
  // best effort (lifecycle.hpp says why).
  s.requests = qosOf(profile::DdsBinding{});
  const Qos& requests = s.requests;
  profile::DdsBinding sensor;
  sensor.qos = profile::DdsQos::SensorData;
  const Qos answers = qosOf(sensor);
  dds_qset_history(answers.get(), DDS_HISTORY_KEEP_ALL, 0);

  std::string errors;
  auto topicOf = [&](const detail::DdsType* type, const std::string& name) -> dds_entity_t {
    const auto* descriptor = static_cast<const dds_topic_descriptor_t*>(type->descriptor);
    return dds_create_topic(participant, descriptor, name.c_str(), nullptr, nullptr);
  };
  for (const LifecycleNode& node : nodes)
    for (const std::string& name : node.names) {
      auto c = std::make_unique<Client>();
      c->owner = &s;
      c->instance = node.instance;
      c->name = name;
      auto made = [&](dds_entity_t e, const std::string& what, bool writer) {
        if (e < 0) {
          errors += fmt::format("node '{}': {}: CycloneDDS refused it: {}\n", node.instance, what, dds_strretcode(e));
          return false;
        }
        std::lock_guard lock(s.entities_mutex);
        s.entities.emplace_back(e, writer);
        return true;
      };
      const std::string change_topic = serviceTopic(name, "change_state", true);
      const std::string get_topic = serviceTopic(name, "get_state", true);
      const std::string reply_topic = serviceTopic(name, "get_state", false);
      const std::string event_topic = ddsTopicName(name + "/transition_event");
      const dds_entity_t change = topicOf(change_type, change_topic);
      const dds_entity_t get = topicOf(get_type, get_topic);
      const dds_entity_t reply = topicOf(s.reply_type, reply_topic);
      const dds_entity_t event = topicOf(s.event_type, event_topic);
      if (change < 0 || get < 0 || reply < 0 || event < 0) {
        errors += fmt::format("node '{}': CycloneDDS refused its lifecycle topics ({})\n", node.instance,
                              dds_strretcode(change < 0  ? change
                                             : get < 0   ? get
                                             : reply < 0 ? reply
                                                         : event));
        continue;
      }
      c->change_topic = change;
      c->get_topic = get;
      c->change_writer = dds_create_writer(participant, change, requests.get(), nullptr);
      if (!made(c->change_writer, change_topic, true)) continue;
      c->get_writer = dds_create_writer(participant, get, requests.get(), nullptr);
      if (!made(c->get_writer, get_topic, true)) continue;
      c->change_outlet = change_type->make_outlet(c->change_writer);
      c->get_outlet = get_type->make_outlet(c->get_writer);
      dds_listener_t* listener = dds_create_listener(c.get());
      dds_lset_data_available(listener, onEvent);
      const dds_entity_t event_reader = dds_create_reader(participant, event, answers.get(), listener);
      dds_lset_data_available(listener, onReply);
      const dds_entity_t reply_reader = dds_create_reader(participant, reply, answers.get(), listener);
      dds_delete_listener(listener);
      if (!made(event_reader, event_topic, false) || !made(reply_reader, reply_topic, false)) continue;
      s.clients.push_back(std::move(c));
    }
  if (!errors.empty()) {
    close();
    errors.pop_back();
    return fail(errors);
  }
  return {};
}

LifecycleClients::Sent LifecycleClients::request(const std::string& instance, const std::string& name,
                                                 std::uint8_t transition) {
  State& s = *state_;
  for (const auto& c : s.clients) {
    if (c->instance != instance || c->name != name) continue;
    std::lock_guard lock(c->write_mutex);
    if (const Sent matched = matchedToNode(s, *c, c->change_writer); matched != Sent::Written) return matched;
    ChangeState_Request r;
    r.transition.id = transition;
    static_cast<detail::Connection<ChangeState_Request>&>(c->change_outlet->connection()).send(r);
    return Sent::Written;
  }
  return Sent::NoSuchNode;
}

LifecycleClients::Sent LifecycleClients::askState(const std::string& instance, const std::string& name) {
  State& s = *state_;
  for (const auto& c : s.clients) {
    if (c->instance != instance || c->name != name) continue;
    std::lock_guard lock(c->write_mutex);
    if (const Sent matched = matchedToNode(s, *c, c->get_writer); matched != Sent::Written) return matched;
    static_cast<detail::Connection<GetState_Request>&>(c->get_outlet->connection()).send(GetState_Request{});
    return Sent::Written;
  }
  return Sent::NoSuchNode;
}

std::vector<std::pair<std::int32_t, std::int32_t>> LifecycleClients::renew(const std::string& instance,
                                                                           const std::string& name) {
  State& s = *state_;
  for (const auto& c : s.clients) {
    if (c->instance != instance || c->name != name) continue;
    std::lock_guard lock(c->write_mutex);
    const dds_entity_t change = dds_create_writer(s.participant, c->change_topic, s.requests.get(), nullptr);
    const dds_entity_t get = dds_create_writer(s.participant, c->get_topic, s.requests.get(), nullptr);
    if (change < 0 || get < 0) {  // the old ones serve on: a replay is less harm than no requests
      if (change >= 0) dds_delete(change);
      if (get >= 0) dds_delete(get);
      return {};
    }
    std::vector<std::pair<std::int32_t, std::int32_t>> replaced{{c->change_writer, change}, {c->get_writer, get}};
    c->change_outlet = s.change_type->make_outlet(change);
    c->get_outlet = s.get_type->make_outlet(get);
    {
      std::lock_guard entities(s.entities_mutex);
      for (auto& [e, writer] : s.entities)
        for (const auto& [before, after] : replaced)
          if (e == before) e = after;
    }
    dds_delete(c->change_writer);
    dds_delete(c->get_writer);
    c->change_writer = change;
    c->get_writer = get;
    return replaced;
  }
  return {};
}

std::vector<std::pair<std::int32_t, bool>> LifecycleClients::entities() const {
  std::lock_guard lock(state_->entities_mutex);
  return state_->entities;
}

void LifecycleClients::close() {
  if (!state_) return;
  std::lock_guard lock(state_->entities_mutex);
  for (const auto& [e, writer] : state_->entities) dds_delete(e);  // a reader's delete waits for its listener
  state_->entities.clear();
  state_->clients.clear();
}

}  // namespace keel::dds
