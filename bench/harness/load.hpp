// The CPU load a benchmark cell runs under, and the load the machine really carried.
//   BackgroundLoad  `percent` busy on every CPU until destroyed: stress-ng (`--cpu 0
//                   --cpu-load P`) when it is installed, otherwise keel-bench's own duty-cycle
//                   load (`keel-bench _load P`: one thread per CPU, busy P% of every 10 ms),
//                   in a process of its own either way, so a benchmark never shares its
//                   threads with the load.
//   CpuMeter        the fraction of the machine's CPU time that was busy since it was made
//                   (/proc/stat), whoever was busy: the load, the benchmark and the rest.
// Thread-safety: none needed (used from the harness's main thread).
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>

#include "process.hpp"

namespace keel::bench {

enum class LoadSource { Auto, StressNg, Internal };

class BackgroundLoad {
 public:
  /// Starts the load (percent 0: none) and lets it settle; throws std::runtime_error with the
  /// reason when it cannot start (stress-ng asked for but missing, spawn failed).
  BackgroundLoad(int percent, LoadSource source, const std::string& self_exe);
  ~BackgroundLoad();  // stops the load and reaps its process
  BackgroundLoad(const BackgroundLoad&) = delete;
  BackgroundLoad& operator=(const BackgroundLoad&) = delete;

  /// "stress-ng", "internal" or "none".
  [[nodiscard]] const std::string& source() const { return source_; }
  [[nodiscard]] pid_t pid() const { return process_ ? process_->pid() : -1; }  // -1: none

 private:
  std::optional<Process> process_;  // in a process group of its own: stopped as a whole
  std::string source_ = "none";
};

/// `keel-bench _guard PID COMMAND ARGS...`: becomes COMMAND (exec), set to get SIGTERM when
/// its parent, keel-bench `PID`, dies, however it dies: a crashed or killed keel-bench leaves no
/// load behind (posix_spawn cannot ask for PR_SET_PDEATHSIG itself). Returns only on failure.
int runGuarded(int argc, char** argv);

/// `keel-bench _load PERCENT`: the internal duty-cycle load; runs until SIGTERM. Returns the exit
/// status.
int runInternalLoad(int percent);

class CpuMeter {
 public:
  CpuMeter();
  /// Busy fraction of all CPUs since construction, 0..1.
  [[nodiscard]] double busy() const;

 private:
  long long busy0_ = 0, total0_ = 0;
};

}  // namespace keel::bench
