#include "runtime/warning.hpp"

#include <cstdio>

namespace keel::runtime {

void warnOnStderr(const std::string& message) { std::fprintf(stderr, "keel: warning: %s\n", message.c_str()); }

}  // namespace keel::runtime
