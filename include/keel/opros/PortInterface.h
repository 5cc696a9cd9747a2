// keel's OPRoS compatibility: PortInterface, the port registry of an OPRoS Component.
#pragma once

#include <string>

#include "Port.h"
#include "ReturnType.h"

class PortInterface {
 public:
  virtual ~PortInterface() = default;
  /// Registers `port` under `name` (the name the profile's <ports> and connections use).
  virtual ReturnType addPort(const std::string& name, Port* port) = 0;
  virtual Port* getPort(const std::string& name) = 0;
  /// Empties every port's queue.
  virtual void portReset() = 0;
};
