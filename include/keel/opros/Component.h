// keel's OPRoS compatibility: Component, the base class of a component written for OPRoS.
// Sources written for OPRoS compile against it unchanged and run under keel with every fault
// mechanism keel has (docs/opros.md, "OPRoS component sources"). An OPRoS library exports
// getComponent()/releaseComponent(); keel creates the object through them and hosts it in a
// keel component of the same instance name, which calls the callbacks below on keel's
// executors: all callbacks of one component serialised, as for keel's own components.
//
// What keel adds, beside OPRoS's API: critical(addr, len) (Ahn et al.'s checkpointed memory).
// Thread-safety: the callbacks run on the component's own executor, one at a time.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "Event.h"
#include "LifecycleInterface.h"
#include "OPRoSTypes.h"
#include "Port.h"
#include "PortInterface.h"
#include "PropertyInterface.h"
#include "ReturnType.h"

class SymbolObject;

class Component : public PropertyInterface, public LifecycleInterface, public PortInterface {
 public:
  Component();
  explicit Component(const std::string& compid);
  ~Component() override;
  Component(const Component&) = delete;
  Component& operator=(const Component&) = delete;

  virtual void setId(std::string id);
  virtual std::string getId();

  // ---- properties (PropertyInterface) ----
  void setProperty(const std::string& name, const std::string& value) override;
  std::string& getProperty(const std::string& name) override;
  std::map<std::string, std::string>& getPropertyMap() override;

  // ---- ports (PortInterface) ----
  ReturnType addPort(const std::string& name, Port* port) override;
  Port* getPort(const std::string& name) override;
  void portReset() override;

  // ---- lifecycle (LifecycleInterface), OPRoS's meaning ----
  ReturnType initialize() override;
  ReturnType start() override;
  ReturnType stop() override;
  ReturnType reset() override;
  ReturnType destroy() override;
  ReturnType stopOnError() override;
  ReturnType recover() override;
  LifecycleState getStatus() override;
  ReturnType getErrorInfo() override;

  // ---- callbacks run for every event, cycle and period change ----
  /// An event arrived on an input event port bound with setOwner(this) and no callback.
  virtual ReturnType onEvent(Event* evt);
  virtual ReturnType onExecute();
  virtual ReturnType onUpdated();
  virtual ReturnType onPeriodChanged();

  // ---- keel's side (not OPRoS API) ----
  /// The folder GetResourcePath() returns (the component profile's folder + "res/").
  void keelSetResourcePath(std::string path) { resource_path_ = std::move(path); }
  const std::string& keelResourcePath() const { return resource_path_; }
  /// Sets the status getStatus() reports (keel's runtime drives the lifecycle).
  void keelSetStatus(LifecycleState s) { status_ = s; }
  /// The ports addPort registered, in registration order.
  const std::vector<std::pair<std::string, Port*>>& keelPorts() const { return ports_; }
  /// Memory registered with critical(), in registration order.
  const std::vector<std::pair<void*, std::size_t>>& keelCritical() const { return critical_; }
  /// Variables exported with EXPORT_VARIABLE, by name.
  const std::map<std::string, std::unique_ptr<SymbolObject>>& keelSymbols() const { return symbols_; }
  /// Records an exported variable (EXPORT_VARIABLE); takes ownership.
  ReturnType keelExport(const std::string& name, SymbolObject* symbol);

 protected:
  // The lifecycle callbacks. Each succeeds by default (as keel's do); a code other than
  // OPROS_SUCCESS is a fault of the component, handled by its fault policy.
  ReturnType onInitialize() override;
  ReturnType onStart() override;
  ReturnType onStop() override;
  ReturnType onReset() override;
  ReturnType onError() override;
  ReturnType onRecover() override;
  ReturnType onDestroy() override;

  /// keel (Ahn et al. §5.3.1): `len` bytes at `addr` are checkpointed at cycle boundaries and
  /// restored when the component is reset or replaced. Call it from onInitialize.
  void critical(void* addr, int len);

 private:
  friend class keel::opros::Adapter;
  ReturnType transition(ReturnType (Component::*callback)(), LifecycleState to);

  std::string id_;
  std::map<std::string, std::string> properties_;
  std::string missing_;  // what getProperty returns for a property the component does not have
  std::string resource_path_;
  std::vector<std::pair<std::string, Port*>> ports_;
  std::vector<Port*> service_ports_;  // owned: generated code makes them with new
  std::vector<std::pair<void*, std::size_t>> critical_;
  std::map<std::string, std::unique_ptr<SymbolObject>> symbols_;
  LifecycleState status_ = OPROS_CS_CREATED;
  ReturnType error_info_ = OPROS_SUCCESS;
};

/// The name a 2010 KITECH export block uses for Component (it was in no published header).
typedef Component IComponent;
