// keel::FaultEvent and keel::FaultKind: the one fault type every detector produces
// (docs/faults.md).
// Components send FaultEvents through an output event port connected to the fault manager's
// `faults` input, or call Component::raiseFault(). Plain value, fixed size (no allocation), so
// it can be built on a fault path.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace keel {

enum class FaultKind : std::uint8_t {
  Signal,     // SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT inside a callback
  Exception,  // C++ exception out of a callback
  ErrorCode,  // non-Ok return code
  Range,      // validity (signal model) violated on a port
  Model,      // process model / sliding window
  Heartbeat,  // watchdog: callback or executor stopped making progress
  Deadline,   // onExecute overran its deadline
  Vote,       // N-version disagreement
  User,       // raised by a component
  Remote,     // a peer process/host lost
  Process,    // the component's OS process died (<process>): any signal, kill -9, exit
  Start,      // a ROS 2 node did not come up (its topics in the graph) within its start timeout
  Reported,   // a ROS 2 node said so itself: its status on /diagnostics at ERROR
  Lifecycle,  // a managed ROS 2 node's transition failed or timed out, or it fell into an error by itself
};

constexpr std::string_view toString(FaultKind k) {
  switch (k) {
    case FaultKind::Signal: return "signal";
    case FaultKind::Exception: return "exception";
    case FaultKind::ErrorCode: return "error_code";
    case FaultKind::Range: return "range";
    case FaultKind::Model: return "model";
    case FaultKind::Heartbeat: return "heartbeat";
    case FaultKind::Deadline: return "deadline";
    case FaultKind::Vote: return "vote";
    case FaultKind::User: return "user";
    case FaultKind::Remote: return "remote";
    case FaultKind::Process: return "process";
    case FaultKind::Start: return "start";
    case FaultKind::Reported: return "reported";
    case FaultKind::Lifecycle: return "lifecycle";
  }
  return "?";
}

struct FaultEvent {
  FaultKind kind = FaultKind::User;
  std::array<char, 64> component{};  // instance name; empty: the sender itself
  std::array<char, 160> detail{};    // human-readable detail (truncated)
  std::int64_t t_ns = 0;             // when detected (steady clock); 0: on arrival
  /// The measurement a state estimator found inconsistent (a `model` fault of the sensor it
  /// comes from); empty for every other fault.
  std::array<char, 32> measurement{};

  FaultEvent() = default;
  FaultEvent(FaultKind k, std::string_view who, std::string_view what) : kind(k) {
    copyInto(component, who);
    copyInto(detail, what);
  }
  std::string_view componentName() const { return component.data(); }
  std::string_view detailText() const { return detail.data(); }
  std::string_view measurementName() const { return measurement.data(); }

  template <std::size_t N>
  static void copyInto(std::array<char, N>& dst, std::string_view src) {
    const std::size_t n = src.size() < N - 1 ? src.size() : N - 1;
    std::memcpy(dst.data(), src.data(), n);
    dst[n] = '\0';
  }
};

}  // namespace keel
