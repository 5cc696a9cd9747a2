// /parameter_events as keel run reads it (parameter_events.hpp).
#include "dds/parameter_events.hpp"

#include <dds/dds.h>
#include <fmt/format.h>

#include <algorithm>
#include <mutex>
#include <optional>
#include <set>
#include <utility>

#include "dds/dds_ports.hpp"
#include "dds/qos.hpp"
#include "dds/take.hpp"
#include "dds/type_registry.hpp"
#include "keel/detail/connection.hpp"
#include "keel/msg/rcl_interfaces/msg/parameter_event.hpp"
#include "keel/msg/rcl_interfaces/msg/parameter_type.hpp"

namespace keel::dds {

namespace {

using Type = msg::rcl_interfaces::ParameterType;

/// `value` typed; nothing for no value, a byte array or an unknown type.
std::optional<profile::ParameterValue> valueOf(const msg::rcl_interfaces::ParameterValue& v) {
  switch (v.type) {
    case Type::PARAMETER_BOOL: return v.bool_value;
    case Type::PARAMETER_INTEGER: return v.integer_value;
    case Type::PARAMETER_DOUBLE: return v.double_value;
    case Type::PARAMETER_STRING: return v.string_value;
    case Type::PARAMETER_BOOL_ARRAY: return std::vector<bool>(v.bool_array_value.begin(), v.bool_array_value.end());
    case Type::PARAMETER_INTEGER_ARRAY: return v.integer_array_value;
    case Type::PARAMETER_DOUBLE_ARRAY: return v.double_array_value;
    case Type::PARAMETER_STRING_ARRAY: return v.string_array_value;
    default: return std::nullopt;
  }
}

}  // namespace

profile::ParameterUpdate updateOf(const msg::rcl_interfaces::ParameterEvent& event, std::vector<std::string>& skipped) {
  profile::ParameterUpdate update;
  for (const auto* list : {&event.new_parameters, &event.changed_parameters})
    for (const auto& p : *list) {
      if (p.value.type == Type::PARAMETER_NOT_SET) update.deleted.push_back(p.name);
      else if (auto v = valueOf(p.value)) update.set.emplace_back(p.name, std::move(*v));
      else skipped.push_back(p.name);
    }
  for (const auto& p : event.deleted_parameters) update.deleted.push_back(p.name);
  return update;
}

struct ParameterEvents::State final : detail::Sink<msg::rcl_interfaces::ParameterEvent> {
  State(ParameterWatch& w, runtime::Warn wa) : watch(w), warn(std::move(wa)), connection(this) {}
  ParameterWatch& watch;
  runtime::Warn warn;
  std::vector<WatchedNode> nodes;
  const detail::DdsType* type = nullptr;
  detail::Connection<msg::rcl_interfaces::ParameterEvent> connection;
  dds_entity_t reader = 0;

  std::mutex mutex;                                      // the rest, and the watch's calls
  std::set<std::pair<std::string, std::string>> warned;  // node, parameter: a byte array said once

  // One event (the mutex held: the listener takes it before delivering).
  void deliver(const msg::rcl_interfaces::ParameterEvent& event) override {
    auto named = [&](const WatchedNode& n) {  // by its name, or a standby's (one may serve it)
      return n.name == event.node || std::find(n.aliases.begin(), n.aliases.end(), event.node) != n.aliases.end();
    };
    const bool ours = std::any_of(nodes.begin(), nodes.end(), named);
    if (!ours) return;  // a node keel does not run
    std::vector<std::string> skipped;
    const profile::ParameterUpdate update = updateOf(event, skipped);
    for (const std::string& name : skipped)
      if (warned.emplace(event.node, name).second)
        warn(
            fmt::format("node '{}': parameter '{}' is a byte array (or of a type keel does not know), which a "
                        "params file cannot hold: a restart gives it its value from the profile, or none",
                        event.node, name));
    if (update.set.empty() && update.deleted.empty()) return;
    for (const WatchedNode& n : nodes)
      if (named(n)) watch.parametersChanged(n.instance, update);
  }
};

namespace {

void onEvents(dds_entity_t reader, void* arg) {
  auto* s = static_cast<ParameterEvents::State*>(arg);
  std::lock_guard lock(s->mutex);
  takeAll(reader, [&](const void* sample, const dds_sample_info_t& info) {
    if (!info.valid_data) return;
    try {
      s->type->deliver(sample, s->connection);
    } catch (...) {  // a C callback: nothing may leave it (the conversion could not allocate)
    }
  });
}

}  // namespace

ParameterEvents::ParameterEvents(ParameterWatch& watch, runtime::Warn warn)
    : state_(std::make_unique<State>(watch, std::move(warn))) {}

ParameterEvents::~ParameterEvents() { close(); }

Result<std::int32_t> ParameterEvents::open(std::int32_t participant, std::vector<WatchedNode> nodes) {
  State& s = *state_;
  s.nodes = std::move(nodes);
  s.type = findType("rcl_interfaces/msg/ParameterEvent");
  if (s.type == nullptr) return fail("/parameter_events: rcl_interfaces/msg/ParameterEvent is not linked into keel");
  const auto* descriptor = static_cast<const dds_topic_descriptor_t*>(s.type->descriptor);
  const dds_entity_t topic = dds_create_topic(participant, descriptor, ddsTopicName("/parameter_events").c_str(),
                                              nullptr, nullptr);
  if (topic < 0) return fail(fmt::format("/parameter_events: CycloneDDS refused the topic: {}", dds_strretcode(topic)));
  // Best effort, every sample kept. A reliable reader matched to a Fast DDS writer holds what it
  // receives until the writer's first heartbeat after the match (Fast DDS sends one every 3 s
  // while a sample is unacknowledged): a node's first change after keel's reader matched it would
  // wait up to 3 s, and be lost with the node if it dies meanwhile — the case keel reads it for.
  // Best effort delivers each sample as it comes; on the host's loopback, where keel's nodes
  // run, a sample is lost only when a socket buffer overflows.
  profile::DdsBinding b;
  b.qos = profile::DdsQos::SensorData;
  const Qos qos = qosOf(b);
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_ALL, 0);
  dds_listener_t* listener = dds_create_listener(&s);
  dds_lset_data_available(listener, onEvents);
  const dds_entity_t reader = dds_create_reader(participant, topic, qos.get(), listener);
  dds_delete_listener(listener);
  if (reader < 0)
    return fail(fmt::format("/parameter_events: CycloneDDS refused the reader: {}", dds_strretcode(reader)));
  s.reader = reader;
  onEvents(reader, &s);  // what came before the listener was set
  return reader;
}

void ParameterEvents::close() {
  if (!state_ || state_->reader <= 0) return;
  dds_delete(state_->reader);  // waits for its listener to return
  state_->reader = 0;
}

}  // namespace keel::dds
