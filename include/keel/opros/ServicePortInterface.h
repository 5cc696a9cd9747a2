// keel's OPRoS compatibility: ServicePortInterface, a service port's methods by name. The port
// owns the methods added to it.
#pragma once

#include <any>
#include <map>
#include <memory>
#include <string>

#include "Method.h"
#include "OPRoSTypes.h"
#include "Port.h"
#include "ReturnType.h"

class ServicePortInterface : public Port {
 public:
  ServicePortInterface() : Port(OPROS_SERVICE) {}
  explicit ServicePortInterface(const std::string& name) : Port(name, OPROS_SERVICE) {}

  /// Adds `method` under `name`; the port owns it. A second method of the same name is refused.
  virtual ReturnType addMethod(const std::string& name, Method* method) {
    if (!method) return OPROS_INPUT_NULL;
    if (methods_.count(name)) {
      delete method;
      return OPROS_PRECONDITION_NOT_MET;
    }
    method->keelSetPort(this);
    methods_.emplace(name, std::unique_ptr<Method>(method));
    return OPROS_SUCCESS;
  }
  virtual Method* getMethod(const std::string& name) {
    auto it = methods_.find(name);
    return it == methods_.end() ? nullptr : it->second.get();
  }
  void reset() override {}

  /// A required port: calls `method` of the connected provider with `args` and gives its result
  /// (RequiredServicePort). A provided port calls nobody.
  virtual std::any keelCall(const std::string& method, std::any args) {
    (void)args;
    throw MethodInvokeException("service port '" + getName() + "' provides '" + method + "': it calls nobody");
  }

  /// The methods by name (keel: checked against the service type profile).
  const std::map<std::string, std::unique_ptr<Method>>& keelMethods() const { return methods_; }

 private:
  std::map<std::string, std::unique_ptr<Method>> methods_;
};
