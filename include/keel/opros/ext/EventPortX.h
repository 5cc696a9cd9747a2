// keel's OPRoS compatibility: OPRoS 2014's ROS bridge for event ports (EVENT_ROS,
// SET_TOPIC_CALLBACK). keel does not bridge OPRoS event ports to ROS: an OPRoS component's
// ports talk to ROS 2 through keel's own DDS bindings. The names exist so that OPRoSInclude.h
// compiles; using them is a compile error saying so.
#pragma once

#ifndef EVENT_ROS
#define EVENT_ROS 1
#endif

#define SET_TOPIC_CALLBACK(...) \
  static_assert(false, "keel: OPRoS's ROS bridge (SET_TOPIC_CALLBACK) is not provided; see docs/opros.md")
