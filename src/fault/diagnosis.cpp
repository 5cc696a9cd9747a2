#include "fault/diagnosis.hpp"

#include <algorithm>
#include <mutex>

#include "fault/escalation.hpp"
#include "log/fault_log.hpp"
#include "runtime/component_core.hpp"
#include "runtime/injection.hpp"

namespace keel::fault {

using runtime::coreOf;

namespace {

/// The injection this detection answers: one that manifested in the accused component, or a
/// corrupted value being pushed on this very thread (caught on delivery by the receiver).
void attributeInjection(FaultReport& r, detail::ComponentCore& core, FaultIds& ids) {
  detail::ComponentCore* source = &core;
  std::uint64_t id = core.injection.injected_id.exchange(0, std::memory_order_acq_rel);
  if (id == 0 && runtime::injectionInFlight()) {
    source = runtime::injectionInFlight();
    id = source->injection.injected_id.exchange(0, std::memory_order_acq_rel);
  }
  if (id != 0) r.injected_ns = source->injection.injected_t_ns.load(std::memory_order_acquire);
  r.id = id != 0 ? id : ids.next();
}

/// The component a fault event names, as its reporter names it: a monitor or voter inside a
/// composite names its siblings (its author cannot know the composite's instance name), so the
/// name is looked up in the reporter's composite first, then in each enclosing one, then as
/// written (qualified from the top: an application's `navigation.planner`). Composed on the
/// stack: no allocation on the fault path.
Component* named(const Component& reporter, std::string_view name,
                 const std::function<Component*(std::string_view)>& find) {
  const std::string_view self = reporter.instanceName();
  char qualified[2 * sizeof(FaultEvent{}.component)];
  for (std::size_t dot = self.rfind('.'); dot != std::string_view::npos; dot = self.rfind('.', dot - 1)) {
    if (dot + 1 + name.size() > sizeof qualified) continue;
    std::copy_n(self.data(), dot + 1, qualified);
    std::copy_n(name.data(), name.size(), qualified + dot + 1);
    if (Component* c = find(std::string_view(qualified, dot + 1 + name.size()))) return c;
    if (dot == 0) break;
  }
  return find(name);
}

}  // namespace

FaultReport diagnose(Component& reporter, const FaultEvent& fault, std::string_view detector,
                     const std::function<Component*(std::string_view)>& find, FaultIds& ids, bool recoverable) {
  const std::int64_t detected = fault.t_ns ? fault.t_ns : runtime::steadyNs();
  Component* accused = &reporter;
  if (fault.component[0] != '\0' && fault.componentName() != reporter.instanceName()) {
    if (Component* c = named(reporter, fault.componentName(), find)) accused = c;
  }
  auto& core = coreOf(*accused);

  FaultReport r;
  r.event = fault;
  r.event.t_ns = detected;
  // The records name the accused by its full instance name: the component the event names, or
  // when that is unknown, the reporter (it reported a fault of nothing that runs).
  FaultEvent::copyInto(r.event.component, accused->instanceName());
  FaultEvent::copyInto(r.detector, detector.empty() ? std::string_view(reporter.instanceName()) : detector);
  r.accused = accused;
  attributeInjection(r, core, ids);
  // Counted before the accused goes to Error, so that whoever sees the Error (keel's
  // /diagnostics) sees its fault too, before the records are written.
  core.fault.last_id.store(r.id, std::memory_order_relaxed);
  core.fault.last_kind.store(static_cast<std::uint8_t>(fault.kind), std::memory_order_relaxed);
  core.fault.last_ns.store(detected, std::memory_order_relaxed);
  core.faults.fetch_add(1, std::memory_order_release);

  auto* h = static_cast<ComponentHandling*>(core.fault.handling);
  const Rules no_rules;
  const Rules& rules = h ? h->rules : no_rules;
  r.has_policy = rules.has_policy;
  r.scope = rules.scope;
  FirstStep first = firstStep(rules, fault.kind, false, false);
  if (h && first.step != Step::Ignore) {
    std::lock_guard lock(h->mutex);
    first = firstStep(rules, fault.kind, h->busy, h->stopped);
    // OPRoS's lifecycle: a component whose transition failed is in Error and leaves it only
    // by being destroyed. A reset would start what never initialized, or restart what stops,
    // and a replacement would too: such a fault is contained (a fault stop) instead, and an
    // emergency stays an emergency (an actuator whose onStop failed).
    if (!recoverable && (first.step == Step::Reset || first.step == Step::Replace)) first.step = Step::Stop;
    if (first.step != Step::Done) h->busy = true;  // this fault's handling owns the role now
  }
  r.severity = first.severity;
  r.first = r.next = first.step;
  if (first.step == Step::Done) r.add(ActionKind::Ignore, true, detected, "{}", first.why);
  return r;
}

}  // namespace keel::fault
