// The record of every fault's life: writes a fault's records to the fault log as its handling
// goes on (`injected`, `detected`, the state change to Error, `diagnosed`, each `action` with
// the state change it makes, `recovered`) and keeps what the run's summary, the benchmarks and
// the tests read back (counts per component and kind, detections, handlings).
// Thread-safety: every member may be called from any thread (one mutex); logReport() on one
// report at a time.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "fault/report.hpp"
#include "log/fault_log.hpp"

namespace keel::fault {

struct FaultCount {
  std::string component;
  std::string kind;
  std::string detail;  // the first one
  std::uint64_t count = 0;
};

/// One detection, as kept for summaries and tests.
struct Detection {
  std::uint64_t fault_id = 0;
  std::string component;
  FaultKind kind = FaultKind::User;
  std::int64_t detected_ns = 0;  // steady clock
  std::int64_t injected_ns = 0;  // 0: not injected
};

/// One fault's handling, as kept for the run's summary and the benchmarks.
struct Handling {
  std::uint64_t fault_id = 0;
  std::string component;
  FaultKind kind = FaultKind::User;
  std::string severity;
  std::string actions;  // "reset", "escalate, replace", ...
  bool failed = false;  // an action failed (the last word is then the outcome)
  std::int64_t detected_ns = 0;
  std::int64_t injected_ns = 0;        // 0: not injected
  std::int64_t recovered_ns = 0;       // 0: not (yet) recovered
  const Component* accused = nullptr;  // the component object (an alternative has the name too)
};

class FaultRecords {
 public:
  explicit FaultRecords(log::FaultLog& log) : log_(log) {}

  log::FaultLog& log() { return log_; }
  /// Called after each report or recovery is logged (on the thread that logged it): the
  /// run's health changed (keel's /diagnostics). Set before the run starts.
  void onChange(std::function<void()> changed) { changed_ = std::move(changed); }

  /// Writes what is new in `r` since the last call for it: its detection (once) and the
  /// actions added since; marks them written in `r`.
  void logReport(FaultReport& r);
  /// `recovered` of fault `id` at steady time `t_ns`, with its latency from the detection.
  void logRecovered(std::uint64_t id, std::string_view component, std::int64_t t_ns);
  /// `injected` with `detected: false` for an injection that manifested and was never detected.
  void logUndetected(std::uint64_t id, std::string_view component, std::int64_t injected_ns);

  std::vector<FaultCount> counts() const;
  std::vector<Detection> detections() const;
  std::vector<Handling> handlings() const;
  std::optional<Handling> handling(std::uint64_t id) const;
  std::size_t recoveredCount() const { return recovered_count_.load(std::memory_order_acquire); }
  std::size_t detectionCount() const { return detection_count_.load(std::memory_order_acquire); }

 private:
  void logDetection(const FaultReport& r);  // holds mutex_
  /// The state changes of `r` that go with its detection or with action `action`.
  void writeChanges(const FaultReport& r, std::uint8_t action);

  log::FaultLog& log_;
  std::function<void()> changed_;
  mutable std::mutex mutex_;  // guards the records below
  std::vector<FaultCount> counts_;
  std::vector<Detection> detections_;
  std::vector<Handling> handlings_;
  std::atomic<std::size_t> detection_count_{0};
  std::atomic<std::size_t> recovered_count_{0};
};

}  // namespace keel::fault
