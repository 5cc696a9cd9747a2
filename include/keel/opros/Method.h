// keel's OPRoS compatibility: Method, one named method of a service port. The generated port
// headers make them with makeProvidedMethod / makeRequiredMethod, reinterpret_cast the result
// to ProvidedMethod<R>* / RequiredMethod<R>* and call it: those derive from Method alone, so
// the pointer needs no adjustment.
#pragma once

#include <any>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "MethodInvokeException.h"
#include "OPRoSTypes.h"
#include "keel/type_name.hpp"

#define METHOD_BLOCKING 1
#define METHOD_NONBLOCKING 2

class ServicePortInterface;

class Method {
 public:
  Method(const std::string& name, std::string return_type, int arity, int call_type)
      : name_(name), return_type_(std::move(return_type)), arity_(arity), call_type_(call_type) {}
  virtual ~Method() = default;
  Method(const Method&) = delete;
  Method& operator=(const Method&) = delete;

  virtual std::string& getName() { return name_; }
  virtual std::string& getReturnType() { return return_type_; }
  virtual int getArity() { return arity_; }
  virtual int getCallType() { return call_type_; }

  // ---- keel's side (not OPRoS API) ----
  /// Runs the method with `args` (a std::tuple of its decayed parameter types): its result, or
  /// empty for void. Throws MethodInvokeException when the arguments are of other types.
  virtual std::any keelInvoke(std::any& args) = 0;
  /// The port the method was added to (ServicePortInterface::addMethod).
  void keelSetPort(ServicePortInterface* port) { port_ = port; }
  ServicePortInterface* keelPort() const { return port_; }

 private:
  std::string name_;
  std::string return_type_;
  int arity_;
  int call_type_;
  ServicePortInterface* port_ = nullptr;
};

namespace keel::opros {

/// The name getReturnType() gives: "void", or keel's name of R.
template <class R>
std::string returnTypeName() {
  if constexpr (std::is_void_v<R>) {
    return "void";
  } else {
    return keel::typeName<std::decay_t<R>>();
  }
}

template <class R>
R resultAs(std::any& r, const std::string& method);

/// Calls `m` with the call site's arguments (packed as a std::tuple of their decayed types):
/// what ProvidedMethod<R> and RequiredMethod<R> do when generated code calls them.
template <class R, class... A>
R invokePacked(Method& m, A&&... args) {
  std::any packed = std::tuple<std::decay_t<A>...>(std::forward<A>(args)...);
  std::any r = m.keelInvoke(packed);
  return resultAs<R>(r, m.getName());
}

/// The result a method call gave, as R. A void method called through a ProvidedMethod<R>* of
/// another R (generated code does it) gives R{}.
template <class R>
R resultAs(std::any& r, const std::string& method) {
  if constexpr (std::is_void_v<R>) {
    (void)r, (void)method;
  } else {
    if (R* v = std::any_cast<R>(&r)) return std::move(*v);
    if (!r.has_value()) {
      if constexpr (std::is_default_constructible_v<R>) return R{};
    }
    throw MethodInvokeException("method '" + method + "' returned a value of another type than its caller's");
  }
}

}  // namespace keel::opros
