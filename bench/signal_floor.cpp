// The machine's floor for catching a fault, and keel's guard beside it, interleaved trial by
// trial on one thread so that the machine's drift blurs neither: the thread sleeps 1 ms (as an
// executor between cycles), wakes and faults — alternately under a bare SA_SIGINFO handler on
// an alternate stack (which takes the time and siglongjmps back) and under keel's
// runtime::guarded (detection time taken in keel's handler). Same for a C++ throw.
// Then the bare handler and catch by cadence, on a 1 ms cycle: a fault on every cycle (the
// path stays warm) and one every third cycle (as `keel bench detection` strikes): what a few
// quiet milliseconds cost the kernel's delivery and the unwinder.
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

#include "floor.hpp"
#include "harness/stats.hpp"
#include "runtime/guard.hpp"

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
  std::printf("| fault right after a 1 ms sleep, interleaved | n | p50 µs | p99 µs | max µs |\n|---|---|---|---|---|\n");
  std::thread t([n] {
    keel::runtime::installSignalHandlers();
    keel::runtime::installAltStack();
    struct sigaction bare {}, keel_sa {};
    bare.sa_sigaction = handler;
    bare.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_NODEFER;
    sigaction(SIGSEGV, nullptr, &keel_sa);
    std::vector<std::int64_t> seg, thr, kseg, kthr;
    auto nap = [] { std::this_thread::sleep_for(std::chrono::milliseconds(1)); };
    auto bareSeg = [&] {
      sigaction(SIGSEGV, &bare, nullptr);
      nap();
      volatile std::int64_t t0 = now();
      if (sigsetjmp(t_env, 0) == 0) faultNow();
      seg.push_back(t_caught - t0);
      sigaction(SIGSEGV, &keel_sa, nullptr);
    };
    auto keelSeg = [&] {
      nap();
      std::int64_t tk = 0;
      auto out = keel::runtime::guarded([&tk] {
        tk = now();
        faultNow();
        return keel::ReturnCode::Ok;
      });
      kseg.push_back(out.t_ns - tk);
    };
    auto bareThrow = [&] {
      nap();
      std::int64_t t1 = now();
      try {
        throwNow();
      } catch (const std::exception&) {
        thr.push_back(now() - t1);
      }
    };
    auto keelThrow = [&] {
      nap();
      std::int64_t tt = now();
      auto out2 = keel::runtime::guarded([]() -> keel::ReturnCode {
        throwNow();
        return keel::ReturnCode::Ok;
      });
      kthr.push_back(out2.t_ns - tt);  // the time keel's catch took, as for a signal
    };
    for (int i = 0; i < n; ++i) {  // alternate the order: neither side always runs warmer
      if (i % 2) {
        bareSeg(), keelSeg(), bareThrow(), keelThrow();
      } else {
        keelSeg(), bareSeg(), keelThrow(), bareThrow();
      }
    }
    report("bare SIGSEGV to handler", seg);
    report("keel: SIGSEGV in a guarded call to detection", kseg);
    report("bare throw to catch", thr);
    report("keel: throw in a guarded call to its catch", kthr);
  });
  t.join();
  std::printf("\n| bare, by cadence (1 ms cycle) | n | p50 µs | p99 µs | max µs |\n|---|---|---|---|---|\n");
  report("SIGSEGV on every cycle", keel::bench::measureSignalFloor(n, false, 1).latencies_ns);
  report("SIGSEGV every third cycle", keel::bench::measureSignalFloor(n, false, 3).latencies_ns);
  report("throw on every cycle", keel::bench::measureThrowFloor(n, false, 1).latencies_ns);
  report("throw every third cycle", keel::bench::measureThrowFloor(n, false, 3).latencies_ns);
  return 0;
}
