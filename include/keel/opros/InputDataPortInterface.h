// keel's OPRoS compatibility: the untyped side of an input data port.
#pragma once

#include "OPRoSTypes.h"
#include "Port.h"

class InputDataPortInterface : public Port {
 public:
  InputDataPortInterface() : Port(OPROS_DATA) {}
  explicit InputDataPortInterface(const std::string& name) : Port(name, OPROS_DATA) {}

  /// The next value (a new opros_any the caller deletes), or NULL when none is queued.
  virtual opros_any* pop() = 0;
  /// The value pop() would return, left queued; owned by the port, valid until the next call.
  virtual opros_any* peek() = 0;
  /// How many values are queued.
  virtual int getSize() = 0;
};
