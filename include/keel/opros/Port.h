// keel's OPRoS compatibility: Port, the base of every OPRoS port class (data, event, service).
// A component registers its ports with addPort(name, port) in its constructor; when keel loads
// the component it gives each port a keel port of the same name, kind and type (keelBind), and
// OPRoS's port calls go through it: keel's queues, range checks, connections, fault handling.
// Thread-safety: as the port classes; bound once, before the component starts.
#pragma once

#include <string>

#include "OPRoSTypes.h"
#include "ReturnType.h"
#include "detail/bridge.hpp"

namespace keel::detail {
class PortBase;
}

class Component;

class Port {
 public:
  Port() = default;
  explicit Port(const PortType& type) : type_(type) {}
  Port(const std::string& name, const PortType& type) : name_(name), type_(type) {}
  virtual ~Port() = default;
  Port(const Port&) = delete;
  Port& operator=(const Port&) = delete;

  virtual std::string& getName() { return name_; }
  virtual void setName(const std::string& name) { name_ = name; }
  virtual PortType getType() { return type_; }
  /// Empties what the port holds (queued values).
  virtual void reset() = 0;

  // ---- keel's side (not OPRoS API): called by keel's host of the component ----
  /// Creates this port's keel port, owned by `host`, named getName().
  virtual keel::detail::PortBase& keelBind(keel::Component& host) = 0;
  /// An input event port: keel delivered an event to it; runs the callback or onEvent.
  virtual ReturnType keelDeliver(::Component& owner) {
    (void)owner;
    return OPROS_SUCCESS;
  }
  /// An input data port whose constructor fixed its queue (OPRoS's policy and limit): true,
  /// with them. keel uses the code's queue, as OPRoS did, and warns when the profile differs.
  virtual bool keelCodeQueue(DataPortPolicy& policy, unsigned int& limit) const {
    (void)policy, (void)limit;
    return false;
  }

 protected:
  std::string name_;
  PortType type_ = OPROS_DATA;
};
