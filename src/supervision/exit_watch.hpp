// Seeing a process end the moment it ends, without polling: one thread waits in epoll on a
// pidfd per watched process (Linux 5.3+), which the kernel makes readable when the process has
// exited. The thread then reaps it (waitid on the pidfd: nothing else in keel may reap a process
// it watches) and says how it ended. A process that is not keel run's child (an attached node)
// can be watched too; its exit status is then unknown.
// The time of an exit is taken when the thread wakes: after the kernel tore the process down
// (its memory and files), which is the part of the delay keel cannot shorten.
// Thread-safety: watch() and stop() from any thread; the callbacks run on the watch's thread,
// one at a time, and must not call stop().
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "keel/result.hpp"

namespace keel::supervision {

/// How a watched process ended.
struct Exit {
  /// Its wait status (as waitpid gives it: describeExit() words it); -1 when it was not keel
  /// run's child, whose status only its parent gets.
  int status = -1;
  std::int64_t at_ns = 0;  // when the watch saw it (runtime::steadyNs)
};

/// describeExit(exit.status), or "exited (its status is its parent's, not keel's)" when unknown.
std::string describe(const Exit& exit);

class ExitWatch {
 public:
  using OnExit = std::function<void(pid_t pid, const Exit& exit)>;

  ExitWatch();
  /// stop().
  ~ExitWatch();
  ExitWatch(const ExitWatch&) = delete;
  ExitWatch& operator=(const ExitWatch&) = delete;

  /// Watches `pid` until it ends; then `on_exit` runs once, on the watch's thread, after a
  /// child of keel run's was reaped. An error when there is no such process (any more: a child
  /// already reaped), or when the watch has stopped.
  Result<void> watch(pid_t pid, OnExit on_exit);
  /// Ends the watch's thread; the processes still watched are no longer (none is reaped, no
  /// callback runs after stop() returned). Idempotent.
  void stop();

 private:
  void run();
  void ended(int pidfd);

  int epoll_ = -1;
  int wake_ = -1;  // an eventfd: stop()
  std::mutex mutex_;
  struct Watched {
    pid_t pid = 0;
    OnExit on_exit;
  };
  std::map<int, Watched> watched_;  // by pidfd
  bool stopped_ = false;
  std::thread thread_;  // last: started once the members it uses are
};

}  // namespace keel::supervision
