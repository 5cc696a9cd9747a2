#include "fault/fault_manager_component.hpp"

#include "runtime/injection.hpp"

namespace keel::fault {

ReturnCode FaultManagerComponent::onEvent(InputEventPortBase& port) {
  if (&port != &faults) return ReturnCode::Ok;
  FaultEvent ev = faults.current();
  if (ev.t_ns == 0) ev.t_ns = runtime::steadyNs();  // arrival: the sender gave no time
  manager_.report(*this, ev);
  return ReturnCode::Ok;
}

}  // namespace keel::fault
