#include "dds/safe_commands.hpp"

#include <dds/dds.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <limits>

#include "dds/dds_ports.hpp"
#include "dds/qos.hpp"
#include "dds/type_registry.hpp"
#include "runtime/clock.hpp"

namespace keel::dds {

SafeCommands::~SafeCommands() { stop(); }

Result<void> SafeCommands::open(std::int32_t participant, const std::vector<NodeSafeCommand>& commands) {
  std::string errors;
  const Qos qos = qosOf(profile::DdsBinding{});  // ROS 2's default: reliable, volatile, keep last 10
  for (const NodeSafeCommand& c : commands) {
    const profile::SafeCommand& s = c.command;
    auto problem = [&](const std::string& what) {
      errors += fmt::format("{}: <publish topic=\"{}\"> of node '{}': {}\n", s.where.str(), s.topic, c.instance, what);
    };
    const detail::DdsType* type = findType(s.type);
    if (type == nullptr) {
      problem(fmt::format("type {} is not linked into keel", s.type));
      continue;
    }
    const auto* descriptor = static_cast<const dds_topic_descriptor_t*>(type->descriptor);
    const dds_entity_t topic = dds_create_topic(participant, descriptor, ddsTopicName(s.topic).c_str(), nullptr,
                                                nullptr);
    if (topic < 0) {
      problem(fmt::format("CycloneDDS refused the topic: {}", dds_strretcode(topic)));
      continue;
    }
    const dds_entity_t writer = dds_create_writer(participant, topic, qos.get(), nullptr);
    if (writer < 0) {
      problem(fmt::format("CycloneDDS refused the writer: {}", dds_strretcode(writer)));
      continue;
    }
    Command cmd;
    cmd.instance = c.instance;
    cmd.writer = writer;
    cmd.zero.assign((descriptor->m_size + sizeof(std::uint64_t) - 1) / sizeof(std::uint64_t), 0);
    cmd.period_ns = static_cast<std::int64_t>(1e9 / s.rate_hz);
    commands_.push_back(std::move(cmd));
  }
  if (!commands_.empty()) thread_ = std::thread([this] { run(); });
  if (!errors.empty()) {
    errors.pop_back();
    return fail(errors);
  }
  return {};
}

void SafeCommands::start(const std::string& instance) {
  std::lock_guard lock(mutex_);
  const std::int64_t now = runtime::steadyNs();
  for (Command& c : commands_)
    if (c.instance == instance && c.next_ns == 0) c.next_ns = now;  // the first at once
  changed_.notify_all();
}

void SafeCommands::clear() {
  std::lock_guard lock(mutex_);
  for (Command& c : commands_) c.next_ns = 0;
  changed_.notify_all();
}

void SafeCommands::stop() {
  {
    std::lock_guard lock(mutex_);
    ending_ = true;
    changed_.notify_all();
  }
  if (thread_.joinable()) thread_.join();
}

std::vector<std::int32_t> SafeCommands::writers() const {
  std::vector<std::int32_t> out;
  for (const Command& c : commands_) out.push_back(c.writer);
  return out;
}

void SafeCommands::run() {
  std::unique_lock lock(mutex_);
  while (!ending_) {
    const std::int64_t now = runtime::steadyNs();
    std::int64_t next = std::numeric_limits<std::int64_t>::max();
    for (Command& c : commands_) {
      if (c.next_ns == 0) continue;
      if (c.next_ns <= now) {
        // A zeroed C sample is the type's zero value: numbers 0, strings and sequences empty.
        (void)dds_write(c.writer, c.zero.data());
        c.next_ns = std::max(c.next_ns + c.period_ns, now + 1);  // no burst after a late wake
      }
      next = std::min(next, c.next_ns);
    }
    if (next == std::numeric_limits<std::int64_t>::max()) changed_.wait(lock);
    else changed_.wait_for(lock, std::chrono::nanoseconds(next - runtime::steadyNs()));
  }
}

}  // namespace keel::dds
