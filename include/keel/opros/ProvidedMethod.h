// keel's OPRoS compatibility: ProvidedMethod<R>, a method a provided port implements, and
// makeProvidedMethod, which wraps a member function (with its object) or a free function.
#pragma once

#include <any>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "Method.h"
#include "MethodInvokeException.h"

template <class R>
class ProvidedMethod : public Method {
 public:
  ProvidedMethod(const std::string& name, int arity, int call_type)
      : Method(name, keel::opros::returnTypeName<R>(), arity, call_type) {}

  /// Calls the method directly, with the arguments given.
  template <class... A>
  R operator()(A&&... args) {
    return keel::opros::invokePacked<R>(*this, std::forward<A>(args)...);
  }
};

namespace keel::opros {

/// Unpacks a call's arguments for a function of parameters P...; throws when they differ.
template <class... P>
std::tuple<std::decay_t<P>...>& argumentsOf(std::any& args, const std::string& method) {
  auto* t = std::any_cast<std::tuple<std::decay_t<P>...>>(&args);
  if (!t)
    throw MethodInvokeException("method '" + method + "' called with " + std::string(args.type().name()) +
                                " where its declaration takes other parameters");
  return *t;
}

template <class R, class F, class Tuple>
std::any invokeWith(F&& f, Tuple& args) {
  if constexpr (std::is_void_v<R>) {
    std::apply(std::forward<F>(f), args);
    return {};
  } else {
    return std::any(std::apply(std::forward<F>(f), args));
  }
}

template <class R, class C, class... P>
class MemberMethod final : public ProvidedMethod<R> {
 public:
  MemberMethod(R (C::*f)(P...), C* object, const std::string& name, int call_type)
      : ProvidedMethod<R>(name, sizeof...(P), call_type), f_(f), object_(object) {}
  std::any keelInvoke(std::any& args) override {
    auto& t = argumentsOf<P...>(args, this->getName());
    return invokeWith<R>([this](auto&... a) -> R { return (object_->*f_)(a...); }, t);
  }

 private:
  R (C::*f_)(P...);
  C* object_;
};

template <class R, class... P>
class FunctionMethod final : public ProvidedMethod<R> {
 public:
  FunctionMethod(R (*f)(P...), const std::string& name, int call_type)
      : ProvidedMethod<R>(name, sizeof...(P), call_type), f_(f) {}
  std::any keelInvoke(std::any& args) override {
    auto& t = argumentsOf<P...>(args, this->getName());
    return invokeWith<R>([this](auto&... a) -> R { return f_(a...); }, t);
  }

 private:
  R (*f_)(P...);
};

}  // namespace keel::opros

template <class C, class O, class R, class... P>
Method* makeProvidedMethod(R (C::*f)(P...), O* object, const char* name, const int& call_type = METHOD_BLOCKING) {
  return new keel::opros::MemberMethod<R, C, P...>(f, object, name, call_type);
}
template <class R, class... P>
Method* makeProvidedMethod(R (*f)(P...), const char* name, const int& call_type = METHOD_BLOCKING) {
  return new keel::opros::FunctionMethod<R, P...>(f, name, call_type);
}
