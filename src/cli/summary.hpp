// The one-screen summary `keel run` prints when the run has ended: components, executors,
// faults, and how each fault was handled with its recovery latency (recovered − detected).
// It is read from the run's fault log after shutdown, so it says what the log says, including
// what happened while the run stopped and in component processes (docs/commands.md#summary).
#pragma once

#include <cstdint>
#include <istream>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace keel::cli {

struct RunSummary {
  struct ComponentLine {
    std::string name;
    std::string state;  // at the `stopping` record (the last before it)
    std::string class_name;
    std::string replacement;  // the class that replaced it, if one did
    std::string executor;     // "passive", or the executor's name
    std::string process;      // empty: keel run's own
    bool counted = false;     // a `counts` record was seen (none from a process that died)
    std::uint64_t executions = 0;
    std::uint64_t deadline_misses = 0;
    std::uint64_t faults = 0;
  };
  struct ExecutorLine {
    std::string name;
    std::string process;
    double period_ms = 0;  // 0: aperiodic
    std::uint64_t cycles = 0;
    std::uint64_t late_cycles = 0;
  };
  struct FaultCount {
    std::string component, kind, first_detail;
    std::uint64_t count = 0;
  };
  /// A ROS 2 node keel ran: its `node` records.
  struct NodeLine {
    std::string name;                     // its instance
    std::string node;                     // its name in the ROS 2 graph
    std::string output;                   // its output file
    std::uint64_t starts = 0;             // started and restarted
    std::uint64_t exits = 0;              // ended by itself (a `process` fault each)
    std::string last_end;                 // how it ended last: "exited with status 1", ...
    bool failed = false;                  // it ended by itself last (not stopped by keel)
    std::vector<std::string> last_lines;  // of its last exit by itself
  };
  struct Handling {
    std::uint64_t fault_id = 0;
    std::string component, kind, severity, actions;
    bool failed = false;
    std::optional<double> recovered_after_us;
  };

  std::string name;
  std::optional<std::int64_t> started_ns, stopping_ns;
  std::string stop_reason;
  std::vector<ComponentLine> components;  // in the order the log first names them
  std::vector<ExecutorLine> executors;
  std::vector<NodeLine> nodes;  // in the order the log first names them
  std::vector<FaultCount> faults;
  std::vector<Handling> handlings;  // in fault id order
  std::vector<std::string> stopped_applications;
  std::vector<std::string> dead_processes;  // "vision (pid 123)": their counts are not in the log
  std::uint64_t undetected = 0;             // injected faults never detected
  std::uint64_t warnings = 0;
  std::uint64_t unreadable_lines = 0;  // not JSON: a torn last line, or not a keel log
  bool emergency_latched = false;      // at the log's end
  std::string ended_by, end_summary;   // the first end_requested
};

/// Reads one run's fault log (JSON lines).
RunSummary summarize(std::istream& log);
void printSummary(std::ostream& out, const RunSummary& summary);

}  // namespace keel::cli
