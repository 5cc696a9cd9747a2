// keel's OPRoS compatibility: InputEventPort<T>. Events arrive through keel's input event port
// of the same name; keel delivers them one by one on the component's own executor (never while
// another of its callbacks runs). Each goes to the callback installed with SET_EVENT_CALLBACK,
// or else, after setOwner(this), to the component's onEvent(Event*); with neither it is dropped.
// Thread-safety: configured in the constructor; delivered on the owner's executor.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "Event.h"
#include "EventData.h"
#include "OPRoSTypes.h"
#include "Port.h"
#include "ReturnType.h"
#include "detail/event_type.hpp"
#include "keel/event_port.hpp"

class Component;

template <class T, int ModType = EVENT_OPROS>
class InputEventPort;

/// OPRoS's own event transport (the one OPRoS components use; EVENT_ROS was a ROS bridge).
template <class T>
class InputEventPort<T, EVENT_OPROS> : public Port {
 public:
  InputEventPort() : Port(OPROS_EVENT) {}
  explicit InputEventPort(const std::string& name) : Port(name, OPROS_EVENT) {}

  /// Events without a callback go to `owner`'s onEvent(Event*).
  void setOwner(Component* owner) { owner_ = owner; }
  void setTopic(const std::string& topic) { topic_ = topic; }
  std::string& getTopic() { return topic_; }
  /// Delivers `evt` to this port's callback or owner now, on the caller's thread.
  ReturnType push(Event* evt) {
    auto* data = dynamic_cast<EventData<T>*>(evt);
    if (!data) return OPROS_BAD_INPUT_PARAMETER;
    return dispatch(*data);
  }
  void reset() override {
    if (keel_) static_cast<keel::detail::InputPortBase&>(*keel_).clear();
  }

  // ---- SET_EVENT_CALLBACK's four signatures (EventCallBack.h) ----
  template <class C, class O>
  void keelSetCallback(void (C::*f)(Event*), O* object) {
    C* obj = object;
    callback_ = [f, obj](EventData<T>& e) { (obj->*f)(&e); };
  }
  template <class C, class O>
  void keelSetCallback(void (C::*f)(EventData<T>*), O* object) {
    C* obj = object;
    callback_ = [f, obj](EventData<T>& e) { (obj->*f)(&e); };
  }
  template <class C, class O>
  void keelSetCallback(void (C::*f)(const std::string&, const T&), O* object) {
    C* obj = object;
    callback_ = [f, obj](EventData<T>& e) { (obj->*f)(e.getId(), *e.getContentData()); };
  }
  template <class C, class O>
  void keelSetCallback(void (C::*f)(const T&), O* object) {
    C* obj = object;
    callback_ = [f, obj](EventData<T>& e) { (obj->*f)(*e.getContentData()); };
  }
  void keelSetCallback(void (*f)(Event*)) {
    callback_ = [f](EventData<T>& e) { f(&e); };
  }
  void keelSetCallback(void (*f)(EventData<T>*)) {
    callback_ = [f](EventData<T>& e) { f(&e); };
  }
  void keelSetCallback(void (*f)(const std::string&, const T&)) {
    callback_ = [f](EventData<T>& e) { f(e.getId(), *e.getContentData()); };
  }
  void keelSetCallback(void (*f)(const T&)) {
    callback_ = [f](EventData<T>& e) { f(*e.getContentData()); };
  }

  keel::detail::PortBase& keelBind(keel::Component& host) override {
    keel_ = std::make_unique<keel::InputEventPort<EventData<T>>>(&host, getName());
    return *keel_;
  }
  ReturnType keelDeliver(Component& owner) override {
    (void)owner;
    EventData<T> e = keel_->current();  // the callback may keep or change its copy
    return dispatch(e);
  }

 private:
  ReturnType dispatch(EventData<T>& e);

  Component* owner_ = nullptr;
  std::string topic_;
  std::function<void(EventData<T>&)> callback_;
  std::unique_ptr<keel::InputEventPort<EventData<T>>> keel_;
};

#include "Component.h"

template <class T>
ReturnType InputEventPort<T, EVENT_OPROS>::dispatch(EventData<T>& e) {
  if (callback_) {
    callback_(e);
    return OPROS_SUCCESS;
  }
  if (owner_) return owner_->onEvent(&e);
  return OPROS_SUCCESS;  // neither: OPRoS drops it too
}
