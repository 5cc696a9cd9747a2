// keel-node-exec: the two helpers keel run needs to leave no node behind, even when it is killed
// with kill -9. libc and the C++ library only: nothing of keel's, so that each costs little.
//
//   keel-node-exec PARENT PROGRAM [ARG...]
//       What keel run starts a node through (a program that cannot ask by itself to die with keel
//       run; keel-hosts ask themselves). It asks the kernel for SIGKILL when the thread of keel
//       run that started it ends (PR_SET_PDEATHSIG, kept across execve), makes sure keel run did
//       not end before it asked (PARENT, keel run's pid, is still its parent), and then becomes
//       the program: same pid, same process group, nothing left of itself. Exit status 127, with
//       a line on stderr (the node's output file), when the program cannot be executed.
//
//   keel-node-exec --guard
//       One per keel run with nodes, in a process group of its own: it reads from descriptor 3
//       lines "+PGID" (a node's process group started) and "-PGID" (it ended), and when the
//       descriptor reaches its end — keel run closed it, or died — sends SIGKILL to every group
//       still listed. That covers what a node forked (`ros2 run`, a shell script), which
//       PR_SET_PDEATHSIG, given to the node alone, does not.
//
// Exit status 2 on a wrong command line.
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>
#include <string>
#include <system_error>

namespace {

bool parsePid(const char* text, long& out) {
  char* end = nullptr;
  errno = 0;
  out = std::strtol(text, &end, 10);
  return *text != '\0' && *end == '\0' && errno == 0 && out > 1;
}

int guard() {
  std::signal(SIGINT, SIG_IGN);  // a terminal's ^C is keel run's to handle, not the guard's
  std::signal(SIGHUP, SIG_IGN);
  std::set<long> groups;
  std::string line;
  char buf[512];
  for (;;) {
    const ssize_t n = ::read(3, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // keel run closed it, or is gone
    for (ssize_t i = 0; i < n; ++i) {
      if (buf[i] != '\n') {
        line += buf[i];
        continue;
      }
      long pgid = 0;
      if (line.size() > 1 && parsePid(line.c_str() + 1, pgid)) {
        if (line[0] == '+') groups.insert(pgid);
        else if (line[0] == '-') groups.erase(pgid);
      }
      line.clear();
    }
  }
  for (long pgid : groups) ::killpg(static_cast<pid_t>(pgid), SIGKILL);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::strcmp(argv[1], "--guard") == 0) return guard();
  if (argc < 3) {
    std::fputs("usage: keel-node-exec PARENT PROGRAM [ARG...] | keel-node-exec --guard\n", stderr);
    return 2;
  }
  long parent = 0;
  if (!parsePid(argv[1], parent)) {
    std::fprintf(stderr, "keel-node-exec: PARENT '%s' is not a pid\n", argv[1]);
    return 2;
  }
  if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0) {
    std::fprintf(stderr, "keel-node-exec: cannot ask to die with keel run: %s\n",
                 std::generic_category().message(errno).c_str());
    return 127;
  }
  if (::getppid() != static_cast<pid_t>(parent)) return 127;  // keel run is gone already: nothing to say it to
  ::execv(argv[2], argv + 2);
  std::fprintf(stderr, "keel-node-exec: cannot execute '%s': %s\n", argv[2],
               std::generic_category().message(errno).c_str());
  return 127;
}
