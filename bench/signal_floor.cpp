// The machine's floor for catching a fault, without keel: a thread that sleeps 1 ms (as an
// executor between cycles), wakes, and faults; a bare SA_SIGINFO handler on an alternate
// stack takes the time and siglongjmps back. Same for a C++ throw caught one frame up. Run in
// the same conditions as keel_bench_detection, it tells what part of keel's detection latency
// is the kernel's and the C++ runtime's.
//   build/bin/keel_bench_signal_floor [--n 1000]
#include <setjmp.h>
#include <signal.h>
#include <sys/mman.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "latency_stats.hpp"

namespace {

thread_local sigjmp_buf t_env;
thread_local volatile std::int64_t t_caught = 0;

std::int64_t now() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void handler(int, siginfo_t*, void*) {
  t_caught = now();
  siglongjmp(t_env, 1);
}

[[gnu::noinline]] void faultNow() {
  volatile std::uintptr_t addr = 0x10;
  *reinterpret_cast<volatile int*>(addr) = 1;
}

[[gnu::noinline]] void throwNow() { throw std::runtime_error("floor"); }

void report(const char* what, std::vector<std::int64_t> v) {
  auto s = keel::bench::summarise(std::move(v));
  std::printf("| %s | %zu | %.1f | %.1f | %.1f |\n", what, s.n, s.p50_us, s.p99_us, s.max_us);
}

}  // namespace

int main(int argc, char** argv) {
  int n = (argc > 2 && std::string(argv[1]) == "--n") ? std::atoi(argv[2]) : 1000;
  std::printf("| baseline (no keel), fault right after a 1 ms sleep | n | p50 µs | p99 µs | max µs |\n|---|---|---|---|---|\n");
  std::thread t([n] {
    stack_t ss{};
    ss.ss_size = 64 * 1024;
    ss.ss_sp = mmap(nullptr, ss.ss_size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    sigaltstack(&ss, nullptr);
    struct sigaction sa {};
    sa.sa_sigaction = handler;
    sa.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_NODEFER;
    sigaction(SIGSEGV, &sa, nullptr);
    std::vector<std::int64_t> seg, thr;
    for (int i = 0; i < n; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      volatile std::int64_t t0 = now();
      if (sigsetjmp(t_env, 0) == 0) faultNow();
      seg.push_back(t_caught - t0);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      std::int64_t t1 = now();
      try {
        throwNow();
      } catch (const std::exception&) {
        thr.push_back(now() - t1);
      }
    }
    report("SIGSEGV to handler", seg);
    report("throw to catch", thr);
  });
  t.join();
  return 0;
}
