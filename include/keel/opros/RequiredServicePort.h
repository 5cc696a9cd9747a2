// keel's OPRoS compatibility: RequiredServicePort, the base of a generated XxxRequired port. A
// call goes through keel's required service port of the same name, with the profile's timeout,
// to the connected provider's executor. When it cannot complete (not connected, the provider
// faulted, not active or too slow) the call throws MethodInvokeException, as OPRoS's did for an
// unconnected method; thrown out of a callback, keel handles it as that component's fault.
#pragma once

#include <any>
#include <memory>
#include <string>
#include <utility>

#include "MethodInvokeException.h"
#include "OPRoSTypes.h"
#include "ServicePortInterface.h"
#include "detail/bridge.hpp"
#include "keel/service_port.hpp"

class RequiredServicePort : public ServicePortInterface {
 public:
  RequiredServicePort() = default;
  explicit RequiredServicePort(const std::string& name) : ServicePortInterface(name) {}

  keel::detail::PortBase& keelBind(keel::Component& host) override {
    keel_ = std::make_unique<keel::RequiredServicePort<keel::opros::Reply(keel::opros::Call)>>(&host, getName());
    return *keel_;
  }

  /// Calls `method` of the connected provider with `args`; its result (empty for void).
  std::any keelCall(const std::string& method, std::any args) override {
    if (!keel_) throw MethodInvokeException("service port '" + getName() + "' is not loaded by keel");
    auto r = keel_->call(keel::opros::Call{method, std::move(args)});
    if (!r) throw MethodInvokeException("calling '" + getName() + "." + method + "': " + r.error().message);
    return std::move(*r);
  }

 private:
  std::unique_ptr<keel::RequiredServicePort<keel::opros::Reply(keel::opros::Call)>> keel_;
};
