// Starting the programs keel supervises: keel-hosts and ROS 2 nodes, any executable alike. Each
// child is started by posix_spawn from the spawner's one thread — a child's PR_SET_PDEATHSIG fires
// when the thread that started it ends, so that thread lives as long as keel run's side of the
// engine, which owns the spawner — in a process group of its own (a terminal's ^C reaches keel
// run, which stops its children in order), with only the descriptors it is given and the signals
// keel run blocks or ignores back at their defaults. A program that cannot set PR_SET_PDEATHSIG
// itself (a node: keel-hosts do) is started through keel-node-exec (`ChildSpec::shim`), which
// sets it and then executes the program.
// Thread-safety: any thread.
#pragma once

#include <sys/types.h>

#include <functional>
#include <string>
#include <vector>

#include "keel/result.hpp"
#include "runtime/job_thread.hpp"

namespace keel::supervision {

/// One child to start.
struct ChildSpec {
  std::string executable;         // a path: not looked up in $PATH
  std::vector<std::string> args;  // after argv[0], which is `executable`
  /// Given to the child as descriptors 3, 4, ... (the caller's stay open); every other
  /// descriptor above 2 is closed in the child, close-on-exec or not.
  std::vector<int> fds;
  /// "NAME=value" each: set in the child's environment over keel run's own (which it inherits).
  std::vector<std::string> environment{};
  /// The child's working directory; empty: keel run's.
  std::string directory{};
  /// A file the child's stdout and stderr are appended to (created if missing); empty: keel
  /// run's own stdout and stderr.
  std::string output{};
  /// Whether `output` is emptied first rather than appended to.
  bool fresh_output = false;
  /// keel-node-exec's path: the child is started through it, so that it dies with the spawner's
  /// thread (PR_SET_PDEATHSIG) even if it cannot ask for that itself; empty: started directly.
  std::string shim{};
};

/// The first descriptor a child gets from ChildSpec::fds.
inline constexpr int kFirstChildFd = 3;

/// How a child ended, from its wait status: "exited with status 3", "killed by signal 9
/// (SIGKILL)".
std::string describeExit(int status);

class Spawner {
 public:
  /// Starts `spec` from the spawner's thread (at once, when called on it); its pid, or why not.
  Result<pid_t> start(const ChildSpec& spec);
  /// Runs `job` on the spawner's thread after what was posted before (work that starts children
  /// and must not wait on the caller's thread).
  void post(std::function<void()> job) { thread_.post(std::move(job)); }
  /// Returns once what was posted before has run: for a user of the spawner whose posted jobs
  /// refer to it, before it goes.
  void drain() { thread_.drain(); }
  /// Ends the thread once what was posted ran. Idempotent.
  void stop() { thread_.stop(); }

 private:
  runtime::JobThread thread_;
};

}  // namespace keel::supervision
