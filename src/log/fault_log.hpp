// The fault log (docs/fault-log.md): one JSON object per line, each written with a single
// write(2) as it happens, so a crash loses at most the line being written. Every record gets `t_ns`
// (steady clock, ns since the engine started) unless it carries one. A tee (keel run --log-tee)
// gets each line right after the log has it, so what a reader of the tee saw is in the log.
// Thread-safety: write() may be called from any thread (one mutex around the write).
#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

#include <nlohmann/json.hpp>

#include "keel/result.hpp"
#include "runtime/clock.hpp"
#include "runtime/ipc/session.hpp"

namespace keel::log {

class FaultLog {
 public:
  FaultLog();
  ~FaultLog();
  FaultLog(const FaultLog&) = delete;
  FaultLog& operator=(const FaultLog&) = delete;

  /// Opens `path`, truncated unless `append` (keel soak's rounds share one log). Without a
  /// successful open, write() does nothing.
  Result<void> open(const std::string& path, bool append = false);
  /// Appends to the log at `path` another process opened (keel run's, from a component
  /// process), with that log's epoch: one log for the run.
  Result<void> join(const std::string& path, std::int64_t epoch_ns);
  /// From now on every line goes to an offset reserved in `arena`, staged in `participant`'s
  /// stage first (keel run calls this once with the log open; the arena's tail starts at the
  /// file's end). What a dead writer left staged is written again by repair().
  void share(runtime::ipc::LogArena& arena, std::size_t participant, std::size_t participants);
  /// Writes again the line `participant` (a dead process) had staged and not finished.
  void repair(std::size_t participant);
  /// For a process about to _exit while others write on: waits up to `within` for the line
  /// being written to be whole, and holds every later one back for good. A line reserved and
  /// cut off by the exit would leave a hole of NUL bytes before the others' lines.
  void quiesce(std::chrono::milliseconds within);
  /// Also writes every line to `path` (keel run --log-tee), right after the log has it. A pipe
  /// or FIFO is written without blocking: a line is written whole or, when the reader is
  /// behind (or gone, or the line is longer than PIPE_BUF), dropped and counted. Anything else
  /// (a regular file, created if need be) is appended to.
  Result<void> openTee(const std::string& path);
  /// The tee's descriptor (another process opens /proc/<pid>/fd/<it>: the same pipe), or -1.
  int teeDescriptor() const { return tee_fd_; }
  /// Lines written to the log that the tee did not get, and all lines written to the log
  /// while there was a tee.
  std::uint64_t teeDropped() const;
  std::uint64_t teeLines() const;
  bool enabled() const { return fd_ >= 0; }
  std::int64_t epoch() const { return epoch_ns_; }

  /// ns since the log's epoch (the engine's start) for a steady-clock time in ns.
  std::int64_t sinceStart(std::int64_t steady_ns) const { return steady_ns - epoch_ns_; }
  std::int64_t now() const;

  void write(nlohmann::json record);
  /// Adds `key: value` to every record written from now on (that has no `key`).
  void tag(std::string key, nlohmann::json value);

 private:
  std::int64_t epoch_ns_;
  int fd_ = -1;
  runtime::ipc::LogArena* arena_ = nullptr;  // shared: lines at reserved offsets
  std::size_t participant_ = 0;
  std::size_t participants_ = 0;  // this process's count, not the shared one: a scribble stays in bounds
  int tee_fd_ = -1;
  bool tee_is_pipe_ = false;
  bool tee_reader_gone_ = false;  // EPIPE: nothing is written to it any more
  std::uint64_t tee_lines_ = 0;
  std::uint64_t tee_dropped_ = 0;
  bool writeShared(const std::string& line);
  void writeTee(const std::string& line);
  nlohmann::json tags_ = nlohmann::json::object();  // set before any other thread writes
  mutable std::mutex mutex_;
};

}  // namespace keel::log
