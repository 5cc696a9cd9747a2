// keel's OPRoS compatibility: OutputEventPort<T>. push() sends an EventData<T> through keel's
// output event port of the same name to every connected input event port.
// Thread-safety: the owner's callbacks only.
#pragma once

#include <memory>
#include <string>

#include "Event.h"
#include "EventData.h"
#include "OPRoSTypes.h"
#include "Port.h"
#include "ReturnType.h"
#include "detail/event_type.hpp"
#include "keel/event_port.hpp"

template <class T, int ModType = EVENT_OPROS>
class OutputEventPort;

template <class T>
class OutputEventPort<T, EVENT_OPROS> : public Port {
 public:
  OutputEventPort() : Port(OPROS_EVENT) {}
  explicit OutputEventPort(const std::string& name) : Port(name, OPROS_EVENT) {}

  void setTopic(const std::string& topic) { topic_ = topic; }
  std::string& getTopic() { return topic_; }

  /// Sends `data` as an event whose id is empty.
  ReturnType push(const T& data) {
    EventData<T> e;
    e.setContentData(data);
    return send(e);
  }
  /// Sends `evt`: an EventData<T>, or any Event whose content holds a T.
  ReturnType push(Event* evt) {
    if (!evt) return OPROS_INPUT_NULL;
    if (auto* data = dynamic_cast<EventData<T>*>(evt)) return send(*data);
    const T* content = opros_any_cast<T>(&evt->getContent());
    if (!content) return OPROS_BAD_INPUT_PARAMETER;
    EventData<T> e;
    e.setId(evt->getId());
    e.setContentData(*content);
    return send(e);
  }
  void reset() override {}

  keel::detail::PortBase& keelBind(keel::Component& host) override {
    keel_ = std::make_unique<keel::OutputEventPort<EventData<T>>>(&host, getName());
    return *keel_;
  }

 private:
  ReturnType send(EventData<T>& e) {
    if (!keel_) return OPROS_PRECONDITION_NOT_MET;
    if (!topic_.empty()) e.setTopic(topic_);
    e.setPortId(getName());
    keel_->send(e);
    return OPROS_SUCCESS;
  }

  std::string topic_;
  std::unique_ptr<keel::OutputEventPort<EventData<T>>> keel_;
};
