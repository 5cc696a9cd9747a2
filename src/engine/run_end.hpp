// RunEnd and RunEndLatch: a component's request to end the run (RunControl::endRun), kept by
// the engine. The first request wins and wakes whoever waits (`keel run`); later ones are
// ignored. runEndRecord() makes the record the engine writes last in the fault log, from the
// request's event and fields_json (JSON object members without braces, checked here).
// Thread-safety: request/get/wait from any thread (one mutex); runEndRecord is a pure function.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace keel::engine {

/// Who ended the run and how (the arguments of the winning RunControl::endRun).
struct RunEnd {
  std::string component;  // its instance name
  std::string summary;    // printed by `keel run`: "ended by <component>: <summary>"
  std::string event;      // empty: no record in the log
  std::string fields;     // members of a JSON object, without braces; may be malformed
};

class RunEndLatch {
 public:
  /// Keeps `end` if it is the first request and wakes the waiters; false if one came before.
  bool request(RunEnd end);
  /// True once a request came (lock-free).
  bool requested() const { return requested_.load(std::memory_order_acquire); }
  std::optional<RunEnd> get() const;
  /// Blocks until a request comes or `until` passes; true if one came.
  bool waitUntil(std::chrono::steady_clock::time_point until) const;

 private:
  mutable std::mutex mutex_;
  mutable std::condition_variable cv_;
  std::optional<RunEnd> end_;
  std::atomic<bool> requested_{false};
};

/// The record {"t_ns", "event", "component", <members of end.fields>} (event, component and
/// t_ns win over members of those names). When end.fields is not the members of one JSON
/// object, the record carries "fields_error" (why, with the text) instead of them.
nlohmann::json runEndRecord(const RunEnd& end, std::int64_t t_ns);

}  // namespace keel::engine
