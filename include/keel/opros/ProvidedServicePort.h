// keel's OPRoS compatibility: ProvidedServicePort, the base of a generated XxxProvided port. Its
// methods are called through keel's provided service port of the same name: on this
// component's own executor, serialised with its other callbacks; an exception or crash inside
// is this component's fault (the caller's call fails).
#pragma once

#include <memory>
#include <string>

#include "OPRoSTypes.h"
#include "ServicePortInterface.h"
#include "detail/bridge.hpp"
#include "keel/service_port.hpp"

class ProvidedServicePort : public ServicePortInterface {
 public:
  ProvidedServicePort() = default;
  explicit ProvidedServicePort(const std::string& name) : ServicePortInterface(name) {}

  keel::detail::PortBase& keelBind(keel::Component& host) override {
    keel_ = std::make_unique<keel::ProvidedServicePort<keel::opros::Reply(keel::opros::Call)>>(
        &host, getName(), [this](keel::opros::Call call) -> keel::opros::Reply {
          Method* m = getMethod(call.method);
          if (!m) throw MethodInvokeException("service port '" + getName() + "' has no method '" + call.method + "'");
          return m->keelInvoke(call.args);
        });
    return *keel_;
  }

 private:
  std::unique_ptr<keel::ProvidedServicePort<keel::opros::Reply(keel::opros::Call)>> keel_;
};
