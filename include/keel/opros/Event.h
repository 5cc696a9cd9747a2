// Event.h — keel's own, from-scratch OPRoS-compatible version of OPRoS's event base class.
//
// An event carries an id (what it is; "event" unless set), a topic, the sending component's and
// port's ids, and its content in an opros_any. Components receive `Event*` in onEvent and tell
// events apart by getId(); EventData<T> (EventData.h) is the concrete, typed event. Getters are
// also callable on const events. An event is a value: copies are independent, one object is not
// shared between threads without a lock.
#pragma once

#include <string>

#include "OPRoSTypes.h"
#include "ReturnType.h"

class Event {
 public:
  Event() = default;
  Event(const Event&) = default;
  Event(Event&&) = default;
  Event& operator=(const Event&) = default;
  Event& operator=(Event&&) = default;
  virtual ~Event() = default;

  virtual std::string& getId() { return id_; }
  const std::string& getId() const { return id_; }
  virtual void setId(const std::string& strid) { id_ = strid; }

  virtual std::string& getTopic() { return topic_; }
  const std::string& getTopic() const { return topic_; }
  virtual void setTopic(const std::string& topic) { topic_ = topic; }

  virtual std::string& getComponentId() { return component_id_; }
  const std::string& getComponentId() const { return component_id_; }
  virtual void setComponentId(const std::string& strid) { component_id_ = strid; }

  virtual std::string& getPortId() { return port_id_; }
  const std::string& getPortId() const { return port_id_; }
  virtual void setPortId(const std::string& strid) { port_id_ = strid; }

  virtual opros_any& getContent() { return content_; }
  const opros_any& getContent() const { return content_; }

  // Replaces the content with a copy of con when checkContentType accepts it: OPROS_SUCCESS;
  // otherwise leaves it and returns OPROS_BAD_INPUT_PARAMETER.
  virtual ReturnType setContent(opros_any& con) {
    if (!checkContentType(con)) return OPROS_BAD_INPUT_PARAMETER;
    content_ = con;
    return OPROS_SUCCESS;
  }
  ReturnType setContent(const opros_any& con) {
    opros_any copy(con);
    return setContent(copy);
  }

  // Whether con holds what this kind of event carries.
  virtual bool checkContentType(opros_any& con) = 0;

  // A new event of the same kind and contents; the caller deletes it.
  virtual Event* clone() = 0;

 private:
  std::string id_ = "event";
  std::string topic_;
  std::string component_id_;
  std::string port_id_;
  opros_any content_;
};
