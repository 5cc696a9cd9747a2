// keel's OPRoS compatibility: LifecycleInterface, OPRoS's lifecycle calls and callbacks. Under
// keel, keel's runtime drives the lifecycle (its states are OPRoS's) and calls the on*
// callbacks itself; the engine-side calls (initialize(), start(), ...) keep OPRoS's meaning for
// code that calls them on a component object of its own.
#pragma once

#include "OPRoSTypes.h"
#include "ReturnType.h"

class LifecycleInterface {
 public:
  virtual ~LifecycleInterface() = default;

  virtual ReturnType initialize() = 0;   // Created → Ready: onInitialize
  virtual ReturnType start() = 0;        // Ready, Inactive → Active: onStart
  virtual ReturnType stop() = 0;         // Active → Inactive: onStop
  virtual ReturnType reset() = 0;        // → Active: onReset, onInitialize, onStart
  virtual ReturnType destroy() = 0;      // → Destroyed: onDestroy
  virtual ReturnType stopOnError() = 0;  // Active → Error: onError
  virtual ReturnType recover() = 0;      // Error → Ready: onRecover
  virtual LifecycleState getStatus() = 0;
  /// The code the last failing callback returned.
  virtual ReturnType getErrorInfo() = 0;

 protected:
  virtual ReturnType onInitialize() = 0;
  virtual ReturnType onStart() = 0;
  virtual ReturnType onStop() = 0;
  virtual ReturnType onReset() = 0;
  virtual ReturnType onError() = 0;
  virtual ReturnType onRecover() = 0;
  virtual ReturnType onDestroy() = 0;
};
