// The kinds that the profile, the plan, the runtime and the tools all name: a port's kind,
// direction and queue policy, a task's scheduling policy. One type each, from the XML to the
// thread (their spellings in profiles are the profile layer's: src/profile/field_reader.hpp).
// Authors never name this header. Thread-safety: plain values.
#pragma once

#include <string_view>

namespace keel {

enum class PortKind { Data, Event, Service };
/// Service ports: Provided = Input, Required = Output.
enum class PortDirection { Input, Output };
/// OPRoS queueing policies of an input data port.
enum class QueuePolicy { Fifo, UFifo, Lifo, Last };
/// A task's scheduling policy: SCHED_OTHER, SCHED_FIFO, SCHED_RR.
enum class SchedPolicy { Other, Fifo, RoundRobin };

constexpr std::string_view toString(PortKind k) {
  return k == PortKind::Data ? "data" : k == PortKind::Event ? "event" : "service";
}

}  // namespace keel
