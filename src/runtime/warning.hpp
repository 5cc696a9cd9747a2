// keel's one warning sink: something the run goes on without (a scheduling policy the OS
// refused, an injected hardware fault nobody took) is reported through a `Warn` given by the
// run's owner. The engine gives every part the same one, which writes the fault log's
// `warning` record and then the owner's callback, or standard error.
// Thread-safety: a Warn is called from any thread; the default is safe to call from any.
#pragma once

#include <functional>
#include <string>

namespace keel::runtime {

using Warn = std::function<void(const std::string& message)>;

/// Prints "keel: warning: <message>" to standard error (the default sink).
void warnOnStderr(const std::string& message);

}  // namespace keel::runtime
