// keel's OPRoS compatibility: InputDataPort<T>. Values arrive through keel's input data port of
// the same name and type (its queue, its range check from the profile's <validity>).
// The queue: a policy and limit given to the constructor are the code's, and win, as in OPRoS
// (whose engine never applied the profile's); keel warns when the profile asks otherwise. A
// port constructed without them takes the profile's queueing_policy and queue_size.
// Thread-safety: the owner's callbacks only.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "InputDataPortInterface.h"
#include "OPRoSTypes.h"
#include "ReturnType.h"
#include "keel/data_port.hpp"

template <class T>
class InputDataPort : public InputDataPortInterface {
 public:
  InputDataPort() = default;
  InputDataPort(DataPortPolicy policy, unsigned int queue_limit)
      : policy_(policy), limit_(queue_limit), code_queue_(true) {}
  explicit InputDataPort(const std::string& name) : InputDataPortInterface(name) {}
  InputDataPort(const std::string& name, DataPortPolicy policy, unsigned int queue_limit)
      : InputDataPortInterface(name), policy_(policy), limit_(queue_limit), code_queue_(true) {}

  opros_any* pop() override {
    if (!keel_) return nullptr;
    std::optional<T> v = keel_->pop();
    return v ? new opros_any(std::move(*v)) : nullptr;
  }
  opros_any* peek() override {
    if (!keel_) return nullptr;
    std::optional<T> v = keel_->peek();
    if (!v) return nullptr;
    peeked_ = opros_any(std::move(*v));
    return &peeked_;
  }
  int getSize() override {
    return keel_ ? static_cast<int>(static_cast<keel::detail::InputPortBase&>(*keel_).queued()) : 0;
  }
  void reset() override {
    if (keel_) static_cast<keel::detail::InputPortBase&>(*keel_).clear();
  }

  /// The value held by `data` (from pop/peek).
  T getContent(opros_any& data) { return opros_any_cast<T>(data); }
  T* getContentPointer(opros_any& data) { return opros_any_cast<T>(&data); }

  keel::detail::PortBase& keelBind(keel::Component& host) override {
    keel_ = std::make_unique<keel::InputDataPort<T>>(&host, getName());
    return *keel_;
  }
  bool keelCodeQueue(DataPortPolicy& policy, unsigned int& limit) const override {
    if (!code_queue_) return false;
    policy = policy_;
    limit = limit_;
    return true;
  }

 private:
  DataPortPolicy policy_ = OPROS_FIFO;
  unsigned int limit_ = DEFAULT_QUEUE_LIMIT;
  bool code_queue_ = false;
  std::unique_ptr<keel::InputDataPort<T>> keel_;
  opros_any peeked_;
};
