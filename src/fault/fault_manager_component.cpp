#include "fault/fault_manager_component.hpp"

#include "runtime/injection.hpp"

namespace keel::fault {

ReturnCode FaultManagerComponent::onEvent(InputEventPortBase& port) {
  if (&port != &faults) return ReturnCode::Ok;
  FaultEvent ev = faults.current();
  if (ev.t_ns == 0) ev.t_ns = runtime::steadyNs();  // arrival: the sender gave no time
  manager_.onFault(*this, ev);
  return ReturnCode::Ok;
}

const profile::ComponentProfile& FaultManagerComponent::profile() {
  static const profile::ComponentProfile p = [] {
    profile::ComponentProfile cp;
    cp.file = "(keel)";
    cp.name = "keel::FaultManager";
    cp.description = "keel's fault manager";
    cp.execution.type = profile::ExecutionType::Aperiodic;
    profile::EventPort in;
    in.name = "faults";
    in.usage = profile::Usage::Input;
    in.data_type = "keel::FaultEvent";
    in.queue_size = 256;
    cp.event_ports.push_back(in);
    return cp;
  }();
  return p;
}

}  // namespace keel::fault
