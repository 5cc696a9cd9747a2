// EventData.h — keel's own, from-scratch OPRoS-compatible version of OPRoS's typed event.
//
// `EventData<T>` is an Event whose content is a T: components fill one (setId, setContentData)
// and push it on an output event port; receivers cast the Event* back and read getContentData().
// It is a value type (default-constructible, copyable, movable; a copy owns its own ids and
// content), so keel can queue copies between components. An archive saves and loads it whole
// (save_this/load_this). Not shared between threads without a lock.
#pragma once

#include <cstring>
#include <ostream>
#include <string>

#include "Event.h"
#include "OPRoSTypes.h"
#include "ReturnType.h"
#include "archive/opros_iarchive.h"
#include "archive/opros_oarchive.h"
#include "archive/opros_type_info.h"

template <typename dataType>
class EventData : public Event {
 public:
  EventData() = default;
  EventData(const EventData&) = default;
  EventData(EventData&&) = default;
  EventData& operator=(const EventData&) = default;
  EventData& operator=(EventData&&) = default;
  ~EventData() override = default;

  bool checkContentType(opros_any& data) override { return opros_any_cast<dataType>(&data) != nullptr; }

  // The content, or null when there is none.
  virtual dataType* getContentData() { return opros_any_cast<dataType>(&getContent()); }
  const dataType* getContentData() const { return opros_any_cast<dataType>(&getContent()); }

  virtual ReturnType setContentData(const dataType& data) {
    opros_any content(data);
    return setContent(content);
  }

  Event* clone() override { return new EventData(*this); }

  friend std::ostream& operator<<(std::ostream& os, const EventData& ev) {
    return os << "[eventid:" << ev.getId() << ",topic:" << ev.getTopic() << ",componentid:" << ev.getComponentId()
              << ",portid:" << ev.getPortId() << "]";
  }
};

// An event's ids, then whether it has content, then the content.
template <class T>
inline void save_this(opros::archive::oarchive& ar, EventData<T>& t) {
  const EventData<T>& event = t;
  ar << OPROS_SERIALIZATION_MAKE_NVP(eventid, event.getId());
  ar << OPROS_SERIALIZATION_MAKE_NVP(topicid, event.getTopic());
  ar << OPROS_SERIALIZATION_MAKE_NVP(componentid, event.getComponentId());
  ar << OPROS_SERIALIZATION_MAKE_NVP(portid, event.getPortId());
  const T* content = event.getContentData();
  const bool IsContent = content != nullptr;
  ar << OPROS_SERIALIZATION_NVP(IsContent);
  if (IsContent) ar << OPROS_SERIALIZATION_MAKE_NVP(content, *content);
}

template <class T>
inline void load_this(opros::archive::iarchive& ar, EventData<T>& t) {
  std::string eventid;
  std::string topicid;
  std::string componentid;
  std::string portid;
  ar >> OPROS_SERIALIZATION_NVP(eventid);
  ar >> OPROS_SERIALIZATION_NVP(topicid);
  ar >> OPROS_SERIALIZATION_NVP(componentid);
  ar >> OPROS_SERIALIZATION_NVP(portid);
  bool IsContent = false;
  ar >> OPROS_SERIALIZATION_NVP(IsContent);
  EventData<T> loaded;
  loaded.setId(eventid);
  loaded.setTopic(topicid);
  loaded.setComponentId(componentid);
  loaded.setPortId(portid);
  if (IsContent) {
    T content{};
    ar >> OPROS_SERIALIZATION_NVP(content);
    loaded.setContentData(content);
  }
  t = std::move(loaded);
}

// "EventData<" + the content's OPRoS name + ">".
template <class T>
inline std::string typeName(EventData<T>*) {
  return "EventData<" + getTypeName(static_cast<T*>(nullptr)) + ">";
}
