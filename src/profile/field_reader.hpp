// Typed readers for profile fields that report a bad value as a diagnostic naming what was
// read, why it is wrong and the offending text ("<queue_size> of data port 'range' must be a
// positive integer, got '-3'"). Used by every profile parser.
// Thread-safety: functions of their arguments; the Ctx belongs to one load() call.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "profile/values.hpp"
#include "profile/xml_reader.hpp"

namespace keel::profile::detail {

/// A finite number > 0 (periods, timeouts in ms).
std::optional<double> readPositive(Ctx& ctx, pugi::xml_node at, std::string_view text, std::string_view what);

/// An integer >= 1 (queue sizes).
std::optional<std::size_t> readCount(Ctx& ctx, pugi::xml_node at, std::string_view text, std::string_view what);

/// An integer in [lo, hi].
std::optional<int> readIntIn(Ctx& ctx, pugi::xml_node at, std::string_view text, std::string_view what, int lo, int hi);

/// fifo and rr need a real-time priority (1..99); other takes 0 ("do not change") or more.
/// `what` names the priority ("<priority> of component 'x'"), `owner` its owner.
void checkRealtimePriority(Ctx& ctx, pugi::xml_node at, SchedPolicy policy, int priority, bool given,
                           std::string_view what, std::string_view owner);

/// true/false/1/0.
std::optional<bool> readBool(Ctx& ctx, pugi::xml_node at, std::string_view text, std::string_view what);

/// One of the words of `table`, case-insensitive.
template <class E>
std::optional<E> readWord(Ctx& ctx, pugi::xml_node at, std::string_view text, std::string_view what,
                          const std::vector<std::pair<std::string_view, E>>& table) {
  auto value = parseWord(text, table);
  if (!value) {
    ctx.error(at, fmt::format("{} must be one of {}, got '{}'", what, wordList(table), text));
  }
  return value;
}

// The enum vocabularies of profiles (docs/profiles.md), first spelling of each value is the
// documented one.
const std::vector<std::pair<std::string_view, ExecutionType>>& executionTypes();
/// OPRoS's periodic types that say how the thread is shared (the others: Sharing::Default).
const std::vector<std::pair<std::string_view, Sharing>>& executionSharing();
const std::vector<std::pair<std::string_view, SchedPolicy>>& schedPolicies();
const std::vector<std::pair<std::string_view, PortDirection>>& usages();
const std::vector<std::pair<std::string_view, ServiceUsage>>& serviceUsages();
const std::vector<std::pair<std::string_view, QueuePolicy>>& queuePolicies();
const std::vector<std::pair<std::string_view, PortKind>>& portTypes();
const std::vector<std::pair<std::string_view, Severity>>& severities();
const std::vector<std::pair<std::string_view, Scope>>& scopes();
/// ROS 2's QoS profiles by name (docs/dds.md#qos).
const std::vector<std::pair<std::string_view, DdsQos>>& ddsQosNames();
/// Fault kinds (docs/faults.md): the keys of FaultPolicy::severity_by_kind.
const std::vector<std::pair<std::string_view, std::string_view>>& faultKinds();

std::string_view name(PortKind t);
std::string_view name(PortDirection u);
std::string_view name(ServiceUsage u);
std::string_view name(SchedPolicy p);
std::string_view name(RootKind k);

}  // namespace keel::profile::detail
