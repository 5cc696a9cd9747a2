// The out-of-line parts of keel's OPRoS Component (include/keel/opros/Component.h): properties,
// the port registry, OPRoS's own lifecycle calls, EXPORT_VARIABLE and GetResourcePath.
#include <Component.h>
#include <PackageUtil.h>
#include <SymbolService.h>

Component::Component() = default;
// OPRoS's signature, which generated constructors call: not by value.
Component::Component(const std::string& compid) : id_(compid) {}  // NOLINT(modernize-pass-by-value): see above

Component::~Component() {
  // The generated portSetup() allocates service ports with new and never deletes them: OPRoS's
  // base class owned them. (Data and event ports are members of the derived class, destroyed by
  // now: nothing here may touch them, not even to ask their type.)
  for (Port* port : service_ports_) delete port;
}

void Component::setId(std::string id) { id_ = std::move(id); }
std::string Component::getId() { return id_; }

void Component::setProperty(const std::string& name, const std::string& value) { properties_[name] = value; }

std::string& Component::getProperty(const std::string& name) {
  auto it = properties_.find(name);
  if (it != properties_.end()) return it->second;
  missing_.clear();  // a caller may have written into the last one it got
  return missing_;
}

std::map<std::string, std::string>& Component::getPropertyMap() { return properties_; }

ReturnType Component::addPort(const std::string& name, Port* port) {
  if (!port) return OPROS_INPUT_NULL;
  if (name.empty()) return OPROS_BAD_INPUT_PARAMETER;
  for (const auto& [n, p] : ports_)
    if (n == name) return OPROS_PRECONDITION_NOT_MET;
  port->setName(name);
  ports_.emplace_back(name, port);
  if (port->getType() == OPROS_SERVICE) service_ports_.push_back(port);
  return OPROS_SUCCESS;
}

Port* Component::getPort(const std::string& name) {
  for (const auto& [n, p] : ports_)
    if (n == name) return p;
  return nullptr;
}

void Component::portReset() {
  for (const auto& [n, p] : ports_) p->reset();
}

ReturnType Component::transition(ReturnType (Component::*callback)(), LifecycleState to) {
  const ReturnType r = (this->*callback)();
  if (r != OPROS_SUCCESS) {
    error_info_ = r;
    return OPROS_PRECONDITION_NOT_MET;
  }
  status_ = to;
  return OPROS_SUCCESS;
}

ReturnType Component::initialize() {
  if (status_ != OPROS_CS_CREATED) return OPROS_PRECONDITION_NOT_MET;
  return transition(&Component::onInitialize, OPROS_CS_READY);
}
ReturnType Component::start() {
  if (status_ != OPROS_CS_READY && status_ != OPROS_CS_INACTIVE) return OPROS_PRECONDITION_NOT_MET;
  return transition(&Component::onStart, OPROS_CS_ACTIVE);
}
ReturnType Component::stop() {
  if (status_ != OPROS_CS_ACTIVE) return OPROS_PRECONDITION_NOT_MET;
  return transition(&Component::onStop, OPROS_CS_INACTIVE);
}
ReturnType Component::reset() {
  if (ReturnType r = transition(&Component::onReset, status_); r != OPROS_SUCCESS) return r;
  if (ReturnType r = transition(&Component::onInitialize, OPROS_CS_READY); r != OPROS_SUCCESS) return r;
  return transition(&Component::onStart, OPROS_CS_ACTIVE);
}
ReturnType Component::destroy() {
  if (status_ == OPROS_CS_CREATED || status_ == OPROS_CS_DESTROYED) return OPROS_PRECONDITION_NOT_MET;
  return transition(&Component::onDestroy, OPROS_CS_DESTROYED);
}
ReturnType Component::stopOnError() {
  if (status_ != OPROS_CS_ACTIVE) return OPROS_PRECONDITION_NOT_MET;
  return transition(&Component::onError, OPROS_CS_ERROR);
}
ReturnType Component::recover() {
  if (status_ != OPROS_CS_ERROR) return OPROS_PRECONDITION_NOT_MET;
  return transition(&Component::onRecover, OPROS_CS_READY);
}
LifecycleState Component::getStatus() { return status_; }
ReturnType Component::getErrorInfo() { return error_info_; }

ReturnType Component::onInitialize() { return OPROS_SUCCESS; }
ReturnType Component::onStart() { return OPROS_SUCCESS; }
ReturnType Component::onStop() { return OPROS_SUCCESS; }
ReturnType Component::onReset() { return OPROS_SUCCESS; }
ReturnType Component::onError() { return OPROS_SUCCESS; }
ReturnType Component::onRecover() { return OPROS_SUCCESS; }
ReturnType Component::onDestroy() { return OPROS_SUCCESS; }
ReturnType Component::onEvent(Event* evt) {
  (void)evt;
  return OPROS_SUCCESS;
}
ReturnType Component::onExecute() { return OPROS_SUCCESS; }
ReturnType Component::onUpdated() { return OPROS_SUCCESS; }
ReturnType Component::onPeriodChanged() { return OPROS_SUCCESS; }

void Component::critical(void* addr, int len) {
  if (!addr || len <= 0) return;
  for (auto& [a, n] : critical_)
    if (a == addr) {
      n = static_cast<std::size_t>(len);  // registered again (onInitialize once more): the new size
      return;
    }
  critical_.emplace_back(addr, static_cast<std::size_t>(len));
}

ReturnType Component::keelExport(const std::string& name, SymbolObject* symbol) {
  if (!symbol) return OPROS_INPUT_NULL;
  symbols_[name].reset(symbol);
  return OPROS_SUCCESS;
}

ReturnType symbolservice_exportSymbol(Component* component, const std::string& name, SymbolObject* symbol) {
  if (!component) {
    delete symbol;
    return OPROS_INPUT_NULL;
  }
  return component->keelExport(name, symbol);
}

std::string opros_package_getResPath(Component* component) {
  return component ? component->keelResourcePath() : std::string();
}
