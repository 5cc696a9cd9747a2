// keel-node-exec: what keel run starts a program through when the program cannot ask by itself
// to die with keel run (a ROS 2 node; keel-hosts ask themselves). It asks the kernel for SIGKILL
// when the thread of keel run that started it ends (PR_SET_PDEATHSIG, kept across execve), makes
// sure keel run did not end before it asked, and then becomes the program: same pid, same process
// group, nothing left of itself. libc only, so that the one more exec costs little.
//
//   keel-node-exec PARENT PROGRAM [ARG...]
//
// PARENT is keel run's pid: when it is no longer this process's parent (keel run died between
// the spawn and the request), the program is not started. Exit status 127, with a line on stderr
// (the node's output file), when the program cannot be executed; 2 on a wrong command line.
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fputs("usage: keel-node-exec PARENT PROGRAM [ARG...]\n", stderr);
    return 2;
  }
  char* end = nullptr;
  const long parent = std::strtol(argv[1], &end, 10);
  if (*argv[1] == '\0' || *end != '\0' || parent <= 1) {
    std::fprintf(stderr, "keel-node-exec: PARENT '%s' is not a pid\n", argv[1]);
    return 2;
  }
  if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0) {
    std::fprintf(stderr, "keel-node-exec: cannot ask to die with keel run: %s\n", std::strerror(errno));
    return 127;
  }
  if (::getppid() != static_cast<pid_t>(parent)) return 127;  // keel run is gone already: nothing to say it to
  ::execv(argv[2], argv + 2);
  std::fprintf(stderr, "keel-node-exec: cannot execute '%s': %s\n", argv[2], std::strerror(errno));
  return 127;
}
