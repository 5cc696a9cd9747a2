// The ROS 2 graph as keel run sees it (ros2_graph.hpp).
#include "dds/ros2_graph.hpp"

#include <dds/dds.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cstring>
#include <map>
#include <mutex>
#include <set>

#include "dds/dds_ports.hpp"
#include "dds/qos.hpp"
#include "dds/take.hpp"
#include "dds/type_registry.hpp"
#include "keel/detail/connection.hpp"
#include "keel/msg/rmw_dds_common/msg/participant_entities_info.hpp"

namespace keel::dds {

namespace {

using Guid = std::array<std::uint8_t, 16>;

Guid guidOf(const dds_guid_t& g) {
  Guid out;
  std::memcpy(out.data(), g.v, out.size());
  return out;
}

/// A participant's GUID prefix (its first 12 bytes), as the rmws and Fast DDS's tools print it.
std::string prefixText(const Guid& g) {
  std::string out;
  for (std::size_t i = 0; i < 12; ++i) out += fmt::format("{:02x}", g[i]);
  return out;
}

/// The participant an entity belongs to: the same prefix, entity id 0x000001c1.
Guid participantOf(const Guid& entity) {
  Guid p = entity;
  p[12] = 0;
  p[13] = 0;
  p[14] = 1;
  p[15] = 0xc1;
  return p;
}

/// Property `name` of `qos` ("" when absent).
std::string property(const dds_qos_t* qos, const char* name) {
  char* value = nullptr;
  if (qos == nullptr || !dds_qget_prop(qos, name, &value) || value == nullptr) return {};
  std::string out(value);
  dds_free(value);
  return out;
}

pid_t pidIn(const std::string& text) {
  pid_t pid = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), pid);
  return ec == std::errc() && end == text.data() + text.size() && pid > 0 ? pid : 0;
}

struct Participant {
  pid_t pid = 0;
  std::string host;
};

}  // namespace

struct Ros2Graph::State final : detail::Sink<msg::rmw_dds_common::ParticipantEntitiesInfo> {
  State(GraphWatch& w, runtime::Warn wa) : watch(w), warn(std::move(wa)), connection(this) {}
  GraphWatch& watch;
  runtime::Warn warn;
  std::vector<WatchedNode> nodes;
  const detail::DdsType* info_type = nullptr;
  detail::Connection<msg::rmw_dds_common::ParticipantEntitiesInfo> connection;
  std::vector<dds_entity_t> readers;

  std::mutex mutex;                                        // the rest, and the watch's calls
  std::map<Guid, Participant> participants;                // alive ones, by GUID
  std::map<Guid, std::pair<Guid, std::string>> writers;    // alive writers: participant, DDS topic
  std::map<Guid, std::set<std::string>> listed;            // participant → the node names it lists
  std::map<std::string, std::vector<NodeSighting>> shown;  // by instance: what the watch was told
  bool reporting = false;                                  // once open() has read what DDS held

  // Sample of ros_discovery_info (the mutex held: the listener takes it before delivering).
  void deliver(const msg::rmw_dds_common::ParticipantEntitiesInfo& info) override {
    std::set<std::string>& names = listed[info.gid.data];
    names.clear();
    for (const auto& n : info.node_entities_info_seq)
      names.insert(n.node_namespace == "/" ? "/" + n.node_name : n.node_namespace + "/" + n.node_name);
  }

  /// Tells the watch of each node whose sightings changed (the mutex held).
  void report() {
    if (!reporting) return;
    for (const WatchedNode& node : nodes) {
      // The participants that list its name, and those that publish one of its topics: a
      // listing comes late when a Fast DDS node starts (a heartbeat after the match, 3 s), its
      // writers at once; its supervisor knows its process by the participant's pid.
      std::set<Guid> candidates;
      for (const auto& [guid, names] : listed)
        if (node.listedIn(names)) candidates.insert(guid);
      std::set<std::string> dds_topics;
      for (const std::string& topic : node.outputs) dds_topics.insert(ddsTopicName(topic));
      for (const auto& [writer, where] : writers)
        if (dds_topics.contains(where.second)) candidates.insert(where.first);
      std::vector<NodeSighting> now;
      for (const Guid& guid : candidates) {
        const auto p = participants.find(guid);
        if (p == participants.end()) continue;  // not discovered yet, or gone
        NodeSighting s;
        s.participant = prefixText(guid);
        s.pid = p->second.pid;
        s.host = p->second.host;
        const auto names = listed.find(guid);
        s.listed = names != listed.end() && node.listedIn(names->second);
        for (const std::string& topic : node.outputs) {
          const std::string dds_topic = ddsTopicName(topic);
          const bool published = std::any_of(writers.begin(), writers.end(), [&](const auto& w) {
            return w.second.first == guid && w.second.second == dds_topic;
          });
          if (!published) s.missing.push_back(topic);
        }
        now.push_back(std::move(s));
      }
      // Its first report, even of nothing: the watch then knows the graph is watched.
      if (const auto before = shown.find(node.instance); before != shown.end() && before->second == now) continue;
      shown[node.instance] = now;
      watch.nodeSeen(node.instance, now);
    }
  }
};

namespace {

void onParticipant(dds_entity_t reader, void* arg) {
  auto* s = static_cast<Ros2Graph::State*>(arg);
  std::lock_guard lock(s->mutex);
  takeAll(reader, [&](const void* sample, const dds_sample_info_t& info) {
    const auto* p = static_cast<const dds_builtintopic_participant_t*>(sample);
    const Guid guid = guidOf(p->key);
    if (info.instance_state != DDS_IST_ALIVE) {  // left: cleanly, or its lease expired
      s->participants.erase(guid);
      s->listed.erase(guid);
      return;
    }
    if (!info.valid_data) return;
    Participant& known = s->participants[guid];
    // CycloneDDS announces __Pid and __Hostname; Fast DDS fastdds.physical_data.*.
    std::string pid = property(p->qos, "__Pid");
    if (pid.empty()) pid = property(p->qos, "fastdds.physical_data.process");
    known.pid = pidIn(pid);
    known.host = property(p->qos, "__Hostname");
    if (known.host.empty()) known.host = property(p->qos, "fastdds.physical_data.host");
  });
  s->report();
}

void onPublication(dds_entity_t reader, void* arg) {
  auto* s = static_cast<Ros2Graph::State*>(arg);
  std::lock_guard lock(s->mutex);
  takeAll(reader, [&](const void* sample, const dds_sample_info_t& info) {
    const auto* e = static_cast<const dds_builtintopic_endpoint_t*>(sample);
    const Guid guid = guidOf(e->key);
    if (info.instance_state != DDS_IST_ALIVE) {
      s->writers.erase(guid);
      return;
    }
    if (!info.valid_data || e->topic_name == nullptr) return;
    s->writers[guid] = {participantOf(guid), e->topic_name};
  });
  s->report();
}

void onDiscoveryInfo(dds_entity_t reader, void* arg) {
  auto* s = static_cast<Ros2Graph::State*>(arg);
  std::lock_guard lock(s->mutex);
  takeAll(reader, [&](const void* sample, const dds_sample_info_t& info) {
    if (!info.valid_data) return;
    try {
      s->info_type->deliver(sample, s->connection);
    } catch (...) {  // a C callback: nothing may leave it (the conversion could not allocate)
    }
  });
  s->report();
}

}  // namespace

Ros2Graph::Ros2Graph(GraphWatch& watch, runtime::Warn warn) : state_(std::make_unique<State>(watch, std::move(warn))) {}

Ros2Graph::~Ros2Graph() { close(); }

Result<void> Ros2Graph::open(std::int32_t participant, std::vector<WatchedNode> nodes) {
  State& s = *state_;
  s.nodes = std::move(nodes);
  s.info_type = findType("rmw_dds_common/msg/ParticipantEntitiesInfo");
  if (s.info_type == nullptr)
    return fail("the ROS 2 graph: rmw_dds_common/msg/ParticipantEntitiesInfo is not linked into keel");
  auto made = [&](dds_entity_t reader, const char* what) -> Result<void> {
    if (reader < 0)
      return fail(
          fmt::format("the ROS 2 graph: CycloneDDS refused the reader of {}: {}", what, dds_strretcode(reader)));
    s.readers.push_back(reader);
    return {};
  };
  auto listener = [&](void (*on)(dds_entity_t, void*)) {
    dds_listener_t* l = dds_create_listener(&s);
    dds_lset_data_available(l, on);
    return l;
  };
  // Samples that come before the three readers exist are kept; nothing is reported until then.
  dds_listener_t* lp = listener(onParticipant);
  const dds_entity_t participants = dds_create_reader(participant, DDS_BUILTIN_TOPIC_DCPSPARTICIPANT, nullptr, lp);
  dds_delete_listener(lp);
  if (auto r = made(participants, "DCPSParticipant"); !r) return r;
  dds_listener_t* lw = listener(onPublication);
  const dds_entity_t publications = dds_create_reader(participant, DDS_BUILTIN_TOPIC_DCPSPUBLICATION, nullptr, lw);
  dds_delete_listener(lw);
  if (auto r = made(publications, "DCPSPublication"); !r) return r;
  // As the rmws read it: reliable, transient local, every sample (the topic has no key: one
  // instance for all participants).
  const auto* descriptor = static_cast<const dds_topic_descriptor_t*>(s.info_type->descriptor);
  const dds_entity_t topic = dds_create_topic(participant, descriptor, "ros_discovery_info", nullptr, nullptr);
  if (topic < 0)
    return fail(fmt::format("the ROS 2 graph: CycloneDDS refused ros_discovery_info: {}", dds_strretcode(topic)));
  profile::DdsBinding b;
  b.qos = profile::DdsQos::TransientLocal;
  const Qos qos = qosOf(b);
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_ALL, 0);
  dds_listener_t* li = listener(onDiscoveryInfo);
  const dds_entity_t info = dds_create_reader(participant, topic, qos.get(), li);
  dds_delete_listener(li);
  if (auto r = made(info, "ros_discovery_info"); !r) return r;
  {
    std::lock_guard lock(s.mutex);
    s.reporting = true;
  }
  // What the readers held before their listeners were set, and the first report of each node.
  onParticipant(participants, &s);
  onPublication(publications, &s);
  onDiscoveryInfo(info, &s);
  return {};
}

bool Ros2Graph::ownedBy(const std::string& instance, const std::uint8_t* participant) {
  State& s = *state_;
  Guid guid;
  std::memcpy(guid.data(), participant, guid.size());
  std::lock_guard lock(s.mutex);
  const auto node = std::find_if(s.nodes.begin(), s.nodes.end(), [&](const auto& n) { return n.instance == instance; });
  const auto p = s.participants.find(guid);
  if (node == s.nodes.end() || p == s.participants.end()) return false;  // not discovered yet: not known to be
  const auto names = s.listed.find(guid);
  const bool listed = names != s.listed.end() && node->listedIn(names->second);
  return s.watch.ownsParticipant(instance, p->second.pid, listed);
}

pid_t Ros2Graph::pidOf(const std::uint8_t* participant) {
  State& s = *state_;
  Guid guid;
  std::memcpy(guid.data(), participant, guid.size());
  std::lock_guard lock(s.mutex);
  const auto p = s.participants.find(guid);
  return p == s.participants.end() ? 0 : p->second.pid;
}

void Ros2Graph::close() {
  if (!state_) return;
  // Deleting a reader waits for its listener to return.
  for (const dds_entity_t r : state_->readers) dds_delete(r);
  state_->readers.clear();
}

}  // namespace keel::dds
