// Test support: runtime hooks and a fault sink that record every state change and fault, for assertions, and
// helpers to name and wire components without profiles.
// Thread-safety: records under a mutex; may be called from executor threads.
#pragma once

#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "fault/rules.hpp"
#include "runtime/component_core.hpp"
#include "runtime/invoke.hpp"

namespace keel::test {

struct StateRecord {
  std::string component;
  State from;
  State to;
};

/// Records, and contains a fault as the fault manager does for a component without rules: a
/// component whose callback could not finish (signal, exception, error code, hang) goes to Error.
class RecordingHooks : public runtime::RunHooks, public runtime::FaultSink {
 public:
  void stateChanged(Component& c, State from, State to) override {
    std::lock_guard lock(mutex_);
    states_.push_back({c.instanceName(), from, to});
  }
  void report(Component& c, const FaultEvent& fault) override {
    {
      std::lock_guard lock(mutex_);
      FaultEvent f = fault;
      if (f.component[0] == '\0') FaultEvent::copyInto(f.component, c.instanceName());
      faults_.push_back(f);
    }
    const bool about_c = fault.componentName().empty() || fault.componentName() == c.instanceName();
    if (about_c && fault::stopsTheComponent(fault.kind) && allowed(c.state(), Transition::Fault))
      runtime::setState(c, State::Error);
  }
  void runPending(Component&) override {}
  void recovered(Component&, std::int64_t) override {}
  std::vector<StateRecord> states() const {
    std::lock_guard lock(mutex_);
    return states_;
  }
  std::vector<FaultEvent> faults() const {
    std::lock_guard lock(mutex_);
    return faults_;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<StateRecord> states_;
  std::vector<FaultEvent> faults_;
};

/// Names `c` and attaches `hooks` as its run hooks and fault sink, as the engine does.
inline void manage(Component& c, const std::string& name, RecordingHooks& hooks) {
  auto& core = runtime::coreOf(c);
  core.instance_name = name;
  core.hooks = &hooks;
  core.fault_sink = &hooks;
}

/// Connects an output port to an input port in-process; the connection is kept in `keep`.
inline void wire(detail::OutputPortBase& out, detail::InputPortBase& in,
                 std::vector<std::unique_ptr<detail::ConnectionBase>>& keep) {
  auto c = in.makeConnection();
  if (!out.attach(*c)) throw std::runtime_error("wire: type mismatch");
  keep.push_back(std::move(c));
}

/// Applies a queue policy and size as the runtime does from the profile.
inline void configureQueue(detail::InputPortBase& in, QueuePolicy policy, std::size_t size) {
  in.configureQueue(policy, size);
}

/// Polls `pred` until true or `timeout` (generous: for behaviour, not for timing).
template <class Pred>
bool eventually(Pred pred, std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
  auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return pred();
}

}  // namespace keel::test
