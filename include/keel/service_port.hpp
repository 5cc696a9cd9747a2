// Service ports (OPRoS service ports): a ProvidedServicePort<R(A...)> offers a function; a
// RequiredServicePort<R(A...)> connected to it calls that function and gets a Result within a
// timeout. The call runs on the provider's own executor, serialised with its other callbacks
// (so the provider writes no locks); when the caller is on that executor already, or the
// provider is passive, it runs on the caller's thread under the provider's lock.
// Signatures are checked when the runtime connects ports. One function per port.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>
#include <variant>

#include "keel/detail/port_base.hpp"
#include "keel/result.hpp"
#include "keel/type_name.hpp"

namespace keel {

namespace detail {

/// One call in flight, shared between caller and provider (the caller may time out first).
class ServiceCall {
 public:
  virtual ~ServiceCall() = default;
  /// Runs the provider's function; called by the runtime inside the provider's guard.
  virtual void run() = 0;
};

/// Runs `call` as a callback of `provider` and waits up to `timeout`. Returns an empty
/// message on success, or why it failed (timeout, provider not active, provider faulted).
/// Defined in libkeel.
std::string invokeService(Component& provider, const std::string& port, const std::shared_ptr<ServiceCall>& call,
                          std::chrono::nanoseconds timeout);

template <class R>
using Returned = std::conditional_t<std::is_void_v<R>, std::monostate, R>;

/// Common base of service ports, as the runtime sees them.
class ServicePortBase : public PortBase {
 public:
  using PortBase::PortBase;
  /// Required side: binds to a provided port of the same signature; false on mismatch.
  virtual bool bind(ServicePortBase& provided) {
    (void)provided;
    return false;
  }
  /// Required side: the default call timeout (from the profile).
  virtual void setTimeout(std::chrono::nanoseconds timeout) { (void)timeout; }
};

}  // namespace detail

template <class Sig>
class ProvidedServicePort;
template <class Sig>
class RequiredServicePort;

template <class R, class... A>
class ProvidedServicePort<R(A...)> final : public detail::ServicePortBase {
 public:
  ProvidedServicePort(Component* owner, std::string name, std::function<R(A...)> fn)
      : ServicePortBase(owner, std::move(name), PortKind::Service, PortDirection::Input, typeid(R(A...)),
                        detail::demangle(typeid(R(A...)).name())),
        fn_(std::move(fn)) {}

  R invoke(A... args) const { return fn_(std::forward<A>(args)...); }

 private:
  std::function<R(A...)> fn_;
};

template <class R, class... A>
class RequiredServicePort<R(A...)> final : public detail::ServicePortBase {
 public:
  using Value = detail::Returned<R>;

  RequiredServicePort(Component* owner, std::string name)
      : ServicePortBase(owner, std::move(name), PortKind::Service, PortDirection::Output, typeid(R(A...)),
                        detail::demangle(typeid(R(A...)).name())) {}

  /// Calls the connected provider with the profile's timeout.
  Result<Value> call(A... args) const { return callWithin(timeout_, std::move(args)...); }

  /// Calls the connected provider, waiting at most `timeout`.
  Result<Value> callWithin(std::chrono::nanoseconds timeout, A... args) const {
    const ProvidedServicePort<R(A...)>* provider = provider_.load(std::memory_order_acquire);
    if (!provider) return fail("service port '" + name() + "' is not connected");
    auto c = std::make_shared<Call>(provider, std::tuple<A...>(std::move(args)...));
    std::string why = detail::invokeService(provider->owner(), provider->name(), c, timeout);
    if (!why.empty() || !c->result) return fail(why.empty() ? "service call failed" : why);
    return std::move(*c->result);
  }

  bool connected() const { return provider_.load(std::memory_order_acquire) != nullptr; }

 private:
  bool bind(ServicePortBase& provided) override {
    if (provided.type() != type() || provided.direction() != PortDirection::Input) return false;
    // atomic: a replacement provider is bound while this port's owner may be calling
    provider_.store(static_cast<ProvidedServicePort<R(A...)>*>(&provided), std::memory_order_release);
    return true;
  }
  void setTimeout(std::chrono::nanoseconds timeout) override { timeout_ = timeout; }

  struct Call final : detail::ServiceCall {
    Call(const ProvidedServicePort<R(A...)>* p, std::tuple<A...> a) : provider(p), args(std::move(a)) {}
    void run() override {
      if constexpr (std::is_void_v<R>) {
        std::apply([this](auto&&... x) { provider->invoke(x...); }, args);
        result.emplace();
      } else {
        result.emplace(std::apply([this](auto&&... x) { return provider->invoke(x...); }, args));
      }
    }
    const ProvidedServicePort<R(A...)>* provider;
    std::tuple<A...> args;
    std::optional<Value> result;
  };

  std::atomic<const ProvidedServicePort<R(A...)>*> provider_{nullptr};
  std::chrono::nanoseconds timeout_ = std::chrono::seconds(1);
};

}  // namespace keel
