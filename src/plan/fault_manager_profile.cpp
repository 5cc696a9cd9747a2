#include "plan/fault_manager_profile.hpp"

namespace keel::plan {

const profile::ComponentProfile& faultManagerProfile() {
  static const profile::ComponentProfile p = [] {
    profile::ComponentProfile cp;
    cp.file = "(keel)";
    cp.name = "keel::FaultManager";
    cp.description = "keel's fault manager";
    cp.execution.type = profile::ExecutionType::Aperiodic;
    profile::EventPort in;
    in.name = "faults";
    in.usage = PortDirection::Input;
    in.data_type = "keel::FaultEvent";
    in.queue_size = 256;
    cp.event_ports.push_back(in);
    return cp;
  }();
  return p;
}

}  // namespace keel::plan
