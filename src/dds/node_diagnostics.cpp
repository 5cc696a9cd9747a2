// What ROS 2 nodes say of themselves on /diagnostics (node_diagnostics.hpp).
#include "dds/node_diagnostics.hpp"

#include <dds/dds.h>
#include <fmt/format.h>

#include <algorithm>

#include "dds/dds_ports.hpp"
#include "dds/qos.hpp"
#include "dds/take.hpp"
#include "dds/type_registry.hpp"
#include "keel/detail/connection.hpp"
#include "keel/msg/diagnostic_msgs/msg/diagnostic_array.hpp"

namespace keel::dds {

struct NodeDiagnostics::State final : detail::Sink<msg::diagnostic_msgs::DiagnosticArray> {
  State(Ros2Graph& g, GraphWatch& w) : graph(g), watch(w), connection(this) {}
  Ros2Graph& graph;
  GraphWatch& watch;
  std::vector<WatchedNode> nodes;  // those that name a status of their own
  const detail::DdsType* type = nullptr;
  detail::Connection<msg::diagnostic_msgs::DiagnosticArray> connection;
  dds_entity_t reader = 0;
  const std::uint8_t* writer_participant = nullptr;  // the sample being delivered's

  void deliver(const msg::diagnostic_msgs::DiagnosticArray& array) override {
    for (const WatchedNode& n : nodes)
      for (const auto& status : array.status) {
        if (status.name != n.diagnostics) continue;
        if (!graph.ownedBy(n.instance, writer_participant)) break;  // another's: any node may use any name
        const bool error = status.level == msg::diagnostic_msgs::DiagnosticStatus::ERROR;
        watch.nodeReported(n.instance, error, fmt::format("{}: {}", status.name, status.message));
      }
  }
};

namespace {

void onDiagnostics(dds_entity_t reader, void* arg) {
  auto* s = static_cast<NodeDiagnostics::State*>(arg);
  takeAll(reader, [&](const void* sample, const dds_sample_info_t& info) {
    if (!info.valid_data) return;
    dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(reader, info.publication_handle);
    if (e == nullptr) return;  // a writer gone already: whose it was is not known
    s->writer_participant = e->participant_key.v;
    try {
      s->type->deliver(sample, s->connection);
    } catch (...) {  // a C callback: nothing may leave it (the conversion could not allocate)
    }
    s->writer_participant = nullptr;
    dds_builtintopic_free_endpoint(e);
  });
}

}  // namespace

NodeDiagnostics::NodeDiagnostics(Ros2Graph& graph, GraphWatch& watch) : state_(std::make_unique<State>(graph, watch)) {}

NodeDiagnostics::~NodeDiagnostics() { close(); }

Result<void> NodeDiagnostics::open(std::int32_t participant, std::vector<WatchedNode> nodes) {
  State& s = *state_;
  for (auto& n : nodes)
    if (!n.diagnostics.empty()) s.nodes.push_back(std::move(n));
  if (s.nodes.empty()) return {};
  s.type = findType("diagnostic_msgs/msg/DiagnosticArray");
  if (s.type == nullptr) return fail("/diagnostics: diagnostic_msgs/msg/DiagnosticArray is not linked into keel");
  const auto* descriptor = static_cast<const dds_topic_descriptor_t*>(s.type->descriptor);
  const dds_entity_t topic = dds_create_topic(participant, descriptor, "rt/diagnostics", nullptr, nullptr);
  if (topic < 0) return fail(fmt::format("/diagnostics: CycloneDDS refused the topic: {}", dds_strretcode(topic)));
  profile::DdsBinding b;
  b.qos = profile::DdsQos::SensorData;  // best effort: matches a reliable writer too
  b.depth = 100;
  const Qos qos = qosOf(b);
  dds_listener_t* listener = dds_create_listener(&s);
  dds_lset_data_available(listener, onDiagnostics);
  s.reader = dds_create_reader(participant, topic, qos.get(), listener);
  dds_delete_listener(listener);
  if (s.reader < 0) {
    const dds_return_t r = s.reader;
    s.reader = 0;
    return fail(fmt::format("/diagnostics: CycloneDDS refused the reader: {}", dds_strretcode(r)));
  }
  return {};
}

void NodeDiagnostics::close() {
  if (state_ && state_->reader > 0) dds_delete(state_->reader);  // waits for its listener
  if (state_) state_->reader = 0;
}

}  // namespace keel::dds
