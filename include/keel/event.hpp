// keel::Event: the general-purpose payload of event ports (OPRoS's Event). Components may also
// use their own copyable types on event ports. Plain value.
#pragma once

#include <cstdint>
#include <string>

namespace keel {

struct Event {
  std::string name;       // what happened, e.g. "obstacle_close"
  std::int64_t code = 0;  // an application-defined code
  double value = 0.0;     // an application-defined value
};

}  // namespace keel
