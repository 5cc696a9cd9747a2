// keel-bench-child: the process the respawn peer of `keel bench recovery` supervises, as a
// daemon under systemd's Restart=always or a launch file's respawn=true would be. No keel in it.
// Protocol, one line per message, with its supervisor (bench/harness/peers.cpp):
//   stdout  "ready <ns>\n"  first thing main does (after disabling its core dump)
//           "crash <ns>\n"  just before it segfaults
//   stdin   "crash\n"       segfault for real: a store through a null pointer
//           end of file     exit 0
// <ns> is CLOCK_MONOTONIC, the same clock for every process on the machine. Single-threaded.
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstring>

namespace {

// volatile: the compiler cannot know the pointer is null, so the store is a real one (not a
// trap instruction) and the kernel delivers a real SIGSEGV.
int* volatile g_nowhere = nullptr;

std::int64_t nowNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

bool report(const char* what, std::int64_t ns) {
  char line[64];
  const int len = std::snprintf(line, sizeof line, "%s %lld\n", what, static_cast<long long>(ns));
  return len > 0 && write(STDOUT_FILENO, line, static_cast<std::size_t>(len)) == len;
}

/// The next command line from stdin, without its newline; false at end of file or on error.
bool readCommand(char* buf, std::size_t size) {
  std::size_t used = 0;
  while (used + 1 < size) {
    char c = 0;
    const ssize_t got = read(STDIN_FILENO, &c, 1);
    if (got <= 0) return false;
    if (c == '\n') break;
    buf[used++] = c;
  }
  buf[used] = '\0';
  return true;
}

}  // namespace

int main() {
  // A crash must not write a core file: with many faults the dump would be what is measured.
  prctl(PR_SET_DUMPABLE, 0, 0, 0, 0);
  if (!report("ready", nowNs())) return 1;
  char command[32];
  while (readCommand(command, sizeof command)) {
    if (std::strcmp(command, "crash") != 0) continue;
    if (!report("crash", nowNs())) return 1;
    *g_nowhere = 1;
  }
  return 0;
}
