// Faults found by ports (the signal model of paper §5.1.2): a value outside the port's
// <validity> is a `range` fault of the port's owner, detected in the same call that pushed or
// delivered it. The detail names the port, the value and the bounds.
#include "keel/detail/validity.hpp"
#include "runtime/component_core.hpp"
#include "runtime/fault_detail.hpp"
#include "runtime/injection.hpp"
#include "runtime/invoke.hpp"

void keel::detail::reportRange(Component& owner, const std::string& port, const Violation& v, bool on_delivery) {
  FaultEvent ev;
  ev.kind = FaultKind::Range;
  ev.t_ns = runtime::steadyNs();
  FaultEvent::copyInto(ev.component, runtime::coreOf(owner).instance_name);
  const char* where = on_delivery ? "received on" : "pushed on";
  if (v.size_expected != 0)
    runtime::formatDetail(ev, "{} port '{}': {} elements, validity expects {}", where, port, v.size_got,
                          v.size_expected);
  else if (v.array)
    runtime::formatDetail(ev, "value {} {} port '{}'[{}] outside [{}, {}]", v.value, where, port, v.index, v.min,
                          v.max);
  else runtime::formatDetail(ev, "value {} {} port '{}' outside [{}, {}]", v.value, where, port, v.min, v.max);
  runtime::reportFault(owner, ev);
}
