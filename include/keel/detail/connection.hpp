// Typed connections between an output port and an input port (data and event). The output
// calls send(); the connection forwards to its current sink. The sink pointer is atomic so the
// runtime can re-point a connection to a replacement component while others push.
// This is the transport seam: a remote transport provides another Sink<T>.
// Thread-safety: send() from any thread; retarget() from the runtime, any time.
#pragma once

#include <atomic>
#include <typeindex>
#include <typeinfo>

#include "keel/detail/port_base.hpp"

namespace keel::detail {

template <class T>
class Sink {
 public:
  virtual ~Sink() = default;
  virtual void deliver(const T& value) = 0;
};

template <class T>
class Connection final : public ConnectionBase {
 public:
  explicit Connection(Sink<T>* target) : target_(target) {}
  std::type_index type() const override { return typeid(T); }
  void send(const T& value) const {
    if (Sink<T>* sink = target_.load(std::memory_order_acquire)) sink->deliver(value);
  }
  void retarget(Sink<T>* target) { target_.store(target, std::memory_order_release); }
  Sink<T>* target() const { return target_.load(std::memory_order_acquire); }

 private:
  std::atomic<Sink<T>*> target_;
};

/// Called by input ports after a value arrived: wakes the owner's executor if it waits for
/// input (aperiodic) or has events to dispatch. Defined in libkeel.
void notifyInput(Component& owner, bool is_event);

}  // namespace keel::detail
