// keel's OPRoS compatibility: RequiredMethod<R>, a method a required port calls on its
// connected provider, and makeRequiredMethod. The arguments travel as a std::tuple of the
// decayed types the call site passes (the generated XxxRequired passes its declared ones); the
// provider unpacks them with its own declaration, so a provider whose parameters differ is a
// MethodInvokeException (the service type profiles are checked when the run loads).
#pragma once

#include <any>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "Method.h"
#include "MethodInvokeException.h"
#include "RequiredServicePort.h"

template <class R>
class RequiredMethod : public Method {
 public:
  RequiredMethod(const std::string& name, int arity, int call_type)
      : Method(name, keel::opros::returnTypeName<R>(), arity, call_type) {}

  template <class... A>
  R operator()(A&&... args) {
    return keel::opros::invokePacked<R>(*this, std::forward<A>(args)...);
  }

  /// Forwards the call to the connected provider, through the port it was added to.
  std::any keelInvoke(std::any& args) override {
    if (!keelPort()) throw MethodInvokeException("method '" + getName() + "' belongs to no service port");
    return keelPort()->keelCall(getName(), std::move(args));
  }
};

template <class C, class R, class... P>
Method* makeRequiredMethod(R (C::*f)(P...), const char* name, const int& call_type = METHOD_BLOCKING) {
  (void)f;
  return new RequiredMethod<R>(name, sizeof...(P), call_type);
}
