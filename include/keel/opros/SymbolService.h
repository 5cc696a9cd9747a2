// keel's OPRoS compatibility: EXPORT_VARIABLE(name, member) exports a member variable under a
// name, as OPRoS's symbol service did for its monitoring tools (the profile's <exports>). keel
// records each export (its name, type and address: Component::keelSymbols()); it neither
// serves nor checkpoints them — a component's checkpointed state is what it registers with
// critical() (Component.h).
#pragma once

#include <string>

#include "OPRoSTypes.h"
#include "ReturnType.h"
#include "keel/type_name.hpp"

class Component;

/// One exported variable.
class SymbolObject {
 public:
  SymbolObject(void* address, std::string type_name) : address_(address), type_name_(std::move(type_name)) {}
  virtual ~SymbolObject() = default;
  void* address() const { return address_; }
  const std::string& typeName() const { return type_name_; }

 private:
  void* address_;
  std::string type_name_;
};

template <class T>
SymbolObject* makeSymbolObject(T* variable) {
  return new SymbolObject(static_cast<void*>(variable), keel::typeName<T>());
}

/// Records `symbol` (owned by `component` from then on) under `name`.
ReturnType symbolservice_exportSymbol(Component* component, const std::string& name, SymbolObject* symbol);

#define EXPORT_VARIABLE(name, variable) symbolservice_exportSymbol(this, name, makeSymbolObject(&(variable)))
