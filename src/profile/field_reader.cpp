// Typed, reporting field readers and the enum vocabularies; see field_reader.hpp.
#include "profile/field_reader.hpp"

namespace keel::profile::detail {

std::optional<double> readPositive(Ctx& ctx, pugi::xml_node at, std::string_view text, std::string_view what) {
  const auto value = parseDouble(text);
  if (!value || *value <= 0.0) {
    ctx.error(at, fmt::format("{} must be a positive number, got '{}'", what, text));
    return std::nullopt;
  }
  return value;
}

std::optional<std::size_t> readCount(Ctx& ctx, pugi::xml_node at, std::string_view text, std::string_view what) {
  const auto value = parseInt(text);
  if (!value || *value < 1) {
    ctx.error(at, fmt::format("{} must be a positive integer, got '{}'", what, text));
    return std::nullopt;
  }
  return static_cast<std::size_t>(*value);
}

std::optional<int> readIntIn(Ctx& ctx, pugi::xml_node at, std::string_view text, std::string_view what, int lo,
                             int hi) {
  const auto value = parseInt(text);
  if (!value || *value < lo || *value > hi) {
    ctx.error(at, fmt::format("{} must be an integer from {} to {}, got '{}'", what, lo, hi, text));
    return std::nullopt;
  }
  return static_cast<int>(*value);
}

void checkRealtimePriority(Ctx& ctx, pugi::xml_node at, SchedPolicy policy, int priority, bool given,
                           std::string_view what, std::string_view owner) {
  if (policy == SchedPolicy::Other || priority >= 1) return;
  if (given) {
    ctx.error(at, fmt::format("{} must be from 1 to 99 with policy {}, got '{}'", what, name(policy), priority));
  } else {
    ctx.error(at, fmt::format("policy {} of {} needs a priority from 1 to 99", name(policy), owner));
  }
}

std::optional<bool> readBool(Ctx& ctx, pugi::xml_node at, std::string_view text, std::string_view what) {
  const auto value = parseBool(text);
  if (!value) ctx.error(at, fmt::format("{} must be true or false, got '{}'", what, text));
  return value;
}

const std::vector<std::pair<std::string_view, ExecutionType>>& executionTypes() {
  static const std::vector<std::pair<std::string_view, ExecutionType>> t = {
      {"periodic", ExecutionType::Periodic},
      {"aperiodic", ExecutionType::Aperiodic},
      {"passive", ExecutionType::Passive},
      {"periodic-shared", ExecutionType::Periodic},     // OPRoS
      {"periodic-exclusive", ExecutionType::Periodic},  // OPRoS
      {"non-periodic", ExecutionType::Aperiodic}};      // OPRoS, with a warning
  return t;
}

const std::vector<std::pair<std::string_view, Sharing>>& executionSharing() {
  static const std::vector<std::pair<std::string_view, Sharing>> t = {{"periodic-shared", Sharing::Shared},
                                                                      {"periodic-exclusive", Sharing::Exclusive}};
  return t;
}

const std::vector<std::pair<std::string_view, SchedPolicy>>& schedPolicies() {
  static const std::vector<std::pair<std::string_view, SchedPolicy>> t = {
      {"other", SchedPolicy::Other},       {"fifo", SchedPolicy::Fifo},       {"rr", SchedPolicy::RoundRobin},
      {"sched_other", SchedPolicy::Other}, {"sched_fifo", SchedPolicy::Fifo}, {"sched_rr", SchedPolicy::RoundRobin}};
  return t;
}

const std::vector<std::pair<std::string_view, PortDirection>>& usages() {
  static const std::vector<std::pair<std::string_view, PortDirection>> t = {{"input", PortDirection::Input},
                                                                            {"output", PortDirection::Output}};
  return t;
}

const std::vector<std::pair<std::string_view, ServiceUsage>>& serviceUsages() {
  static const std::vector<std::pair<std::string_view, ServiceUsage>> t = {{"provided", ServiceUsage::Provided},
                                                                           {"required", ServiceUsage::Required}};
  return t;
}

const std::vector<std::pair<std::string_view, QueuePolicy>>& queuePolicies() {
  static const std::vector<std::pair<std::string_view, QueuePolicy>> t = {{"FIFO", QueuePolicy::Fifo},
                                                                          {"UFIFO", QueuePolicy::UFifo},
                                                                          {"LIFO", QueuePolicy::Lifo},
                                                                          {"LAST", QueuePolicy::Last}};
  return t;
}

const std::vector<std::pair<std::string_view, PortKind>>& portTypes() {
  static const std::vector<std::pair<std::string_view, PortKind>> t = {
      {"data", PortKind::Data},
      {"event", PortKind::Event},
      {"service", PortKind::Service},
      {"method", PortKind::Service}};  // OPRoS tools write "method" for service ports
  return t;
}

const std::vector<std::pair<std::string_view, Severity>>& severities() {
  static const std::vector<std::pair<std::string_view, Severity>> t = {{"ignore", Severity::Ignore},
                                                                       {"reset", Severity::Reset},
                                                                       {"stop", Severity::Stop},
                                                                       {"emergency", Severity::Emergency}};
  return t;
}

const std::vector<std::pair<std::string_view, Scope>>& scopes() {
  static const std::vector<std::pair<std::string_view, Scope>> t = {{"component", Scope::Component},
                                                                    {"executor", Scope::Executor},
                                                                    {"composite", Scope::Composite},
                                                                    {"system", Scope::System}};
  return t;
}

const std::vector<std::pair<std::string_view, DdsQos>>& ddsQosNames() {
  static const std::vector<std::pair<std::string_view, DdsQos>> t = {{"default", DdsQos::Default},
                                                                     {"sensor_data", DdsQos::SensorData},
                                                                     {"reliable", DdsQos::Reliable},
                                                                     {"transient_local", DdsQos::TransientLocal}};
  return t;
}

const std::vector<std::pair<std::string_view, std::string_view>>& faultKinds() {
  static const std::vector<std::pair<std::string_view, std::string_view>> t = {
      {"signal", "signal"},     {"exception", "exception"}, {"error_code", "error_code"}, {"range", "range"},
      {"model", "model"},       {"heartbeat", "heartbeat"}, {"deadline", "deadline"},     {"vote", "vote"},
      {"user", "user"},         {"remote", "remote"},       {"process", "process"},       {"start", "start"},
      {"reported", "reported"}, {"lifecycle", "lifecycle"}};
  return t;
}

std::string_view name(PortKind t) {
  switch (t) {
    case PortKind::Data: return "data";
    case PortKind::Event: return "event";
    case PortKind::Service: return "service";
  }
  return "?";
}

std::string_view name(PortDirection u) { return u == PortDirection::Input ? "input" : "output"; }

std::string_view name(ServiceUsage u) { return u == ServiceUsage::Provided ? "provided" : "required"; }

std::string_view name(SchedPolicy p) {
  switch (p) {
    case SchedPolicy::Other: return "other";
    case SchedPolicy::Fifo: return "fifo";
    case SchedPolicy::RoundRobin: return "rr";
  }
  return "?";
}

std::string_view name(RootKind k) {
  switch (k) {
    case RootKind::Component: return "component_profile";
    case RootKind::Composite: return "composite_component_profile";
    case RootKind::Package: return "package_profile";
    case RootKind::System: return "system_profile";
    case RootKind::ServiceType: return "service_port_type_profile";
    case RootKind::DataType: return "data_type";
    case RootKind::EngineConfig: return "system_config";
    case RootKind::Node: return "ros2_node_profile";
  }
  return "?";
}

}  // namespace keel::profile::detail
