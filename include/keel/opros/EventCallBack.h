// keel's OPRoS compatibility: SET_EVENT_CALLBACK(port, Class::method, object) installs a typed
// callback on an input event port. The member may take `Event*`, `EventData<T>*`,
// `(const std::string& id, const T&)` or `(const T&)`; a port with a callback no longer calls
// onEvent. SET_EVENT_CALLBACK_EX(port, function) does the same with a free function.
#pragma once

#include "EventData.h"
#include "InputEventPort.h"

#define SET_EVENT_CALLBACK(port, method, object) (port).keelSetCallback(&method, object)
#define SET_EVENT_CALLBACK_EX(port, function) (port).keelSetCallback(&function)
