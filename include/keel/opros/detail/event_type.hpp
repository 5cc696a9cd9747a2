// keel's OPRoS compatibility: an OPRoS event port carries EventData<T> through keel's event
// ports (the event's id, topic and content travel together); its data type, as profiles and
// keel's port check name it, is T's.
#pragma once

#include <string>

#include "../EventData.h"
#include "keel/type_name.hpp"

#ifndef EVENT_OPROS
#define EVENT_OPROS 0
#endif

namespace keel {
template <class T>
struct TypeName<::EventData<T>> {
  static std::string get() { return typeName<T>(); }
};
}  // namespace keel
