#include "fault/fault_manager.hpp"

#include "runtime/component_core.hpp"
#include "runtime/injection.hpp"
#include "runtime/invoke.hpp"

namespace keel::fault {
namespace {

/// Kinds after which the component cannot simply go on: it is put in Error.
bool stopsTheComponent(FaultKind k) {
  return k == FaultKind::Signal || k == FaultKind::Exception || k == FaultKind::ErrorCode ||
         k == FaultKind::Heartbeat;
}

}  // namespace

FaultManager::FaultManager(FaultLog& log, std::function<Component*(std::string_view)> find)
    : log_(log), find_(std::move(find)) {}

void FaultManager::onFault(Component& reporter, const FaultEvent& fault, std::string_view detector) {
  const std::int64_t detected = fault.t_ns ? fault.t_ns : steadyNowNs();
  Component* accused = &reporter;
  if (fault.component[0] != '\0' && fault.componentName() != reporter.instanceName()) {
    if (Component* c = find_(fault.componentName())) accused = c;
  }
  auto& core = runtime::coreOf(*accused);
  core.faults.fetch_add(1, std::memory_order_relaxed);
  const std::string who = fault.component[0] ? std::string(fault.componentName()) : accused->instanceName();

  // The injection this detection answers: one that manifested in the accused component, or a
  // corrupted value being pushed on this very thread (caught on delivery by the receiver).
  detail::ComponentCore* source = &core;
  std::uint64_t id = core.injected_id.exchange(0, std::memory_order_acq_rel);
  if (id == 0 && runtime::injectionInFlight()) {
    source = runtime::injectionInFlight();
    id = source->injected_id.exchange(0, std::memory_order_acq_rel);
  }
  std::int64_t injected = 0;
  if (id != 0) {
    injected = source->injected_t_ns.load(std::memory_order_acquire);
    log_.write({{"event", "injected"}, {"fault_id", id}, {"component", who},
                {"t_ns", log_.sinceStart(injected)}});
  } else {
    id = nextId();
  }
  if (stopsTheComponent(fault.kind) && allowed(accused->state(), Transition::Fault))
    runtime::setState(*accused, State::Error);
  const std::string kind(toString(fault.kind));
  log_.write({{"event", "detected"},
              {"fault_id", id},
              {"component", who},
              {"kind", kind},
              {"detail", fault.detailText()},
              {"detector", detector.empty() ? reporter.instanceName() : std::string(detector)},
              {"t_ns", log_.sinceStart(detected)}});
  std::lock_guard lock(mutex_);
  detections_.push_back({id, who, fault.kind, detected, injected});
  detection_count_.store(detections_.size(), std::memory_order_release);
  for (auto& fc : counts_) {
    if (fc.component == who && fc.kind == kind) {
      ++fc.count;
      return;
    }
  }
  counts_.push_back({who, kind, std::string(fault.detailText()), 1});
}

std::vector<FaultCount> FaultManager::counts() const {
  std::lock_guard lock(mutex_);
  return counts_;
}

std::vector<Detection> FaultManager::detections() const {
  std::lock_guard lock(mutex_);
  return detections_;
}

void FaultManager::flushUndetected(const std::vector<Component*>& components) {
  for (Component* c : components) {
    auto& core = runtime::coreOf(*c);
    std::uint64_t id = core.injected_id.exchange(0, std::memory_order_acq_rel);
    if (id == 0) continue;
    log_.write({{"event", "injected"}, {"fault_id", id}, {"component", c->instanceName()},
                {"t_ns", log_.sinceStart(core.injected_t_ns.load())}, {"detected", false}});
  }
}

}  // namespace keel::fault
