// keel's OPRoS compatibility: the untyped side of an output data port.
#pragma once

#include "OPRoSTypes.h"
#include "Port.h"
#include "ReturnType.h"

class OutputDataPortInterface : public Port {
 public:
  OutputDataPortInterface() : Port(OPROS_DATA) {}
  explicit OutputDataPortInterface(const std::string& name) : Port(name, OPROS_DATA) {}

  /// Sends the value held in `data` (of the port's type) to every connected input.
  virtual ReturnType push(opros_any& data) = 0;
};
